//! The coarse deformation model in solver form: linear blend skinning of affine node
//! transformations (thesis eq. 3.2) written so that every deformed vertex is linear in the unknowns.
//!
//! Node `i` owns 12 unknowns `x[12 i + 3 c + k]`: for `c < 3` the entry `A_i[k][c]` (the columns of
//! `A_i` one after the other), for `c = 3` the translation `b_i[k]`. With `φ = (v − g_i, 1)` the
//! transformed vertex `A_i (v − g_i) + g_i + b_i` is `g_i + Σ_c φ_c x[12 i + 3 c + ·]`, so the
//! Jacobian of a deformed vertex with respect to node `i` is `w_i φᵀ ⊗ I₃`. Every term of the
//! coarse energy keeps that Kronecker shape, which is what makes assembly cheap.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::graph::DeformationGraph;

/// Unknowns per graph node.
pub const NODE_DOFS: usize = 12;

/// Work items per rayon task where results are combined in a fixed order.
pub const CHUNK: usize = 1024;

/// Maps world coordinates to solver coordinates (origin at the mesh's centroid, one unit per mean
/// edge length), so every weight and threshold means the same at any scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Units {
    pub origin: DVec3,
    pub unit: f64,
}

impl Units {
    pub fn new(positions: &[Vec3], unit: f32) -> Self {
        let sum = positions
            .iter()
            .fold(DVec3::ZERO, |acc, p| acc + p.as_dvec3());
        Self {
            origin: sum / positions.len().max(1) as f64,
            unit: f64::from(unit),
        }
    }

    pub fn to_local(self, p: Vec3) -> DVec3 {
        (p.as_dvec3() - self.origin) / self.unit
    }

    pub fn to_world(self, p: DVec3) -> Vec3 {
        (p * self.unit + self.origin).as_vec3()
    }
}

/// The graph in solver coordinates, with each skinning entry's `w φ` precomputed.
#[derive(Debug, Clone)]
pub struct Model {
    pub nodes: Vec<DVec3>,
    /// Graph edges `[i, j]`, `i < j`.
    pub edges: Vec<[u32; 2]>,
    /// Graph neighbours of each node (compressed rows).
    pub neighbour_offsets: Vec<u32>,
    pub neighbours: Vec<u32>,
    pub skin_offsets: Vec<u32>,
    pub skin_nodes: Vec<u32>,
    /// `w_s (v − g_s, 1)` for each skinning entry.
    pub skin_u: Vec<[f64; 4]>,
    /// `Σ_s w_s g_s` per vertex: the part of a deformed vertex that does not depend on the unknowns.
    pub base: Vec<DVec3>,
    /// The skinning entries naming each node, as (vertex, entry), by increasing vertex.
    pub node_skin_offsets: Vec<u32>,
    pub node_skin: Vec<[u32; 2]>,
}

