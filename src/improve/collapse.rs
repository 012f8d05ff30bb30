//! When an edge collapse is allowed (paper §4.1; thesis §3.2.2). The new vertex sits at the edge's
//! midpoint, as in the paper, so the event's forward rule `(a + b)/2` is also where the vertex goes
//! (where the older end was carried over from an earlier frame, that end goes there instead, a
//! merge; the checks are the same).
//! The mesh itself refuses non-manifold results (link condition, valence-3 trap, degenerate faces);
//! these checks add the geometric ones it leaves to improvement: no face turns over, no fold sharper
//! than the dihedral limit, no new edge past the split threshold, and the surface moves no farther
//! than the deviation limit. Triangle quality is not guarded: a collapse may leave a small angle
//! behind, which the queue then fixes like any other, and guarding it blocks more fixes than it saves.
//!
//! An edge shorter than [`NEGLIGIBLE`] of the collapse threshold moves no face measurably when it
//! collapses: its two triangles are needles whose normals say nothing, and a fold or an inverted
//! face beside them is already there, hidden behind a needle. The fold and orientation checks
//! would keep such a needle for ever (on the DFSPH double dam break's frame 15, 71 refusals of
//! collapses of edges near 10⁻⁶ L were of that kind, and output frames held 0.001° triangles),
//! so they are skipped for it; the mesh's own checks and the deviation bound still hold.

use super::deviation::within;
use super::diamond::diamond;
use super::geometry::{face_normal, fold, folds_worse, min_angle, reliable_normal};
use super::params::Limits;
use super::report::Refusal;
use crate::mesh::{HalfEdgeId, Mesh, VertexId};
use glam::Vec3;

/// A face of the fan the collapse creates around the new vertex `m`: `(m, x, y)`, its normal, and the
/// normal of the untouched face beyond its edge `(x, y)`.
struct FanFace {
    x: u32,
    y: u32,
    corners: [Vec3; 3],
    normal: Vec3,
    outside: Option<Vec3>,
}

/// Whether the edge of `h` may be collapsed to its midpoint.
///
/// Faces whose own normal is unreliable (slivers, see `geometry::reliable_normal`) are compared with
/// the area-weighted normal of the whole neighbourhood instead, and a fold past the dihedral limit is
/// refused only when the collapse makes the neighbourhood's sharpest fold sharper: without both rules
/// a zero-length edge between two slivers could never be collapsed.
pub(super) fn check_collapse(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Result<(), Refusal> {
    let m = (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h))) * 0.5;
    check_contraction(mesh, h, m, limits, false)
}

