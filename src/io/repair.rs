//! The repairs every reader applies: weld duplicate vertices, drop exactly-degenerate faces, split
//! non-manifold edges and vertices (`split`), remove vertices no face uses. A valid closed mesh
//! passes through unchanged (all counts zero).

use super::split::split_non_manifold;
use super::weld::weld_targets;
use crate::mesh::IndexedMesh;
use glam::DVec3;
use serde::Serialize;

/// What `repair` changed, so `inspect` can tell a user their file was not clean.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct RepairReport {
    /// Vertices merged into an earlier vertex within the weld tolerance.
    pub welded_vertices: usize,
    /// Faces dropped because two corners are the same vertex (after welding) or the area is exactly
    /// zero (collinear corners).
    pub degenerate_faces: usize,
    /// Vertices removed because no remaining face uses them.
    pub unreferenced_vertices: usize,
    /// Edges of more than two triangles whose triangles were paired across the solid between
    /// them.
    pub split_edges: usize,
    /// Copies added so that each fan of triangles around a vertex has a vertex of its own.
    pub split_vertices: usize,
}

impl RepairReport {
    /// True when nothing was changed.
    pub fn is_clean(&self) -> bool {
        *self == RepairReport::default()
    }
}

/// Welds vertices within `relative_tolerance` × mean edge length, drops degenerate faces, splits
/// non-manifold edges and vertices and removes unreferenced vertices, carrying ids and attributes
/// of the kept vertices (a split vertex's copies take its attributes and new ids after the
/// largest).
///
/// Requires every triangle index to be in range (readers check that before calling).
pub(crate) fn repair(
    mut mesh: IndexedMesh,
    relative_tolerance: f32,
) -> (IndexedMesh, RepairReport) {
    let tolerance = relative_tolerance * corner_mean_edge_length(&mesh);
    let target = weld_targets(&mesh.positions, tolerance);
    let welded_vertices = target
        .iter()
        .enumerate()
        .filter(|&(i, &t)| t as usize != i)
        .count();

    let mut triangles = Vec::with_capacity(mesh.triangles.len());
    for tri in &mesh.triangles {
        let tri = tri.map(|v| target[v as usize]);
        if !is_exactly_degenerate(&mesh, tri) {
            triangles.push(tri);
        }
    }
    let degenerate_faces = mesh.triangles.len() - triangles.len();
    mesh.triangles = triangles;
    let split = split_non_manifold(&mut mesh);

    // Vertex `v` of the input, then the copies the split added, each standing for its source.
    let vertices = mesh.positions.len();
    let source = |v: usize| {
        if v < vertices {
            v
        } else {
            split.copies[v - vertices] as usize
        }
    };
    let mut referenced = vec![false; vertices + split.copies.len()];
    for &v in mesh.triangles.iter().flatten() {
        referenced[v as usize] = true;
    }
    let kept = referenced[..vertices].iter().filter(|&&r| r).count();
    let unreferenced_vertices = vertices - welded_vertices - kept;
    let report = RepairReport {
        welded_vertices,
        degenerate_faces,
        unreferenced_vertices,
        split_edges: split.edges,
        split_vertices: split.copies.len(),
    };
    if kept == vertices && degenerate_faces == 0 && split.copies.is_empty() {
        return (mesh, report);
    }

    let mut new_index = vec![u32::MAX; referenced.len()];
    let mut order = Vec::with_capacity(kept + split.copies.len());
    for (v, _) in referenced.iter().enumerate().filter(|&(_, &r)| r) {
        new_index[v] = order.len() as u32;
        order.push(v);
    }
    let mut triangles = std::mem::take(&mut mesh.triangles);
    for tri in &mut triangles {
        *tri = tri.map(|v| new_index[v as usize]);
    }
    let sources: Vec<usize> = order.iter().map(|&v| source(v)).collect();
    let repaired = IndexedMesh {
        positions: sources.iter().map(|&v| mesh.positions[v]).collect(),
        triangles,
        ids: mesh.ids.as_ref().map(|ids| {
            let mut fresh = ids.iter().max().map_or(0, |&id| id + 1);
            order
                .iter()
                .map(|&v| {
                    if v < vertices {
                        ids[v]
                    } else {
                        fresh += 1;
                        fresh - 1
                    }
                })
                .collect()
        }),
        attributes: mesh.attributes.iter().map(|a| a.gather(&sources)).collect(),
    };
    (repaired, report)
}

/// A repeated corner, or a cross product that is exactly zero in double precision (where the
/// differences of single-precision coordinates are exact): collinear corners.
fn is_exactly_degenerate(mesh: &IndexedMesh, [a, b, c]: [u32; 3]) -> bool {
    if a == b || b == c || a == c {
        return true;
    }
    let p = |v: u32| mesh.positions[v as usize].as_dvec3();
    let (pa, pb, pc) = (p(a), p(b), p(c));
    (pb - pa).cross(pc - pa) == DVec3::ZERO
}

/// Mean edge length over triangle corners (each interior edge counted once per side): the same
/// value as the mean over undirected edges for a closed mesh, without sorting edges, and well
/// defined for the unwelded meshes repair starts from. Zero without triangles.
fn corner_mean_edge_length(mesh: &IndexedMesh) -> f32 {
    let mut sum = 0.0f64;
    for [a, b, c] in &mesh.triangles {
        let p = |v: &u32| mesh.positions[*v as usize].as_dvec3();
        let (pa, pb, pc) = (p(a), p(b), p(c));
        sum += pa.distance(pb) + pb.distance(pc) + pc.distance(pa);
    }
    if mesh.triangles.is_empty() {
        0.0
    } else {
        (sum / (3 * mesh.triangles.len()) as f64) as f32
    }
}