impl Model {
    /// The model of `graph` over the mesh vertices `vertices` (indices into `rest`, the mesh in
    /// solver coordinates); the model's vertex `p` is mesh vertex `vertices[p]`.
    pub fn new(graph: &DeformationGraph, rest: &[DVec3], vertices: &[u32], units: &Units) -> Self {
        let nodes: Vec<DVec3> = graph
            .node_positions()
            .iter()
            .map(|&p| units.to_local(p))
            .collect();
        let mut skin_offsets = Vec::with_capacity(vertices.len() + 1);
        skin_offsets.push(0u32);
        let mut skin_nodes = Vec::new();
        let mut skin_u = Vec::new();
        let mut base = Vec::with_capacity(vertices.len());
        for &v in vertices {
            let p = rest[v as usize];
            let (ids, weights) = graph.skinning(v as usize);
            let mut b = DVec3::ZERO;
            for (&node, &w) in ids.iter().zip(weights) {
                let g = nodes[node as usize];
                let (w, d) = (f64::from(w), p - g);
                skin_nodes.push(node);
                skin_u.push([w * d.x, w * d.y, w * d.z, w]);
                b += w * g;
            }
            base.push(b);
            skin_offsets.push(skin_nodes.len() as u32);
        }
        let (node_skin_offsets, node_skin) =
            invert_skinning(nodes.len(), &skin_offsets, &skin_nodes);
        let edges = graph.edges().to_vec();
        let mut degree = vec![0u32; nodes.len() + 1];
        for &[a, b] in &edges {
            degree[a as usize + 1] += 1;
            degree[b as usize + 1] += 1;
        }
        for i in 0..nodes.len() {
            degree[i + 1] += degree[i];
        }
        let neighbour_offsets = degree;
        let mut fill = neighbour_offsets[..nodes.len()].to_vec();
        let mut neighbours = vec![0u32; 2 * edges.len()];
        for &[a, b] in &edges {
            neighbours[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            neighbours[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        Self {
            nodes,
            edges,
            neighbour_offsets,
            neighbours,
            skin_offsets,
            skin_nodes,
            skin_u,
            base,
            node_skin_offsets,
            node_skin,
        }
    }

    /// (vertex, skinning entry) pairs that involve node `i`.
    pub fn node_skin(&self, i: usize) -> &[[u32; 2]] {
        &self.node_skin[self.node_skin_offsets[i] as usize..self.node_skin_offsets[i + 1] as usize]
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn vertex_count(&self) -> usize {
        self.base.len()
    }

    pub fn unknowns(&self) -> usize {
        NODE_DOFS * self.nodes.len()
    }

    pub fn skin_range(&self, v: usize) -> std::ops::Range<usize> {
        self.skin_offsets[v] as usize..self.skin_offsets[v + 1] as usize
    }

    pub fn node_neighbours(&self, i: usize) -> &[u32] {
        &self.neighbours[self.neighbour_offsets[i] as usize..self.neighbour_offsets[i + 1] as usize]
    }

    /// The unknowns of the identity deformation: `A_i = I`, `b_i = 0`.
    pub fn identity(&self) -> Vec<f64> {
        let mut x = vec![0.0; self.unknowns()];
        for node in x.chunks_exact_mut(NODE_DOFS) {
            node[0] = 1.0;
            node[4] = 1.0;
            node[8] = 1.0;
        }
        x
    }

    /// Deformed vertex `v`: `Σ_s w_s (A_s (v − g_s) + g_s + b_s)`.
    pub fn deform_vertex(&self, x: &[f64], v: usize) -> DVec3 {
        let mut p = self.base[v];
        for s in self.skin_range(v) {
            let node = &x[NODE_DOFS * self.skin_nodes[s] as usize..][..NODE_DOFS];
            let u = &self.skin_u[s];
            for c in 0..4 {
                p += u[c] * DVec3::new(node[3 * c], node[3 * c + 1], node[3 * c + 2]);
            }
        }
        p
    }

    /// Every deformed vertex.
    pub fn deform(&self, x: &[f64]) -> Vec<DVec3> {
        (0..self.vertex_count())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| self.deform_vertex(x, v))
            .collect()
    }
}

/// For every node, the (vertex, entry) pairs of the skinning entries that name it, by vertex.
fn invert_skinning(
    nodes: usize,
    skin_offsets: &[u32],
    skin_nodes: &[u32],
) -> (Vec<u32>, Vec<[u32; 2]>) {
    let mut offsets = vec![0u32; nodes + 1];
    for &n in skin_nodes {
        offsets[n as usize + 1] += 1;
    }
    for i in 0..nodes {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets[..nodes].to_vec();
    let mut entries = vec![[0u32; 2]; skin_nodes.len()];
    for v in 0..skin_offsets.len() - 1 {
        for s in skin_offsets[v]..skin_offsets[v + 1] {
            let n = skin_nodes[s as usize] as usize;
            entries[fill[n] as usize] = [v as u32, s];
            fill[n] += 1;
        }
    }
    (offsets, entries)
}

/// `Σ values` computed in parallel in fixed-size chunks and combined in chunk order, so the result
/// does not depend on the number of threads.
pub fn ordered_sum<F>(count: usize, term: F) -> f64
where
    F: Fn(usize) -> f64 + Sync,
{
    let partial: Vec<f64> = (0..count.div_ceil(CHUNK))
        .into_par_iter()
        .map(|chunk| {
            (chunk * CHUNK..((chunk + 1) * CHUNK).min(count))
                .map(&term)
                .sum()
        })
        .collect();
    partial.iter().sum()
}
