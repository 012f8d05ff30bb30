//! Which elements break the criteria. Only these are ever touched: a mesh that meets every criterion
//! gets no operation at all (improvement is conservative, because every re-sampled vertex costs
//! coherence — paper §4.1).

use super::geometry::{dihedral_degrees, face_normal, folds_beyond, has_angle_below, min_angle};
use super::params::Limits;
use super::queue::{Kind, Task};
use crate::mesh::{FaceId, HalfEdgeId, Mesh};
use glam::Vec3;
use rayon::prelude::*;

/// The face's task when its smallest angle is below the limit.
pub(super) fn face_task(mesh: &Mesh, f: FaceId, limits: &Limits) -> Option<Task> {
    face_task_at(mesh, f, mesh.face_positions(f), limits)
}

/// `face_task` given the face's corner positions.
fn face_task_at(mesh: &Mesh, f: FaceId, p: [Vec3; 3], limits: &Limits) -> Option<Task> {
    if !has_angle_below(p, limits.cos_angle_filter) {
        return None;
    }
    let angle = min_angle(p);
    (angle < limits.min_angle).then(|| Task::face(mesh, angle, mesh.face_half_edge(f)))
}

/// The edge's tasks: too short, and too sharp a dihedral angle.
pub(super) fn edge_tasks(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> [Option<Task>; 2] {
    let n = |e: HalfEdgeId| face_normal(mesh.face_positions(mesh.face(e)));
    edge_tasks_with(mesh, h, limits, [n(h), n(mesh.twin(h))])
}

/// `edge_tasks` given the normals of the edge's two faces.
fn edge_tasks_with(
    mesh: &Mesh,
    h: HalfEdgeId,
    limits: &Limits,
    [first, second]: [Vec3; 2],
) -> [Option<Task>; 2] {
    let length = mesh
        .position(mesh.origin(h))
        .distance(mesh.position(mesh.target(h)));
    let short = (length < limits.min_edge).then(|| Task::edge(mesh, Kind::ShortEdge, length, h));
    let sharp = folds_beyond(first, second, limits.cos_dihedral_filter)
        .then(|| dihedral_degrees(first, second))
        .flatten()
        .filter(|&angle| angle < limits.min_dihedral)
        .map(|angle| Task::edge(mesh, Kind::SharpDihedral, angle, h));
    [short, sharp]
}

/// Every bad element of the mesh, in slot order (faces, then edges), found in parallel.
pub(super) fn scan(mesh: &Mesh, limits: &Limits) -> Vec<Task> {
    let faces: Vec<FaceId> = mesh.faces().collect();
    let measured: Vec<(Vec3, Option<Task>)> = faces
        .par_iter()
        .map(|&f| {
            let p = mesh.face_positions(f);
            (face_normal(p), face_task_at(mesh, f, p, limits))
        })
        .collect();
    let slots = faces.last().map_or(0, |f| f.0 as usize + 1);
    let mut normals = vec![Vec3::ZERO; slots];
    let mut tasks = Vec::new();
    for (f, (n, task)) in faces.iter().zip(measured) {
        normals[f.0 as usize] = n;
        tasks.extend(task);
    }
    let edges: Vec<HalfEdgeId> = mesh.edges().collect();
    let edge_tasks: Vec<Task> = edges
        .par_iter()
        .flat_map_iter(|&h| {
            let n = [h, mesh.twin(h)].map(|e| normals[mesh.face(e).0 as usize]);
            edge_tasks_with(mesh, h, limits, n).into_iter().flatten()
        })
        .collect();
    tasks.extend(edge_tasks);
    tasks
}

/// Pushes the bad elements among `faces` and their edges (each edge once).
pub(super) fn rescan(mesh: &Mesh, faces: &[FaceId], limits: &Limits, push: &mut impl FnMut(Task)) {
    let normals: Vec<Vec3> = faces
        .iter()
        .map(|&f| face_normal(mesh.face_positions(f)))
        .collect();
    for (i, &f) in faces.iter().enumerate() {
        if let Some(task) = face_task(mesh, f, limits) {
            push(task);
        }
        let h = mesh.face_half_edge(f);
        for e in [h, mesh.next(h), mesh.prev(h)] {
            let across = mesh.face(mesh.twin(e));
            let inside = faces.iter().position(|&g| g == across);
            if inside.is_some_and(|j| j < i) {
                continue;
            }
            let other = match inside {
                Some(j) => normals[j],
                None => face_normal(mesh.face_positions(across)),
            };
            edge_tasks_with(mesh, e, limits, [normals[i], other])
                .into_iter()
                .flatten()
                .for_each(&mut *push);
        }
    }
}
