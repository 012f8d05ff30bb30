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
    /// `2 count` slots per vertex: its accepted labels (node index, distance), then the search's
    /// pending offers. Side by side, a vertex's labels and offers share cache lines, and the
    /// search, which reads both for every neighbour it reaches, is bound by those reads.
    slots: Vec<(u32, f32)>,
    /// Per vertex: labels accepted, offers pending.
    lengths: Vec<[u8; 2]>,
}

impl NearestNodes {
    /// Multi-source Dijkstra that lets each vertex accept at most `count` sources. Truncating is
    /// exact: if node `s` is among the `count` nearest of `v`, it is among the `count` nearest of
    /// every vertex on its shortest path to `v` (any node nearer to such a vertex would be nearer to
    /// `v` too).
    ///
    /// Each vertex also keeps its best pending offers, at most as many as it has labels left to
    /// accept, and a neighbour's offer is queued only when it improves that list. That is exact
    /// too (a source pushed out by as many better offers has that many nearer nodes), and it
    /// queues a vertex's source once or twice instead of once per settled neighbour: the queue is
    /// what the search's time is made of.
    pub fn search(
        adjacency: &VertexAdjacency,
        positions: &[Vec3],
        nodes: &[u32],
        count: usize,
    ) -> Self {
        let n = adjacency.vertex_count();
        let count = count.clamp(1, u8::MAX as usize / 2);
        let mut found = Self {
            count,
            slots: vec![(u32::MAX, f32::INFINITY); n * 2 * count],
            lengths: vec![[0u8; 2]; n],
        };
        let mut heap = RadixHeap::new();
        for (source, &vertex) in nodes.iter().enumerate() {
            if found.offer(vertex as usize, source as u32, 0.0) {
                heap.push(0.0, (vertex, source as u32));
            }
        }
        while let Some((distance, (vertex, source))) = heap.pop() {
            let v = vertex as usize;
            if !found.take(v, source, distance) {
                continue;
            }
            let p = positions[v];
            for &u in adjacency.neighbours(v) {
                let d = distance + p.distance(positions[u as usize]);
                if found.offer(u as usize, source, d) {
                    heap.push(d, (u, source));
                }
            }
        }
        found
    }

    /// The nearest nodes of vertex `v` as (node index, geodesic distance), nearest first; fewer than
    /// `count` when its component holds fewer nodes.
    pub fn of(&self, v: usize) -> &[(u32, f32)] {
        let start = 2 * v * self.count;
        &self.slots[start..start + self.lengths[v][0] as usize]
    }

    /// Records `source` reaching `v` at `distance`; true when that improves `v`'s offers (and so
    /// must be queued).
    fn offer(&mut self, v: usize, source: u32, distance: f32) -> bool {
        let [filled, pending] = self.lengths[v].map(usize::from);
        let (labels, offers) = halves(&mut self.slots, self.count, v);
        if labels[..filled].iter().any(|&(s, _)| s == source) {
            return false;
        }
        let list = &mut offers[..pending];
        if let Some(entry) = list.iter_mut().find(|e| e.0 == source) {
            if distance < entry.1 {
                entry.1 = distance;
                return true;
            }
            return false;
        }
        if pending < self.count - filled {
            offers[pending] = (source, distance);
            self.lengths[v][1] += 1;
            return true;
        }
        let worst = list
            .iter_mut()
            .max_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        match worst {
            Some(entry) if distance < entry.1 => {
                *entry = (source, distance);
                true
            }
            _ => false,
        }
    }

    /// Accepts `v`'s offer of `source` as its next label if the offer still stands at `distance`
    /// (a queued item whose offer was improved or pushed out since is stale); true when it did.
    fn take(&mut self, v: usize, source: u32, distance: f32) -> bool {
        let [filled, pending] = self.lengths[v].map(usize::from);
        let (labels, offers) = halves(&mut self.slots, self.count, v);
        let Some(i) = offers[..pending]
            .iter()
            .position(|&e| e == (source, distance))
        else {
            return false;
        };
        offers.swap(i, pending - 1);
        labels[filled] = (source, distance);
        self.lengths[v] = [filled as u8 + 1, pending as u8 - 1];
        true
    }
}

/// A (node index, geodesic distance) pair: a label or an offer.
type Label = (u32, f32);

/// Vertex `v`'s label slots and offer slots, `count` each.
fn halves(slots: &mut [Label], count: usize, v: usize) -> (&mut [Label], &mut [Label]) {
    slots[2 * v * count..2 * (v + 1) * count].split_at_mut(count)
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
        assert_matches_single_sources(&adjacency, &positions, &[0, 17, 40, 77, 101], 3);
    }

    #[test]
    fn nearest_nodes_match_brute_force_on_a_sphere() {
        let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let adjacency = VertexAdjacency::new(mesh.positions.len(), &mesh.triangles);
        let nodes = sample(&adjacency, &mesh.positions, 2.5 * mesh.mean_edge_length());
        assert!(nodes.len() > 20, "{} nodes", nodes.len());
        assert_matches_single_sources(&adjacency, &mesh.positions, &nodes, 5);
    }

    /// Every vertex's `count` labels have the distances of its `count` nearest nodes by a
    /// separate search from each node, and each label's distance is its own node's.
    fn assert_matches_single_sources(
        adjacency: &VertexAdjacency,
        positions: &[Vec3],
        nodes: &[u32],
        count: usize,
    ) {
        let nearest = NearestNodes::search(adjacency, positions, nodes, count);
        let distances: Vec<Vec<f32>> = nodes
            .iter()
            .map(|&s| single_source(adjacency, positions, s))
            .collect();
        for v in 0..positions.len() {
            let mut all: Vec<f32> = distances.iter().map(|d| d[v]).collect();
            all.sort_by(f32::total_cmp);
            let got = nearest.of(v);
            assert_eq!(got.len(), count);
            for (k, (&(node, d), &expected)) in got.iter().zip(&all).enumerate() {
                assert!(
                    (d - expected).abs() < 1e-5,
                    "vertex {v}, label {k}: {d} vs {expected}"
                );
                assert!(
                    (distances[node as usize][v] - d).abs() < 1e-5,
                    "vertex {v}: node {node}"
                );
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
