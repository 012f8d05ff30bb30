//! The per-triangle data a BVH carries besides geometry, in leaf order: vertex normals to
//! interpolate at a hit (Max's weights, exact for vertices on a sphere; `004_…` "Mesh
//! Processing") and the angle-weighted pseudo-normals that sign closest-point distances
//! (Bærentzen & Aanæs 2005); and the target's mean edge length.
//!
//! Everything is computed per triangle or gathered per vertex over a vertex→triangle adjacency,
//! in parallel, each sum in a fixed order, so results do not depend on the thread count. None of
//! it depends on the tree, so it is computed while the tree is built.

use std::f32::consts::PI;

use glam::Vec3;
use rayon::prelude::*;

use crate::geometry::VertexFaces;
use crate::kernels::shared::{NormalTriple, PseudoNormals};
use crate::mesh::IndexedMesh;

/// Normals and edge data in mesh order.
pub(super) struct Shading {
    /// Per vertex: the normal with Max's weights and the angle-weighted normal, both unit.
    vertex: Vec<(Vec3, Vec3)>,
    /// Per triangle: its unit normal.
    faces: Vec<Vec3>,
    /// Per triangle: the triangle across each edge (ab, bc, ca), if any.
    twins: Vec<[Option<u32>; 3]>,
    pub mean_edge_length: f32,
}

/// What a triangle adds at each corner (a, b, c) to its vertex's two normals:
/// cross(e1, e2) / (|e1|²·|e2|²) (Max) and the unit face normal times the corner's angle.
struct Corners {
    max: [Vec3; 3],
    angle: [Vec3; 3],
}

/// What a triangle knows of its three edges (ab, bc, ca).
struct Edges {
    /// The triangle across each edge: the first in mesh order with the reversed edge.
    twins: [Option<u32>; 3],
    owned: Owned,
}

/// The edges a triangle owns: an undirected edge belongs to the first triangle, in mesh order,
/// that has it, so each is counted once.
#[derive(Debug, Clone, Copy, Default)]
struct Owned {
    length: f64,
    count: u32,
}

impl Shading {
    /// The shading of `mesh`, whose indices must be in range.
    pub(super) fn new(mesh: &IndexedMesh) -> Self {
        let triangles = &mesh.triangles;
        let around = VertexFaces::new(mesh.positions.len(), triangles);
        let (faces, corners): (Vec<Vec3>, Vec<Corners>) =
            triangles.par_iter().map(|&tri| corners(mesh, tri)).unzip();
        let vertex = (0..around.vertices() as u32)
            .into_par_iter()
            .map(|v| {
                let (mut max, mut by_angle) = (Vec3::ZERO, Vec3::ZERO);
                for &f in around.around(v) {
                    let tri = triangles[f as usize];
                    if let Some(k) = tri.iter().position(|&w| w == v) {
                        max += corners[f as usize].max[k];
                        by_angle += corners[f as usize].angle[k];
                    }
                }
                (max.normalize_or_zero(), by_angle.normalize_or_zero())
            })
            .collect();
        let edges: Vec<Edges> = (0..triangles.len())
            .into_par_iter()
            .map(|t| edges(mesh, &around, t))
            .collect();
        Self {
            vertex,
            faces,
            twins: edges.iter().map(|e| e.twins).collect(),
            mean_edge_length: mean_length(edges.iter().map(|e| e.owned)),
        }
    }

    /// Vertex normals and pseudo-normals of the triangles `order[slot]`, one record per slot.
    pub(super) fn in_leaf_order(
        &self,
        mesh: &IndexedMesh,
        order: &[u32],
    ) -> (Vec<NormalTriple>, Vec<PseudoNormals>) {
        order
            .par_iter()
            .map(|&t| {
                let tri = mesh.triangles[t as usize];
                let own = self.faces[t as usize];
                let twins = self.twins[t as usize];
                let edge = |k: usize| {
                    let twin = twins[k].map_or(own, |f| self.faces[f as usize]);
                    (own + twin).normalize_or(own)
                };
                let smooth = NormalTriple::new(tri.map(|v| self.vertex[v as usize].0));
                let pseudo = PseudoNormals {
                    vertices: NormalTriple::new(tri.map(|v| self.vertex[v as usize].1)),
                    edges: NormalTriple::new([edge(0), edge(1), edge(2)]),
                };
                (smooth, pseudo)
            })
            .unzip()
    }
}

/// A triangle's unit normal and its corners' contributions. The three angles sum to π, so the
/// third is not measured.
fn corners(mesh: &IndexedMesh, tri: [u32; 3]) -> (Vec3, Corners) {
    let p = tri.map(|v| mesh.positions[v as usize]);
    let cross = (p[1] - p[0]).cross(p[2] - p[0]);
    let normal = cross.normalize_or_zero();
    let sin = cross.length();
    let mut max = [Vec3::ZERO; 3];
    let mut angles = [0.0f32; 3];
    for k in 0..3 {
        let e1 = p[(k + 1) % 3] - p[k];
        let e2 = p[(k + 2) % 3] - p[k];
        let d = e1.length_squared() * e2.length_squared();
        if d > 0.0 {
            max[k] = cross / d;
        }
        if k < 2 {
            angles[k] = sin.atan2(e1.dot(e2));
        }
    }
    angles[2] = (PI - angles[0] - angles[1]).max(0.0);
    (
        normal,
        Corners {
            max,
            angle: angles.map(|a| normal * a),
        },
    )
}

fn edges(mesh: &IndexedMesh, around: &VertexFaces, t: usize) -> Edges {
    let triangles = &mesh.triangles;
    let tri = triangles[t];
    let twins = [0, 1, 2].map(|k| {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        around
            .around(b)
            .iter()
            .copied()
            .find(|&f| has_edge(triangles[f as usize], b, a))
    });
    Edges {
        twins,
        owned: owned(mesh, around, t),
    }
}

/// The edges triangle `t` owns and their total length.
fn owned(mesh: &IndexedMesh, around: &VertexFaces, t: usize) -> Owned {
    let triangles = &mesh.triangles;
    let tri = triangles[t];
    let mut owned = Owned::default();
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let first = around
            .around(a.min(b))
            .iter()
            .copied()
            .find(|&f| triangles[f as usize].contains(&a.max(b)));
        if first == Some(t as u32) && a != b {
            let (pa, pb) = (mesh.positions[a as usize], mesh.positions[b as usize]);
            owned.length += f64::from(pa.distance(pb));
            owned.count += 1;
        }
    }
    owned
}

/// The mean length of the edges of `owned` (per triangle, in mesh order, summed in that order).
fn mean_length(owned: impl Iterator<Item = Owned>) -> f32 {
    let (length, count) = owned.fold((0.0f64, 0u64), |(l, n), o| {
        (l + o.length, n + u64::from(o.count))
    });
    if count == 0 {
        0.0
    } else {
        (length / count as f64) as f32
    }
}

/// The mean edge length of `mesh`, each undirected edge counted once: what [`Shading::new`]
/// computes besides the normals, for a tree that needs no normals.
pub(super) fn mean_edge_length(mesh: &IndexedMesh) -> f32 {
    let around = VertexFaces::new(mesh.positions.len(), &mesh.triangles);
    let owned: Vec<Owned> = (0..mesh.triangles.len())
        .into_par_iter()
        .map(|t| owned(mesh, &around, t))
        .collect();
    mean_length(owned.into_iter())
}

fn has_edge(tri: [u32; 3], a: u32, b: u32) -> bool {
    (0..3).any(|k| tri[k] == a && tri[(k + 1) % 3] == b)
}
