//! Fixing short edges, small angles and sharp dihedral angles, worst first. Each bad element has a
//! short list of candidate operations, tried in order until one passes its checks: flips first where
//! they can help (they re-sample nothing), then collapses (paper §4.1). After an operation the faces
//! it touched are examined again, so new problems join the queue.

use super::collapse::check_collapse;
use super::flip::check_flip;
use super::split::check_split;
use super::params::Limits;
use super::queue::{Kind, Queue, Task};
use super::report::{ImproveReport, Refusal};
use super::scan::{rescan, scan};
use crate::mesh::{FaceId, HalfEdgeId, Mesh};

/// One candidate operation on an edge.
#[derive(Debug, Clone, Copy)]
pub(super) enum Fix {
    Flip(HalfEdgeId),
    Collapse(HalfEdgeId),
    Split(HalfEdgeId),
}

/// The operations that could fix the element of `task` located at `h`, most preferred first. A small
/// angle is opposite the shortest edge: collapsing that edge removes the triangle; a triangle with
/// one huge angle (a "cap") is better served by flipping its longest edge.
pub(super) fn candidates(mesh: &Mesh, task: &Task, h: HalfEdgeId, limits: &Limits) -> Vec<Fix> {
    match task.kind {
        Kind::ShortEdge => {
            let mut fixes = vec![Fix::Collapse(h)];
            fixes.extend(removals(mesh, h, limits));
            fixes.extend([h, mesh.twin(h)].map(|e| Fix::Split(longest_edge(mesh, e))));
            fixes
        }
        Kind::SharpDihedral => vec![Fix::Collapse(h), Fix::Flip(h)],
        Kind::SmallAngle => {
            let mut edges = [h, mesh.next(h), mesh.prev(h)];
            let length = |e: HalfEdgeId| {
                mesh.position(mesh.origin(e))
                    .distance(mesh.position(mesh.target(e)))
            };
            edges.sort_by(|&x, &y| length(x).total_cmp(&length(y)));
            let [shortest, middle, longest] = edges;
            let mut fixes = vec![Fix::Flip(longest), Fix::Collapse(shortest)];
            fixes.extend(removals(mesh, shortest, limits));
            fixes.extend([Fix::Collapse(middle), Fix::Flip(middle), Fix::Split(longest)]);
            fixes
        }
    }
}

/// Collapses that remove one end of the short edge of `h` by merging it with another neighbour, so
/// that the merged vertex lands at least `min_edge` from the other end: where the surface curves
/// across the short edge but not along some other edge of its ends, such a collapse moves the surface
/// far less than collapsing the short edge itself. Shortest first (the smallest move), so the order
/// depends only on the mesh.
fn removals(mesh: &Mesh, h: HalfEdgeId, limits: &Limits) -> Vec<Fix> {
    let (a, b) = (mesh.origin(h), mesh.target(h));
    let mut out: Vec<(f32, HalfEdgeId)> = [(a, b), (b, a)]
        .into_iter()
        .flat_map(|(end, other)| {
            mesh.outgoing(end).filter_map(move |e| {
                let x = mesh.target(e);
                let merged = (mesh.position(end) + mesh.position(x)) * 0.5;
                (x != other && merged.distance(mesh.position(other)) >= limits.min_edge)
                    .then(|| (mesh.position(end).distance(mesh.position(x)), e))
            })
        })
        .collect();
    out.sort_by(|x, y| x.0.total_cmp(&y.0));
    out.into_iter().map(|(_, e)| Fix::Collapse(e)).collect()
}

/// The longest edge of the face of `h`.
fn longest_edge(mesh: &Mesh, h: HalfEdgeId) -> HalfEdgeId {
    let length = |e: HalfEdgeId| mesh.position(mesh.origin(e)).distance(mesh.position(mesh.target(e)));
    [h, mesh.next(h), mesh.prev(h)]
        .into_iter()
        .max_by(|&x, &y| length(x).total_cmp(&length(y)))
        .unwrap_or(h)
}

