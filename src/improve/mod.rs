//! Mesh improvement (paper §4.1): split edges that are too long, collapse edges that are too short or
//! that belong to a triangle with too small an angle or to too sharp a fold, and flip edges where that
//! raises the smallest angle without moving the surface (thesis §3.2.1). A short edge is merged into
//! one of its ends rather than collapsed to its midpoint wherever that leaves nothing to fix, so
//! removing a vertex re-samples one vertex rather than two; and before either, a vertex carried over
//! from an earlier frame is moved along the surface wherever that alone fixes the element, so it is
//! not re-sampled at all. Where a collapse is needed after all, such a vertex at its older end
//! stays, moved to the midpoint.
//!
//! Improvement is *conservative*: only elements that break a criterion are touched, so a mesh that
//! meets them all is left exactly as it is and records no event — every re-sampled vertex costs
//! coherence. It is *deterministic*: elements are processed worst first with ties broken by
//! persistent ids, so the result depends only on the mesh and the parameters. Every split and collapse
//! goes through the mesh's mutations, whose journal becomes the frame's event list (`events`).

mod assess;
mod collapse;
mod deviation;
mod diamond;
mod error;
mod fix;
mod flip;
mod geometry;
mod hausdorff;
mod params;
mod queue;
mod relax;
mod report;
mod scan;
mod split;

pub use crate::geometry::{ANGLE_BUCKETS, point_triangle_distance};
pub use assess::{Assessment, FailingTriangle, LENGTH_BUCKETS, RATIO_BUCKETS, assess};
pub use error::ImproveError;
pub use hausdorff::{SurfaceDistance, one_sided_hausdorff};
pub use params::ImproveParams;
pub use report::{ImproveReport, Operation, Problem, Refusal, Unfixed};

use crate::mesh::Mesh;
use params::Limits;
use queue::Kind;

/// Improves `mesh` in place: rounds of splitting long edges and fixing bad elements until a round
/// changes nothing (or `params.max_rounds` is reached), then reports what it did. What is left,
/// with the reasons each fix was refused, is [`unfixed`]'s to say.
///
/// The mesh's journal is switched on if it was off, so every split and collapse is recorded for the
/// frame's event list (`EventList::drain`) whoever calls this.
pub fn improve(mesh: &mut Mesh, params: &ImproveParams) -> Result<ImproveReport, ImproveError> {
    params.check()?;
    mesh.record_mutations();
    let limits = Limits::new(params);
    let mut report = ImproveReport::default();
    while report.rounds < params.max_rounds {
        report.rounds += 1;
        let split = split::split_long_edges(mesh, &limits, &mut report);
        let fixed = fix::fix_bad_elements(mesh, &limits, &mut report);
        if split + fixed == 0 {
            report.converged = true;
            break;
        }
    }
    Ok(report)
}

/// The elements of `mesh` that break `params`' criteria, by problem, worst first, each with the
/// reasons its candidate fixes are refused: what [`improve`] left. A query of its own rather than
/// part of every improvement's report: it scans the whole mesh and tries every bad element's fixes
/// again, and the tracker, which improves a frame up to four times, never reads it (on the dam
/// break's splash frames it was 26 ms of the 153 ms a frame spent improving).
pub fn unfixed(mesh: &Mesh, params: &ImproveParams) -> Result<Vec<Unfixed>, ImproveError> {
    params.check()?;
    let limits = &Limits::new(params);
    let mut out: Vec<Unfixed> = scan::scan(mesh, limits)
        .into_iter()
        .filter_map(|task| {
            let h = task.locate(mesh)?;
            let mut refusals: Vec<(Operation, Refusal)> = fix::candidates(mesh, &task, h, limits)
                .filter_map(|f| {
                    fix::check(mesh, f, limits)
                        .err()
                        .map(|r| (f.operation(), r))
                })
                .collect();
            refusals.sort();
            refusals.dedup();
            let ids = task.corners.map(|c| c.1);
            let (problem, vertices, measure) = match task.kind {
                Kind::SmallAngle => (Problem::SmallAngle, ids.to_vec(), task.measure),
                Kind::ShortEdge => (
                    Problem::ShortEdge,
                    ids[..2].to_vec(),
                    task.measure / limits.target,
                ),
                Kind::SharpDihedral => (Problem::SharpDihedral, ids[..2].to_vec(), task.measure),
            };
            Some(Unfixed {
                problem,
                vertices,
                measure,
                refusals,
            })
        })
        .collect();
    out.extend(mesh.edges().filter_map(|h| {
        let (a, b) = (mesh.origin(h), mesh.target(h));
        let length = mesh.position(a).distance(mesh.position(b));
        (length > limits.max_edge).then(|| Unfixed {
            problem: Problem::LongEdge,
            vertices: vec![mesh.id(a), mesh.id(b)],
            measure: length / limits.target,
            refusals: vec![(Operation::Split, Refusal::Degenerate)],
        })
    }));
    out.sort_by(|x, y| {
        x.problem
            .cmp(&y.problem)
            .then(x.measure.total_cmp(&y.measure))
            .then_with(|| x.vertices.cmp(&y.vertices))
    });
    Ok(out)
}
