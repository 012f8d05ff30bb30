//! Non-rigid registration of the tracked mesh onto a target frame (paper §4.2, Birger's thesis
//! §3.3): a coarse stage over a deformation graph, solved by Gauss-Newton with faer's sparse
//! Cholesky factorization, then a fine per-vertex stage solved by conjugate gradients.
//!
//! All lengths are in mean edge lengths of the source mesh: positions are mapped to solver
//! coordinates (centroid at the origin, unit mean edge length) before either stage, so the paper's
//! weights mean the same at any scale. The CPU work is parallel and combines results in a fixed
//! order, so a registration gives bit-identical positions whatever the thread count.

mod adjacency;
mod assemble;
mod cholesky;
mod coarse;
mod correspond;
mod cover;
mod cpu;
mod damping;
mod energy;
mod error;
mod fine;
#[cfg(test)]
mod fine_parity;
mod fine_solve;
mod flush;
mod geodesic;
mod gpu;
mod graph;
#[cfg(test)]
mod jacobian_tests;
mod model;
mod normals;
mod operator;
mod options;
mod pattern;
mod pcg;
mod radix_heap;
mod report;
mod rigid;
mod small_blocks;
mod surface;

use std::time::{Duration, Instant};

use glam::Vec3;

pub use coarse::CoarseSolver;
use coarse::{Setup, rigid_start};
pub use error::{FactorizationError, RegisterError};
pub use graph::{DeformationGraph, GraphOptions};
pub use options::{CoarseOptions, FineOptions, LinearSolver, RegisterOptions};
pub use report::{
    CoarseReport, FineReport, FineRound, IterationReport, RegistrationReport, StageReport,
    StepTimes,
};

use crate::compute::Backend;
use crate::mesh::{IndexedMesh, Mesh, VertexId};
use crate::project::{Bvh, ProjectError};
use correspond::Projector;

/// The fine stage alone: per-vertex displacements moving `source` onto the target behind `bvh`
/// (projection and the solves on `backend`). Returns the new positions of `source`'s vertices.
/// [`register`] runs it after the coarse stage; alone it is regularized projection, for meshes
/// already close to the target.
pub fn fine_align(
    backend: &Backend,
    bvh: &Bvh,
    source: &IndexedMesh,
    options: &RegisterOptions,
) -> Result<(Vec<Vec3>, FineReport), RegisterError> {
    options.check()?;
    graph::check_indices(source, "source")?;
    let unit = source.mean_edge_length();
    if !(unit.is_finite() && unit > 0.0) {
        return Err(RegisterError::NoScale { which: "source" });
    }
    let surface = surface::Surface::new(&source.positions, &source.triangles, unit);
    let projector = Projector {
        backend,
        bvh,
        max_angle_degrees: options.max_angle_degrees,
    };
    let (positions, report) =
        fine::fine(backend, &projector, &surface, &surface.rest, &options.fine)?;
    Ok((
        positions
            .iter()
            .map(|&p| surface.units.to_world(p))
            .collect(),
        report,
    ))
}

/// What a registration aligns a mesh onto.
#[derive(Debug, Clone, Copy)]
pub enum Target<'a> {
    /// A mesh: its tree, and on it the rigid pre-alignment, are built while the graph is.
    Mesh(&'a IndexedMesh),
    /// A tree already built over the target (the tracker builds one per frame for its other
    /// stages too); the report's `bvh_time` is then zero.
    Tree(&'a Bvh),
}

/// Deforms `mesh` onto `target`: coarse graph registration, then fine alignment. Projection and the
/// fine stage's solve run on `backend`; everything else on the CPU. Vertex ids and connectivity are untouched; only positions
/// change.
///
/// A stage that does not converge is reported in the returned [`RegistrationReport`]
/// (`converged()`), never silently; errors are reserved for input that cannot be registered and for
/// a factorization that fails at every damping.
pub fn register(
    backend: &Backend,
    mesh: &mut Mesh,
    target: Target,
    options: &RegisterOptions,
) -> Result<RegistrationReport, RegisterError> {
    let total = Instant::now();
    let source = mesh.to_indexed();
    let t = Instant::now();
    let mut report = match target {
        Target::Tree(bvh) => {
            check_scale(bvh)?;
            let coarse = CoarseSolver::new(backend, bvh, &source, options)?;
            finish(backend, mesh, bvh, coarse, t.elapsed(), options)?
        }
        Target::Mesh(target) => {
            let (setup, beside) = Setup::build(&source, options, |surface, samples| {
                let t = Instant::now();
                let bvh = Bvh::build(target).map_err(|e| match e {
                    ProjectError::Target(source) => RegisterError::Mesh {
                        which: "target",
                        source,
                    },
                    other => RegisterError::Correspondence(other),
                })?;
                let bvh_time = t.elapsed();
                check_scale(&bvh)?;
                let projector = Projector {
                    backend,
                    bvh: &bvh,
                    max_angle_degrees: options.max_angle_degrees,
                };
                let rigid = rigid_start(&projector, surface, samples, &options.coarse)?;
                Ok::<_, RegisterError>((bvh, bvh_time, rigid))
            })?;
            let (bvh, bvh_time, rigid) = beside?;
            let projector = Projector {
                backend,
                bvh: &bvh,
                max_angle_degrees: options.max_angle_degrees,
            };
            let coarse =
                CoarseSolver::from_setup(Box::new(projector), setup, rigid, &options.coarse)?;
            let mut report = finish(backend, mesh, &bvh, coarse, t.elapsed(), options)?;
            report.bvh_time = bvh_time;
            report
        }
    };
    report.total_time = total.elapsed();
    Ok(report)
}

fn check_scale(bvh: &Bvh) -> Result<(), RegisterError> {
    if bvh.mean_edge_length().is_finite() && bvh.mean_edge_length() > 0.0 {
        Ok(())
    } else {
        Err(RegisterError::NoScale { which: "target" })
    }
}

/// The coarse stage's schedule, then the fine stage, written back to `mesh`; `setup_time` is what
/// setting up `coarse` took.
fn finish(
    backend: &Backend,
    mesh: &mut Mesh,
    bvh: &Bvh,
    mut coarse: CoarseSolver,
    setup_time: Duration,
    options: &RegisterOptions,
) -> Result<RegistrationReport, RegisterError> {
    let t = Instant::now();
    let coarse_report = coarse.run()?;
    let coarse_time = t.elapsed();
    let t = Instant::now();
    let projector = Projector {
        backend,
        bvh,
        max_angle_degrees: options.max_angle_degrees,
    };
    let surface = coarse.surface();
    let (fine, fine_report) = fine::fine(
        backend,
        &projector,
        surface,
        &coarse.solver_positions(),
        &options.fine,
    )?;
    let fine_time = t.elapsed();
    // The solver's vertices are the mesh's live ones in slot order (`to_indexed`'s order).
    let slots: Vec<VertexId> = mesh.vertices().collect();
    for (&slot, &p) in slots.iter().zip(&fine) {
        mesh.set_position(slot, surface.units.to_world(p));
    }
    Ok(RegistrationReport {
        vertices: slots.len(),
        coarse: coarse_report,
        fine: fine_report,
        bvh_time: Duration::ZERO,
        setup_time,
        coarse_time,
        fine_time,
        total_time: Duration::ZERO,
    })
}