/// What `fix` would cost (how far it moves the surface), or why it is refused.
pub(super) fn check(mesh: &Mesh, fix: Fix, limits: &Limits) -> Result<f32, Refusal> {
    match fix {
        Fix::Collapse(h) => check_collapse(mesh, h, limits).map(|c| c.deviation),
        Fix::Flip(h) => check_flip(mesh, h, limits),
        Fix::Split(h) => check_split(mesh, h, limits).map(|()| 0.0),
    }
}

/// Performs the best allowed fix among `fixes` — a flip if any is allowed (flips re-sample nothing),
/// else the collapse that moves the surface least, earlier candidates winning ties — and returns the
/// faces it created.
fn apply_best(mesh: &mut Mesh, fixes: &[Fix], limits: &Limits, report: &mut ImproveReport) -> Option<Vec<FaceId>> {
    let mut best: Option<(u8, f32, Fix)> = None;
    for &fix in fixes {
        match check(mesh, fix, limits) {
            Ok(deviation) => {
                let key = (rank(fix), deviation);
                if best.is_none_or(|(c, d, _)| key < (c, d)) {
                    best = Some((key.0, key.1, fix));
                }
                if std::env::var("FIRST").is_ok() { break; }
            }
            Err(reason) => report.refused(reason),
        }
    }
    let (_, _, fix) = best?;
    match fix {
        Fix::Collapse(h) => {
            let position = check_collapse(mesh, h, limits).ok()?.position;
            let Some(m) = mesh.collapse(h, position) else {
                report.refused(Refusal::Degenerate);
                return None;
            };
            report.collapses += 1;
            Some(mesh.outgoing(m).map(|e| mesh.face(e)).collect())
        }
        Fix::Split(h) => {
            let Some(m) = mesh.split_edge(h, 0.5) else {
                report.refused(Refusal::Degenerate);
                return None;
            };
            report.splits += 1;
            Some(mesh.outgoing(m).map(|e| mesh.face(e)).collect())
        }
        Fix::Flip(h) => {
            let Some(e) = mesh.flip(h) else {
                report.refused(Refusal::Degenerate);
                return None;
            };
            report.flips += 1;
            Some(vec![mesh.face(e), mesh.face(mesh.twin(e))])
        }
    }
}

/// Preference among allowed fixes: flips re-sample nothing, collapses are the paper's fix, splits
/// add vertices.
fn rank(fix: Fix) -> u8 {
    match fix {
        Fix::Flip(_) => 0,
        Fix::Collapse(_) => 1,
        Fix::Split(_) => 2,
    }
}

/// Works the queue of bad elements until it is empty; returns the number of operations performed.
pub(super) fn fix_bad_elements(mesh: &mut Mesh, limits: &Limits, report: &mut ImproveReport) -> usize {
    let mut queue: Queue = scan(mesh, limits).into_iter().collect();
    let mut done = 0;
    while let Some(task) = queue.pop() {
        let Some(h) = task.locate(mesh) else {
            continue;
        };
        if !still_bad(mesh, &task, h, limits) {
            continue;
        }
        let changed = apply_best(mesh, &candidates(mesh, &task, h, limits), limits, report);
        if let Some(faces) = changed {
            done += 1;
            rescan(mesh, &faces, limits, &mut |t| queue.push(t));
        }
    }
    done
}

/// Whether the element of `task` (at `h`) still breaks its criterion: an operation nearby may have
/// fixed it, or changed its measure (then it is in the queue again under the new measure).
fn still_bad(mesh: &Mesh, task: &Task, h: HalfEdgeId, limits: &Limits) -> bool {
    let current = match task.kind {
        Kind::SmallAngle => super::scan::face_task(mesh, mesh.face(h), limits).map(|t| t.measure),
        Kind::ShortEdge => super::scan::edge_tasks(mesh, h, limits)[0].map(|t| t.measure),
        Kind::SharpDihedral => super::scan::edge_tasks(mesh, h, limits)[1].map(|t| t.measure),
    };
    current == Some(task.measure)
}
