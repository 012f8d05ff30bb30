//! When an edge flip is allowed. The paper skips flips; the thesis (§3.2.1) shows what they need: the
//! new faces must not turn over and the surface must not move much (bounded here by distance, see
//! `deviation`). Flips re-sample no vertex, so they cost no coherence; they are only tried on a bad
//! element and only kept when they raise the smallest angle of the pair.

use super::deviation::within;
use super::diamond::diamond;
use super::geometry::{face_normal, fold, folds_worse, min_angle_sine, reliable_normal};
use super::params::Limits;
use super::report::Refusal;
use crate::mesh::{HalfEdgeId, Mesh};
use glam::Vec3;

/// A flip must raise the sine of the pair's smallest angle by at least this much (about 0.001° at
/// the angle limit), so rounding can never make two flips undo each other.
const MIN_GAIN: f32 = 1e-5;

/// Whether the edge of `h`, between faces `(a, b, c)` and `(b, a, d)`, may be flipped to `(c, d)`.
pub(super) fn check_flip(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Result<(), Refusal> {
    let t = mesh.twin(h);
    let [a, b, c, d] = diamond(mesh, h);
    if mesh.valence(a) <= 3 || mesh.valence(b) <= 3 {
        return Err(Refusal::Valence);
    }
    if c == d || mesh.find_half_edge(c, d).is_some() {
        return Err(Refusal::LinkCondition);
    }
    let [pa, pb, pc, pd] = [a, b, c, d].map(|v| mesh.position(v));
    let old = [[pa, pb, pc], [pb, pa, pd]];
    let new = [[pd, pc, pa], [pc, pd, pb]];
    let worst = |faces: &[[Vec3; 3]; 2]| min_angle_sine(faces[0]).min(min_angle_sine(faces[1]));
    if worst(&new) < worst(&old) + MIN_GAIN {
        return Err(Refusal::NoGain);
    }
    // A sliver's normal is noise (see `geometry::reliable_normal`): the pair's summed normal
    // stands in for it.
    let pair = face_normal(old[0]) + face_normal(old[1]);
    let old_normals = old.map(|f| reliable_normal(f).unwrap_or(pair));
    let new_normals = new.map(face_normal);
    if new_normals
        .iter()
        .any(|n| old_normals.iter().any(|o| n.dot(*o) <= 0.0))
    {
        return Err(Refusal::NormalFlip);
    }
    if pc.distance(pd) > limits.max_edge {
        return Err(Refusal::LongEdge);
    }
    let beyond = |e: HalfEdgeId| reliable_normal(mesh.face_positions(mesh.face(mesh.twin(e))));
    let [next_h, prev_h, next_t, prev_t] =
        [mesh.next(h), mesh.prev(h), mesh.next(t), mesh.prev(t)].map(beyond);
    // new[0] = (d, c, a) borders the faces beyond (c, a) and (a, d); new[1] = (c, d, b) those
    // beyond (d, b) and (b, c). old[0] = (a, b, c) borders the faces beyond (b, c) and (c, a);
    // old[1] = (b, a, d) those beyond (a, d) and (d, b).
    // The sharpest fold of the two faces `x`, `y` with each other and with their neighbours
    // beyond: `x` with the first two of `beyond`, `y` with the last two.
    let sharpest = |x: Option<Vec3>, y: Option<Vec3>, beyond: [Option<Vec3>; 4]| {
        [
            (x, y),
            (x, beyond[0]),
            (x, beyond[1]),
            (y, beyond[2]),
            (y, beyond[3]),
        ]
        .iter()
        .map(|&(x, y)| fold(x, y).unwrap_or(-1.0))
        .fold(-1.0f32, f32::max)
    };
    let [new0, new1] = new.map(reliable_normal);
    let after = sharpest(new0, new1, [prev_h, next_t, prev_t, next_h]);
    // The folds before the flip matter only when the new ones pass the limit.
    if after > limits.cos_min_dihedral {
        let [old0, old1] = old.map(reliable_normal);
        let before = sharpest(old0, old1, [next_h, prev_h, next_t, prev_t]);
        if folds_worse(after, before, limits.cos_min_dihedral) {
            return Err(Refusal::SharpDihedral);
        }
    }
    if !within(&new, &old, limits.deviation) {
        return Err(Refusal::Deviation);
    }
    Ok(())
}
