//! The per-triangle data a BVH carries besides geometry, in leaf order: vertex normals to
//! interpolate at a hit (Max's weights, exact for vertices on a sphere; `004_…` "Mesh
//! Processing") and the angle-weighted pseudo-normals that sign closest-point distances
//! (Bærentzen & Aanæs 2005); and the target's mean edge length.
//!
//! Everything is gathered per vertex or per triangle over a vertex→triangle adjacency, in
//! parallel, each sum in a fixed order, so results do not depend on the thread count.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::adjacency::VertexFaces;
use super::{NormalTriple, PseudoNormals};
use crate::mesh::IndexedMesh;

pub(super) struct Shading {
    pub normals: Vec<NormalTriple>,
    pub pseudo: Vec<PseudoNormals>,
    pub mean_edge_length: f32,
}

/// The shading of the triangles `order[slot]`, one record per leaf slot. Indices must be in range.
pub(super) fn shading(mesh: &IndexedMesh, order: &[u32]) -> Shading {
    let triangles = &mesh.triangles;
    let around = VertexFaces::new(mesh.positions.len(), triangles);
    let corner_normals = vertex_normals(mesh, &around);
    let faces: Vec<Vec3> = triangles
        .par_iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|v| mesh.positions[v as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect();
    let corner = |normals: &[(Vec3, Vec3)], tri: [u32; 3], angle: bool| {
        NormalTriple::new(tri.map(|v| {
            let (max, by_angle) = normals[v as usize];
            if angle { by_angle } else { max }
        }))
    };
    let (normals, pseudo) = order
        .par_iter()
        .map(|&t| {
            let tri = triangles[t as usize];
            let own = faces[t as usize];
            let edge = |k: usize| {
                let twin = around
                    .face_with_edge(triangles, tri[(k + 1) % 3], tri[k])
                    .map_or(own, |f| faces[f]);
                (own + twin).normalize_or(own)
            };
            let pseudo = PseudoNormals {
                vertices: corner(&corner_normals, tri, true),
                edges: NormalTriple::new([edge(0), edge(1), edge(2)]),
            };
            (corner(&corner_normals, tri, false), pseudo)
        })
        .unzip();
    Shading {
        normals,
        pseudo,
        mean_edge_length: mean_edge_length(mesh, &around),
    }
}

/// Per vertex: the normal with Max's weights, cross(e1, e2) / (|e1|²·|e2|²), and the
/// angle-weighted normal, both unit (zero for a vertex without a non-degenerate triangle).
fn vertex_normals(mesh: &IndexedMesh, around: &VertexFaces) -> Vec<(Vec3, Vec3)> {
    (0..around.vertices() as u32)
        .into_par_iter()
        .map(|v| {
            let mut max = DVec3::ZERO;
            let mut by_angle = DVec3::ZERO;
            for &f in around.around(v) {
                let tri = mesh.triangles[f as usize];
                let Some(k) = tri.iter().position(|&w| w == v) else {
                    continue;
                };
                let p = |j: usize| mesh.positions[tri[(k + j) % 3] as usize].as_dvec3();
                let (e1, e2) = (p(1) - p(0), p(2) - p(0));
                let cross = e1.cross(e2);
                let d = e1.length_squared() * e2.length_squared();
                if d > 0.0 {
                    max += cross / d;
                }
                by_angle += cross.normalize_or_zero() * cross.length().atan2(e1.dot(e2));
            }
            (
                max.normalize_or_zero().as_vec3(),
                by_angle.normalize_or_zero().as_vec3(),
            )
        })
        .collect()
}

/// Mean length of the distinct undirected edges, summed in vertex order.
fn mean_edge_length(mesh: &IndexedMesh, around: &VertexFaces) -> f32 {
    let per_vertex: Vec<(f64, usize)> = around
        .edges_per_vertex(&mesh.triangles)
        .map(|(a, higher)| {
            let pa = mesh.positions[a as usize].as_dvec3();
            let sum = higher
                .iter()
                .map(|&b| pa.distance(mesh.positions[b as usize].as_dvec3()))
                .sum::<f64>();
            (sum, higher.len())
        })
        .collect();
    let (sum, count) = per_vertex
        .iter()
        .fold((0.0, 0), |(s, n), &(vs, vn)| (s + vs, n + vn));
    if count == 0 {
        0.0
    } else {
        (sum / count as f64) as f32
    }
}
