//! Fixing short edges, small angles and sharp dihedral angles, worst first. Each bad element has a
//! short list of candidate operations, tried in order until one passes its checks: a flip first where
//! it can help (it re-samples nothing), then a move of one end of the short or sharply folded edge
//! along the surface (it re-samples nothing either; see `relax`), then a merge of that edge into one
//! of its ends (it re-samples that end alone), then the paper's collapse (§4.1), then collapses that remove
//! one end of a short edge along a flatter direction, and last a split that halves an over-long edge
//! of a badly proportioned triangle. After an operation the faces it created are examined again, so
//! new problems join the queue. A collapse whose older end was carried over from an earlier frame
//! keeps that end, moved to the midpoint, rather than creating a vertex there; a merge into the
//! newer end keeps such an older end too, moved to where the newer one stood.

use super::collapse::{check_collapse, check_merge};
use super::flip::check_flip;
use super::params::Limits;
use super::queue::{Kind, Queue, Task};
use super::relax::check_relax;
use super::report::{ImproveReport, Operation, Refusal};
use super::scan::{edge_tasks, face_task, rescan, scan};
use super::split::check_split;
use crate::mesh::{FaceId, HalfEdgeId, Mesh};
use glam::Vec3;
use rustc_hash::FxHashSet;

/// One candidate operation on an edge.
#[derive(Debug, Clone, Copy)]
pub(super) enum Fix {
    Flip(HalfEdgeId),
    Collapse(HalfEdgeId),
    /// Merge into the origin of the half-edge.
    Merge(HalfEdgeId),
    Split(HalfEdgeId),
    /// Move the origin of the half-edge along the surface.
    Relax(HalfEdgeId),
}

impl Fix {
    pub fn operation(self) -> Operation {
        match self {
            Fix::Flip(_) => Operation::Flip,
            Fix::Collapse(_) => Operation::Collapse,
            Fix::Merge(_) => Operation::Merge,
            Fix::Split(_) => Operation::Split,
            Fix::Relax(_) => Operation::Relax,
        }
    }
}

/// The operations that could fix the element of `task` located at `h`, most preferred first. A small
/// angle is opposite the shortest edge: collapsing that edge removes the triangle; a triangle with
/// one huge angle (a "cap") is better served by flipping its longest edge.
pub(super) fn candidates<'a>(
    mesh: &'a Mesh,
    task: &Task,
    h: HalfEdgeId,
    limits: &'a Limits,
) -> Box<dyn Iterator<Item = Fix> + 'a> {
    let later = |e: HalfEdgeId| std::iter::once(()).flat_map(move |()| removals(mesh, e, limits));
    match task.kind {
        Kind::ShortEdge => Box::new(
            relaxes(mesh, h, limits)
                .into_iter()
                .chain(merges(mesh, h))
                .chain(std::iter::once(Fix::Collapse(h)))
                .chain(later(h))
                .chain([h, mesh.twin(h)].map(|e| Fix::Split(longest_edge(mesh, e)))),
        ),
        Kind::SharpDihedral => Box::new(
            relaxes(mesh, h, limits)
                .into_iter()
                .chain(merges(mesh, h))
                .chain([Fix::Collapse(h), Fix::Flip(h)]),
        ),
        Kind::SmallAngle => {
            let mut edges = [h, mesh.next(h), mesh.prev(h)];
            edges.sort_by(|&x, &y| length(mesh, x).total_cmp(&length(mesh, y)));
            let [shortest, middle, longest] = edges;
            Box::new(
                std::iter::once(Fix::Flip(longest))
                    .chain(relaxes(mesh, shortest, limits))
                    .chain(merges(mesh, shortest))
                    .chain(std::iter::once(Fix::Collapse(shortest)))
                    .chain(later(shortest))
                    .chain([
                        Fix::Collapse(middle),
                        Fix::Flip(middle),
                        Fix::Split(longest),
                    ]),
            )
        }
    }
}

/// The half-edges of the edge of `h` out of its older end (the smaller id), then out of its newer.
fn older_first(mesh: &Mesh, h: HalfEdgeId) -> [HalfEdgeId; 2] {
    let t = mesh.twin(h);
    if mesh.id(mesh.origin(h)) < mesh.id(mesh.origin(t)) {
        [h, t]
    } else {
        [t, h]
    }
}

