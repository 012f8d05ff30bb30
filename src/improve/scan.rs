//! Which elements break the criteria. Only these are ever touched: a mesh that meets every criterion
//! gets no operation at all (improvement is conservative, because every re-sampled vertex costs
//! coherence — paper §4.1).

use super::geometry::{dihedral_degrees, face_normal, min_angle};
use super::params::Limits;
use super::queue::{Kind, Task};
use crate::mesh::{FaceId, HalfEdgeId, Mesh};
use rayon::prelude::*;

/// The face's task when its smallest angle is below the limit.
pub(super) fn face_task(mesh: &Mesh, f: FaceId, limits: &Limits) -> Option<Task> {
    let angle = min_angle(mesh.face_positions(f));
    (angle < limits.min_angle).then(|| Task::face(mesh, angle, mesh.face_half_edge(f)))
}

/// The edge's tasks: too short, and too sharp a dihedral angle.
pub(super) fn edge_tasks(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> [Option<Task>; 2] {
    let length = mesh
        .position(mesh.origin(h))
        .distance(mesh.position(mesh.target(h)));
    let short = (length < limits.min_edge).then(|| Task::edge(mesh, Kind::ShortEdge, length, h));
    let sharp = dihedral_of(mesh, h)
        .filter(|&angle| angle < limits.min_dihedral)
        .map(|angle| Task::edge(mesh, Kind::SharpDihedral, angle, h));
    [short, sharp]
}

/// Interior dihedral angle at the edge of `h` (degrees).
pub(super) fn dihedral_of(mesh: &Mesh, h: HalfEdgeId) -> Option<f32> {
    let n = |e: HalfEdgeId| face_normal(mesh.face_positions(mesh.face(e)));
    dihedral_degrees(n(h), n(mesh.twin(h)))
}

/// Every bad element of the mesh, in slot order (faces, then edges), found in parallel.
pub(super) fn scan(mesh: &Mesh, limits: &Limits) -> Vec<Task> {
    let faces: Vec<FaceId> = mesh.faces().collect();
    let edges: Vec<HalfEdgeId> = mesh.edges().collect();
    let mut tasks: Vec<Task> = faces
        .par_iter()
        .filter_map(|&f| face_task(mesh, f, limits))
        .collect();
    let edge_tasks: Vec<Task> = edges
        .par_iter()
        .flat_map_iter(|&h| edge_tasks(mesh, h, limits).into_iter().flatten())
        .collect();
    tasks.extend(edge_tasks);
    tasks
}

/// Pushes the bad elements among `faces` and their edges.
pub(super) fn rescan(mesh: &Mesh, faces: &[FaceId], limits: &Limits, push: &mut impl FnMut(Task)) {
    for &f in faces {
        if let Some(task) = face_task(mesh, f, limits) {
            push(task);
        }
        let h = mesh.face_half_edge(f);
        for e in [h, mesh.next(h), mesh.prev(h)] {
            edge_tasks(mesh, e, limits)
                .into_iter()
                .flatten()
                .for_each(&mut *push);
        }
    }
}
