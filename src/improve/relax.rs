//! When a vertex may be moved along the surface instead of removed. Registration bunches vertices
//! where a fluid surface shears (paper §4.2 fits positions, not spacing), and the short edges and
//! thin triangles it leaves would otherwise be merged or collapsed (§4.1), re-sampling a vertex each.
//! Moving one end of such an edge towards the centre of its neighbours, in its tangent plane, keeps
//! every id and fixes the element as well, wherever the move leaves nothing else to fix: every edge
//! of the vertex within the length band, no angle below the limit, no face turned over, no fold
//! past the dihedral limit, and the surface (the vertex itself included) within the deviation limit
//! of where it was. It is tried before any removal; where it fails a merge or collapse serves.

use super::deviation::within;
use super::geometry::{face_normal, fold, min_angle, reliable_normal};
use super::params::Limits;
use super::report::Refusal;
use crate::geometry::point_triangle_distance;
use crate::mesh::{HalfEdgeId, Mesh};
use glam::Vec3;

/// Fractions of the step to the neighbours' centre that are tried, largest first.
const STEPS: [f32; 2] = [1.0, 0.5];

/// Where the origin of `h` may move to fix its elements, or why it may not move.
pub(super) fn check_relax(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Result<Vec3, Refusal> {
    let v = mesh.origin(h);
    let p = mesh.position(v);
    let star: Vec<HalfEdgeId> = mesh.outgoing(v).collect();
    let old: Vec<[Vec3; 3]> = star
        .iter()
        .map(|&e| mesh.face_positions(mesh.face(e)))
        .collect();
    let normal = old.iter().map(|&f| face_normal(f)).sum::<Vec3>();
    let Some(n) = normal.try_normalize() else {
        return Err(Refusal::NormalFlip);
    };
    let centre = star
        .iter()
        .map(|&e| mesh.position(mesh.target(e)))
        .sum::<Vec3>()
        / star.len() as f32;
    let step = centre - p;
    let tangential = step - step.dot(n) * n;
    let mut refusal = Refusal::ShortEdge;
    for fraction in STEPS {
        let q = p + fraction * tangential;
        match check_position(mesh, &star, &old, q, limits) {
            Ok(()) => return Ok(q),
            Err(reason) => refusal = reason,
        }
    }
    Err(refusal)
}

/// The checks of moving the vertex whose outgoing half-edges are `star` (faces `old`) to `q`.
fn check_position(
    mesh: &Mesh,
    star: &[HalfEdgeId],
    old: &[[Vec3; 3]],
    q: Vec3,
    limits: &Limits,
) -> Result<(), Refusal> {
    let mut new = Vec::with_capacity(star.len());
    for (&e, &before) in star.iter().zip(old) {
        let (x, y) = (mesh.target(e), mesh.origin(mesh.prev(e)));
        let length = q.distance(mesh.position(x));
        if length < limits.min_edge {
            return Err(Refusal::ShortEdge);
        }
        if length > limits.max_edge {
            return Err(Refusal::LongEdge);
        }
        let face = [q, mesh.position(x), mesh.position(y)];
        if min_angle(face) < limits.min_angle {
            return Err(Refusal::SmallAngle);
        }
        if face_normal(face).dot(face_normal(before)) <= 0.0 {
            return Err(Refusal::NormalFlip);
        }
        new.push(face);
    }
    // Folds between neighbouring new faces, and between each new face and the face beyond its
    // outer edge.
    for (i, &e) in star.iter().enumerate() {
        let own = reliable_normal(new[i]);
        let next = reliable_normal(new[(i + 1) % new.len()]);
        let beyond = reliable_normal(mesh.face_positions(mesh.face(mesh.twin(mesh.next(e)))));
        for other in [next, beyond] {
            if fold(own, other).is_some_and(|f| f > limits.cos_min_dihedral) {
                return Err(Refusal::SharpDihedral);
            }
        }
    }
    let moved = old
        .iter()
        .map(|&[a, b, c]| point_triangle_distance(q, a, b, c))
        .fold(f32::INFINITY, f32::min);
    if moved > limits.deviation || !within(&new, old, limits.deviation) {
        return Err(Refusal::Deviation);
    }
    Ok(())
}