/// The two merges of the edge of `h`, keeping the older end (the smaller id) first: a short edge
/// one of whose ends must go costs that end alone, and the end that has been tracked longer stays.
fn merges(mesh: &Mesh, h: HalfEdgeId) -> [Fix; 2] {
    older_first(mesh, h).map(Fix::Merge)
}

/// Moves of either end of the edge of `h` along the surface, for the ends that may move
/// (`ImproveParams::relax_below`), the newer end (the larger id) first: a move keeps both ids, so
/// it comes before any removal.
fn relaxes(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Vec<Fix> {
    let [older, newer] = older_first(mesh, h);
    [newer, older]
        .into_iter()
        .filter(|&e| mesh.id(mesh.origin(e)) < limits.relax_below)
        .map(Fix::Relax)
        .collect()
}

/// Collapses that remove one end of the short edge of `h` by merging it with another neighbour, so
/// that the merged vertex lands at least `min_edge` from the other end. Where the surface curves
/// across the short edge but less along another edge of its ends, such a collapse moves the surface
/// far less than collapsing the short edge itself. Shortest first (the smallest move).
fn removals(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Vec<Fix> {
    let (a, b) = (mesh.origin(h), mesh.target(h));
    let mut out: Vec<(f32, HalfEdgeId)> = [(a, b), (b, a)]
        .into_iter()
        .flat_map(|(end, other)| {
            mesh.outgoing(end).filter_map(move |e| {
                let x = mesh.target(e);
                let merged = (mesh.position(end) + mesh.position(x)) * 0.5;
                (x != other && merged.distance(mesh.position(other)) >= limits.min_edge)
                    .then(|| (length(mesh, e), e))
            })
        })
        .collect();
    out.sort_by(|x, y| x.0.total_cmp(&y.0));
    out.into_iter().map(|(_, e)| Fix::Collapse(e)).collect()
}

fn length(mesh: &Mesh, h: HalfEdgeId) -> f32 {
    mesh.position(mesh.origin(h))
        .distance(mesh.position(mesh.target(h)))
}

/// The longest edge of the face of `h`.
fn longest_edge(mesh: &Mesh, h: HalfEdgeId) -> HalfEdgeId {
    [mesh.next(h), mesh.prev(h)].into_iter().fold(h, |best, e| {
        if length(mesh, e) > length(mesh, best) {
            e
        } else {
            best
        }
    })
}

/// Why `fix` would be refused now, if it would; for a move, where the vertex goes.
pub(super) fn check(mesh: &Mesh, fix: Fix, limits: &Limits) -> Result<Option<Vec3>, Refusal> {
    match fix {
        Fix::Flip(h) => check_flip(mesh, h, limits).map(|()| None),
        Fix::Collapse(h) => check_collapse(mesh, h, limits).map(|()| None),
        Fix::Merge(h) => check_merge(mesh, h, limits).map(|()| None),
        Fix::Split(h) => check_split(mesh, h, limits).map(|()| None),
        Fix::Relax(h) => check_relax(mesh, h, limits).map(Some),
    }
}

/// Performs a fix whose checks passed (a move to `to`, where they put it); returns the faces it
/// created, or `None` when the mesh itself refuses (a face would be degenerate).
fn apply(
    mesh: &mut Mesh,
    (fix, to): (Fix, Option<Vec3>),
    limits: &Limits,
    report: &mut ImproveReport,
) -> Option<Vec<FaceId>> {
    let created = match fix {
        Fix::Flip(h) => mesh.flip(h).map(|e| {
            report.flips += 1;
            vec![mesh.face(e), mesh.face(mesh.twin(e))]
        }),
        Fix::Collapse(h) => {
            let midpoint = (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h))) * 0.5;
            // Where the older end was carried over from an earlier frame, it is the vertex at the
            // midpoint: the collapse's geometry, re-sampling one vertex instead of two.
            let [older, _] = older_first(mesh, h);
            if mesh.id(mesh.origin(older)) < limits.relax_below {
                mesh.merge_to(older, midpoint).map(|m| {
                    report.merges += 1;
                    mesh.outgoing(m).map(|e| mesh.face(e)).collect()
                })
            } else {
                mesh.collapse(h, midpoint).map(|m| {
                    report.collapses += 1;
                    mesh.outgoing(m).map(|e| mesh.face(e)).collect()
                })
            }
        }
        Fix::Merge(h) => {
            // A merge into the newer end that would remove a carried older end keeps the older
            // one instead, moved to where the newer end stands: the same surface, one id kept.
            let (a, b) = (mesh.origin(h), mesh.target(h));
            let merged = if mesh.id(b) < mesh.id(a) && mesh.id(b) < limits.relax_below {
                let at = mesh.position(a);
                mesh.merge_to(mesh.twin(h), at)
            } else {
                mesh.merge(h)
            };
            merged.map(|m| {
                report.merges += 1;
                mesh.outgoing(m).map(|e| mesh.face(e)).collect()
            })
        }
        Fix::Split(h) => mesh.split_edge(h, 0.5).map(|m| {
            report.splits += 1;
            mesh.outgoing(m).map(|e| mesh.face(e)).collect()
        }),
        Fix::Relax(h) => {
            let v = mesh.origin(h);
            to.map(|q| {
                mesh.set_position(v, q);
                report.relaxes += 1;
                mesh.outgoing(v).map(|e| mesh.face(e)).collect()
            })
        }
    };
    if created.is_none() {
        report.refused(Refusal::Degenerate);
    }
    created
}

