//! The repairs every reader applies: weld duplicate vertices, drop exactly-degenerate faces, remove
//! vertices no face uses. A valid closed mesh passes through unchanged (all counts zero).

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
}

impl RepairReport {
    /// True when nothing was changed.
    pub fn is_clean(&self) -> bool {
        *self == RepairReport::default()
    }
}

/// Welds vertices within `relative_tolerance` × mean edge length, drops degenerate faces and
/// removes unreferenced vertices, carrying ids and attributes of the kept vertices.
///
/// Requires every triangle index to be in range (readers check that before calling).
pub(crate) fn repair(mesh: IndexedMesh, relative_tolerance: f32) -> (IndexedMesh, RepairReport) {
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

    let mut referenced = vec![false; mesh.positions.len()];
    for &v in triangles.iter().flatten() {
        referenced[v as usize] = true;
    }
    let kept = referenced.iter().filter(|&&r| r).count();
    let unreferenced_vertices = mesh.positions.len() - welded_vertices - kept;
    let report = RepairReport {
        welded_vertices,
        degenerate_faces,
        unreferenced_vertices,
    };
    if kept == mesh.positions.len() && degenerate_faces == 0 {
        return (mesh, report);
    }

    let mut new_index = vec![u32::MAX; mesh.positions.len()];
    let mut order = Vec::with_capacity(kept);
    for (v, _) in referenced.iter().enumerate().filter(|&(_, &r)| r) {
        new_index[v] = order.len() as u32;
        order.push(v);
    }
    for tri in &mut triangles {
        *tri = tri.map(|v| new_index[v as usize]);
    }
    let repaired = IndexedMesh {
        positions: order.iter().map(|&v| mesh.positions[v]).collect(),
        triangles,
        ids: mesh
            .ids
            .as_ref()
            .map(|ids| order.iter().map(|&v| ids[v]).collect()),
        attributes: mesh.attributes.iter().map(|a| a.gather(&order)).collect(),
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
