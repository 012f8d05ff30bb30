//! Edge splits at the midpoint (paper §4.1), which never move the surface: every edge longer than the
//! limit, longest first — the two halves of an edge just past the limit are at least `L` long, above
//! the collapse threshold — and, as a last resort, the longest edge of a badly proportioned triangle.
//! A long edge whose flip passes the flip's checks (thesis §3.2.1) is flipped instead: where
//! registration shears the mesh, the other diagonal of the pair is short enough, and a flip
//! re-samples no vertex.

use super::flip::check_flip;
use super::geometry::fails;
use super::params::Limits;
use super::report::{ImproveReport, Refusal};
use crate::mesh::{HalfEdgeId, Mesh, VertexId};
use glam::Vec3;
use std::collections::BinaryHeap;

/// An edge to split: longest first, then by the persistent ids of its ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct LongEdge {
    length_bits: u32,
    ids: std::cmp::Reverse<(u64, u64)>,
}

/// Splits every edge longer than `limits.max_edge` (repeatedly, until none is); returns how many.
/// No vertex is removed during the pass, so the heap can name edges by vertex slots.
pub(super) fn split_long_edges(
    mesh: &mut Mesh,
    limits: &Limits,
    report: &mut ImproveReport,
) -> usize {
    let key = |mesh: &Mesh, h: HalfEdgeId| {
        let (a, b) = (mesh.origin(h), mesh.target(h));
        let length = mesh.position(a).distance(mesh.position(b));
        let (ia, ib) = (mesh.id(a), mesh.id(b));
        (length > limits.max_edge).then_some(LongEdge {
            length_bits: length.to_bits(),
            ids: std::cmp::Reverse((ia.min(ib), ia.max(ib))),
        })
    };
    let mut heap: BinaryHeap<(LongEdge, u32, u32)> = mesh
        .edges()
        .filter_map(|h| key(mesh, h).map(|k| (k, mesh.origin(h).0, mesh.target(h).0)))
        .collect();
    let mut splits = 0;
    while let Some((edge, a, b)) = heap.pop() {
        let (a, b) = (VertexId(a), VertexId(b));
        let Some(h) = mesh.find_half_edge(a, b) else {
            continue;
        };
        if key(mesh, h) != Some(edge) {
            continue;
        }
        // The other diagonal re-samples nothing: a flip serves where it passes its checks, which
        // include a new edge within the limit.
        if check_flip(mesh, h, limits).is_ok() && mesh.flip(h).is_some() {
            report.flips += 1;
            continue;
        }
        let Some(m) = mesh.split_edge(h, 0.5) else {
            report.refused(Refusal::Degenerate);
            continue;
        };
        splits += 1;
        let around: Vec<HalfEdgeId> = mesh.outgoing(m).collect();
        for e in around {
            if let Some(k) = key(mesh, e) {
                heap.push((k, m.0, mesh.target(e).0));
            }
        }
    }
    report.splits += splits;
    splits
}

/// Whether splitting the edge of `h` at its midpoint fixes a triangle without moving the surface. A
/// triangle whose longest edge is more than `edge_ratio` times its shortest, and whose short edge
/// cannot be collapsed without moving the surface too far, is fixed by halving its longest edge. The
/// split must not raise the number of failing faces among those it replaces: a needle that still
/// fails after one split is half as long, and its short edge may then be collapsed without creating
/// an edge past the split threshold. It must create no edge shorter than the collapse threshold, so
/// it never feeds the collapse queue, and every repeated split halves an edge at least `L` long.
pub(super) fn check_split(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Result<(), Refusal> {
    let t = mesh.twin(h);
    let (a, b) = (mesh.origin(h), mesh.target(h));
    let (c, d) = (mesh.origin(mesh.prev(h)), mesh.origin(mesh.prev(t)));
    let [pa, pb, pc, pd] = [a, b, c, d].map(|v| mesh.position(v));
    let m = (pa + pb) * 0.5;
    if [pa, pc, pd]
        .iter()
        .any(|&p| m.distance(p) < limits.min_edge)
    {
        return Err(Refusal::ShortEdge);
    }
    let failing = |faces: &[[Vec3; 3]]| {
        faces
            .iter()
            .filter(|&&f| fails(f, limits.min_angle, limits.edge_ratio))
            .count()
    };
    let old = [[pa, pb, pc], [pb, pa, pd]];
    let new = [[pa, m, pc], [m, pb, pc], [pb, m, pd], [m, pa, pd]];
    if failing(&new) > failing(&old) {
        return Err(Refusal::NoGain);
    }
    Ok(())
}