/// Operations one pass may perform per face it starts with. A pass on a mesh of `F` faces that fixes
/// what it can needs about one operation per bad element; on raw input (marching-cubes slivers of a
/// fluid cache) a split can make a neighbour bad that a collapse then fixes by undoing the split,
/// and this bound is what ends such a cycle. What is left is reported as unfixed.
const OPERATIONS_PER_FACE: usize = 4;

/// Works the queue of bad elements until it is empty, or until the pass has performed
/// [`OPERATIONS_PER_FACE`] operations per face of the mesh it started on; returns the number of
/// operations performed.
pub(super) fn fix_bad_elements(
    mesh: &mut Mesh,
    limits: &Limits,
    report: &mut ImproveReport,
) -> usize {
    let mut queue = Queue::new(scan(mesh, limits));
    let budget = OPERATIONS_PER_FACE * mesh.face_count() + 64;
    // A merge never removes a vertex this pass created, nor a collapse one this pass's last-resort
    // splits created; the next round may. Such a split beside an edge that cannot be fixed, undone
    // by a merge or collapse that sees only its own fan, would otherwise repeat until the budget ran
    // out (on real fluid frames, hundreds of thousands of times). Vertices other collapses
    // created stay free to go: holding them back to the next round costs coherence.
    let fresh = mesh.next_id();
    let mut split: FxHashSet<u64> = FxHashSet::default();
    let removes_fresh = |mesh: &Mesh, fix: Fix, split: &FxHashSet<u64>| match fix {
        Fix::Merge(h) => mesh.id(mesh.target(h)) >= fresh,
        Fix::Collapse(h) => [mesh.origin(h), mesh.target(h)]
            .iter()
            .any(|v| split.contains(&mesh.id(*v))),
        Fix::Flip(_) | Fix::Split(_) | Fix::Relax(_) => false,
    };
    let mut done = 0;
    while done < budget
        && let Some(task) = queue.pop()
    {
        let Some(h) = task.locate(mesh) else {
            continue;
        };
        if !still_bad(mesh, &task, h, limits) {
            continue;
        }
        let chosen = candidates(mesh, &task, h, limits).find_map(|fix| {
            if removes_fresh(mesh, fix, &split) {
                return None;
            }
            check(mesh, fix, limits)
                .map(|to| (fix, to))
                .map_err(|reason| report.refused(reason))
                .ok()
        });
        if let Some(faces) = chosen.and_then(|chosen| apply(mesh, chosen, limits, report)) {
            done += 1;
            if let Some((Fix::Split(_), _)) = chosen {
                split.insert(mesh.next_id() - 1);
            }
            rescan(mesh, &faces, limits, &mut |t| queue.push(t));
        }
    }
    done
}

/// Whether the element of `task` (at `h`) still breaks its criterion with the same measure: an
/// operation nearby may have fixed it, or changed its measure (then it is queued again under the new
/// one).
fn still_bad(mesh: &Mesh, task: &Task, h: HalfEdgeId, limits: &Limits) -> bool {
    let current = match task.kind {
        Kind::SmallAngle => face_task(mesh, mesh.face(h), limits),
        Kind::ShortEdge => edge_tasks(mesh, h, limits)[0],
        Kind::SharpDihedral => edge_tasks(mesh, h, limits)[1],
    };
    current.map(|t| t.measure) == Some(task.measure)
}