/// Whether the edge of `h` may be merged into its origin, which stays where it is. A merge keeps
/// one end's id where the paper's collapse re-samples both, so it is tried first. It must pass the
/// collapse's checks (with the kept end where it is) and leave nothing for the queue behind: no
/// angle below the limit, no edge shorter than the collapse threshold and no fold past the
/// dihedral limit, so a merge never starts a cascade. Otherwise the paper's collapse serves.
pub(super) fn check_merge(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Result<(), Refusal> {
    check_contraction(mesh, h, mesh.position(mesh.origin(h)), limits, true)
}

/// Edges shorter than this fraction of the collapse threshold collapse without the fold and
/// orientation checks (see the module comment).
const NEGLIGIBLE: f32 = 1e-3;

/// The checks of a collapse of the edge of `h` to a vertex at `m`; `merge` adds a merge's.
fn check_contraction(
    mesh: &Mesh,
    h: HalfEdgeId,
    m: Vec3,
    limits: &Limits,
    merge: bool,
) -> Result<(), Refusal> {
    let t = mesh.twin(h);
    let [a, b, c, d] = diamond(mesh, h);
    if mesh.valence(c) <= 3 || mesh.valence(d) <= 3 {
        return Err(Refusal::Valence);
    }
    let ring: Vec<VertexId> = mesh.neighbours(a).collect();
    let shared = mesh.neighbours(b).filter(|v| ring.contains(v)).count();
    if shared != 2 {
        return Err(Refusal::LinkCondition);
    }
    let (fa, fb) = (mesh.face(h), mesh.face(t));
    let negligible =
        !merge && mesh.position(a).distance(mesh.position(b)) < NEGLIGIBLE * limits.min_edge;
    let star: Vec<HalfEdgeId> = mesh.outgoing(a).chain(mesh.outgoing(b)).collect();
    let mut region: Option<Vec3> = None;
    let mut old = Vec::with_capacity(star.len());
    let mut fan = Vec::with_capacity(star.len());
    for &e in &star {
        let f = mesh.face(e);
        if f == fa || f == fb {
            continue;
        }
        let corners = mesh.face_positions(f);
        old.push(corners);
        let (x, y) = (mesh.target(e), mesh.origin(mesh.prev(e)));
        let new = [m, mesh.position(x), mesh.position(y)];
        let normal = face_normal(new);
        let reference = match reliable_normal(corners) {
            Some(n) => n,
            None => *region.get_or_insert_with(|| {
                star.iter()
                    .map(|&e| face_normal(mesh.face_positions(mesh.face(e))))
                    .sum()
            }),
        };
        if normal.dot(reference) <= 0.0 && !negligible {
            return Err(Refusal::NormalFlip);
        }
        let length = m.distance(new[1]);
        if length > limits.max_edge {
            return Err(Refusal::LongEdge);
        }
        if merge && length < limits.min_edge {
            return Err(Refusal::ShortEdge);
        }
        if merge && min_angle(new) < limits.min_angle {
            return Err(Refusal::SmallAngle);
        }
        let beyond = mesh.face_positions(mesh.face(mesh.twin(mesh.next(e))));
        fan.push(FanFace {
            x: x.0,
            y: y.0,
            corners: new,
            normal,
            outside: reliable_normal(beyond),
        });
    }
    let mut after = -1.0f32;
    for f in &fan {
        let next = fan.iter().find(|g| g.x == f.y).map(|g| g.normal);
        let own = reliable_normal(f.corners);
        for other in [f.outside, next] {
            after = after.max(fold(own, other).unwrap_or(-1.0));
        }
    }
    if merge && after > limits.cos_min_dihedral {
        return Err(Refusal::SharpDihedral);
    }
    // The folds before the collapse matter only when the new ones pass the limit.
    if !negligible
        && after > limits.cos_min_dihedral
        && folds_worse(after, sharpest_fold(mesh, &star), limits.cos_min_dihedral)
    {
        return Err(Refusal::SharpDihedral);
    }
    old.extend([mesh.face_positions(fa), mesh.face_positions(fb)]);
    let new: Vec<[Vec3; 3]> = fan.iter().map(|f| f.corners).collect();
    if !within(&new, &old, limits.deviation) {
        return Err(Refusal::Deviation);
    }
    Ok(())
}

/// The sharpest fold (see `geometry::fold`) between a face of `star` and any face next to it.
fn sharpest_fold(mesh: &Mesh, star: &[HalfEdgeId]) -> f32 {
    let mut sharpest = -1.0f32;
    for &e in star {
        let own = reliable_normal(mesh.face_positions(mesh.face(e)));
        for k in [e, mesh.next(e), mesh.prev(e)] {
            let beyond = reliable_normal(mesh.face_positions(mesh.face(mesh.twin(k))));
            sharpest = sharpest.max(fold(own, beyond).unwrap_or(-1.0));
        }
    }
    sharpest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::improve::ImproveParams;
    use crate::mesh::IndexedMesh;

    /// An octahedron flattened to a thin blade (its rim folds by about 6°, far past the dihedral
    /// limit) whose rim vertex (1, 0, 0) is split into two `gap` apart across the blade, with a
    /// needle on each side of the rim between them: the half-edge from one to the other.
    fn split_blade(gap: f32) -> (Mesh, HalfEdgeId) {
        let s = 0.05;
        let positions = vec![
            Vec3::new(1.0, 0.5 * gap, 0.0),
            Vec3::new(1.0, -0.5 * gap, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, s, 0.0),
            Vec3::new(0.0, -s, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
        ];
        let (a, b, w, top, bottom, front, back) = (0, 1, 2, 3, 4, 5, 6);
        let triangles = vec![
            [a, top, front],
            [a, back, top],
            [b, front, bottom],
            [b, bottom, back],
            [w, front, top],
            [w, top, back],
            [w, bottom, front],
            [w, back, bottom],
            [a, front, b],
            [a, b, back],
        ];
        let mesh = Mesh::from_indexed(&IndexedMesh::new(positions, triangles)).unwrap();
        let h = mesh
            .outgoing(VertexId(a))
            .find(|&e| mesh.target(e) == VertexId(b))
            .unwrap();
        (mesh, h)
    }

    #[test]
    fn a_negligible_edge_collapses_where_its_needles_hide_a_fold() {
        let limits = Limits::new(&ImproveParams::new(1.0));
        // 10⁻⁵ of the edge length: the collapse gives back the blade, whose rim fold is there
        // already, hidden behind the needles.
        let (mesh, h) = split_blade(1e-5);
        assert_eq!(check_collapse(&mesh, h, &limits), Ok(()));
        let mut collapsed = mesh.clone();
        assert!(collapsed.collapse(h, Vec3::new(1.0, 0.0, 0.0)).is_some());
        collapsed.to_indexed().validate().unwrap();
        // A tenth of the edge length moves the faces: the fold it would open is refused.
        let (mesh, h) = split_blade(0.1);
        assert_eq!(
            check_collapse(&mesh, h, &limits),
            Err(Refusal::SharpDihedral)
        );
    }
}
