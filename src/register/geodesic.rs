//! Geodesic distances along mesh edges (Dijkstra), for sampling the deformation graph and for
//! finding each vertex's nearest graph nodes. Geodesic rather than Euclidean distance is what keeps
//! separate components, and parts that touch in space but not along the surface, apart (paper §4.2,
//! Fig. 5).

use std::collections::VecDeque;

use glam::Vec3;

use super::adjacency::VertexAdjacency;
use super::radix_heap::RadixHeap;

/// Vertices chosen as graph nodes so that nodes are at least `spacing` apart along the surface and
/// every vertex lies within `spacing` of one (a geodesic Poisson-disk sample).
///
/// Vertices are visited in breadth-first order from the lowest-indexed vertex of each component, so
/// the region covered by nodes grows as a front and each new node sits just beyond it, which keeps
/// the sampling even (Birger's thesis §3.3.1 grows regions the same way).
pub fn sample(adjacency: &VertexAdjacency, positions: &[Vec3], spacing: f32) -> Vec<u32> {
    let n = adjacency.vertex_count();
    let mut cover = vec![f32::INFINITY; n];
    let mut nodes = Vec::new();
    let mut heap = RadixHeap::new();
    for v in breadth_first_order(adjacency) {
        if cover[v as usize] < spacing {
            continue;
        }
        nodes.push(v);
        cover[v as usize] = 0.0;
        heap.restart();
        heap.push(0.0, v);
        while let Some((distance, vertex)) = heap.pop() {
            if distance > cover[vertex as usize] {
                continue;
            }
            let p = positions[vertex as usize];
            for &u in adjacency.neighbours(vertex as usize) {
                let d = distance + p.distance(positions[u as usize]);
                if d < spacing && d < cover[u as usize] {
                    cover[u as usize] = d;
                    heap.push(d, u);
                }
            }
        }
    }
    nodes
}

/// Every vertex in breadth-first order, component after component.
fn breadth_first_order(adjacency: &VertexAdjacency) -> Vec<u32> {
    let n = adjacency.vertex_count();
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut queue = VecDeque::new();
    for start in 0..n {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        queue.push_back(start as u32);
        while let Some(v) = queue.pop_front() {
            order.push(v);
            for &u in adjacency.neighbours(v as usize) {
                if !seen[u as usize] {
                    seen[u as usize] = true;
                    queue.push_back(u);
                }
            }
        }
    }
    order
}

/// The `count` geodesically nearest nodes of every vertex, nearest first.
#[derive(Debug, Clone)]
pub struct NearestNodes {
    count: usize,
    /// `count` slots per vertex: (node index, distance).
    labels: Vec<(u32, f32)>,
    filled: Vec<u8>,
}

impl NearestNodes {
    /// Multi-source Dijkstra that lets each vertex accept at most `count` sources. Truncating is
    /// exact: if node `s` is among the `count` nearest of `v`, it is among the `count` nearest of
    /// every vertex on its shortest path to `v` (any node nearer to such a vertex would be nearer to
    /// `v` too).
    pub fn search(
        adjacency: &VertexAdjacency,
        positions: &[Vec3],
        nodes: &[u32],
        count: usize,
    ) -> Self {
        let n = adjacency.vertex_count();
        let count = count.clamp(1, u8::MAX as usize);
        let mut labels = vec![(u32::MAX, f32::INFINITY); n * count];
        let mut filled = vec![0u8; n];
        let mut heap = RadixHeap::new();
        for (source, &vertex) in nodes.iter().enumerate() {
            heap.push(0.0, (vertex, source as u32));
        }
        let has = |labels: &[(u32, f32)], filled: &[u8], v: usize, source: u32| {
            labels[v * count..v * count + filled[v] as usize]
                .iter()
                .any(|&(s, _)| s == source)
        };
        while let Some((distance, (vertex, source))) = heap.pop() {
            let v = vertex as usize;
            if filled[v] as usize == count || has(&labels, &filled, v, source) {
                continue;
            }
            labels[v * count + filled[v] as usize] = (source, distance);
            filled[v] += 1;
            let p = positions[v];
            for &u in adjacency.neighbours(v) {
                let u = u as usize;
                if filled[u] as usize == count || has(&labels, &filled, u, source) {
                    continue;
                }
                heap.push(distance + p.distance(positions[u]), (u as u32, source));
            }
        }
        Self {
            count,
            labels,
            filled,
        }
    }

    /// The nearest nodes of vertex `v` as (node index, geodesic distance), nearest first; fewer than
    /// `count` when its component holds fewer nodes.
    pub fn of(&self, v: usize) -> &[(u32, f32)] {
        &self.labels[v * self.count..v * self.count + self.filled[v] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::IndexedMesh;

    /// A flat strip of `n × m` unit squares, each split in two.
    fn grid(n: usize, m: usize) -> (Vec<Vec3>, VertexAdjacency) {
        let mut positions = Vec::new();
        for j in 0..=m {
            for i in 0..=n {
                positions.push(Vec3::new(i as f32, j as f32, 0.0));
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut tris = Vec::new();
        for j in 0..m {
            for i in 0..n {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let adjacency = VertexAdjacency::new(positions.len(), &tris);
        (positions, adjacency)
    }

    #[test]
    fn samples_are_spaced_and_cover_everything() {
        let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
        let adjacency = VertexAdjacency::new(mesh.positions.len(), &mesh.triangles);
        let spacing = 4.0 * mesh.mean_edge_length();
        let nodes = sample(&adjacency, &mesh.positions, spacing);
        let nearest = NearestNodes::search(&adjacency, &mesh.positions, &nodes, 2);
        for (i, &v) in nodes.iter().enumerate() {
            let labels = nearest.of(v as usize);
            assert_eq!(labels[0], (i as u32, 0.0));
            assert!(
                labels[1].1 >= spacing,
                "nodes {i} and {} too close",
                labels[1].0
            );
        }
        for v in 0..mesh.positions.len() {
            assert!(nearest.of(v)[0].1 < spacing, "vertex {v} uncovered");
        }
    }

    #[test]
    fn nearest_nodes_match_brute_force_dijkstra() {
        let (positions, adjacency) = grid(12, 7);
        let nodes = [0u32, 17, 40, 77, 101];
        let nearest = NearestNodes::search(&adjacency, &positions, &nodes, 3);
        for v in 0..positions.len() {
            let mut all: Vec<(u32, f32)> = nodes
                .iter()
                .enumerate()
                .map(|(i, &s)| (i as u32, single_source(&adjacency, &positions, s)[v]))
                .collect();
            all.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            let got = nearest.of(v);
            assert_eq!(got.len(), 3);
            for (g, e) in got.iter().zip(&all) {
                assert!((g.1 - e.1).abs() < 1e-5, "vertex {v}: {got:?} vs {all:?}");
            }
        }
    }

    fn single_source(adjacency: &VertexAdjacency, positions: &[Vec3], s: u32) -> Vec<f32> {
        let mut dist = vec![f32::INFINITY; positions.len()];
        dist[s as usize] = 0.0;
        let mut changed = true;
        while changed {
            changed = false;
            for v in 0..positions.len() {
                for &u in adjacency.neighbours(v) {
                    let d = dist[v] + positions[v].distance(positions[u as usize]);
                    if d < dist[u as usize] {
                        dist[u as usize] = d;
                        changed = true;
                    }
                }
            }
        }
        dist
    }
}
