//! The fine stage (paper §4.2): per-vertex displacements `d` that bring the detail the coarse graph
//! cannot express onto the target,
//!
//! `E = Σ_v α_plane (n_v·(p_v + d_v − c_v))² + α_point |p_v + d_v − c_v|²
//!    + α_disp Σ_(i,j) |d_i − d_j|² + α_edge Σ_(i,j) (ê_ij·(d_i − d_j))²`,
//!
//! over the mesh edges `(i, j)`, with `ê_ij` the unit edge direction before the stage (so the last
//! term is the linearized change of edge length) and correspondences farther than σ pruned.
//!
//! The paper's correspondences run from the source to the target only, so a target feature no
//! source normal ray reaches — a dimple deepening faster than the mesh follows, a thin spike —
//! pulls on nothing, and the mesh lags behind it frame after frame (paper §4.2: "we do not
//! guarantee that every target surface region will have a corresponding source point"). A cover
//! term closes that gap: every target sample (triangle centroid) farther than `cover_min_distance`
//! from the source as the stage starts but within σ, whose normal agrees within the pruning angle,
//! pulls the source's nearest point, a barycentric blend of three vertices, along the target's
//! normal only (`E_plane`'s weight): a point term would also drag the surface sideways towards
//! wherever the samples sit, which is drift; and samples the source already lies close to are left
//! to `E_fit`, since there the term can only add the target's triangulation noise, which also
//! accumulates as drift. It is scaled by `cover_weight` × source vertices / target samples so that
//! both directions weigh alike at any resolution, and each pair by `(gap / cover_min_distance)^
//! cover_growth`: a sample a cell from the source is a feature it lacks, one just past the minimum
//! distance mostly noise (`register::cover`). With a flat weight of 3 (samples from 0.25 L) the
//! `morph` scene's narrowing dimple is followed within 0.69 Δ where the one-sided fit lags
//! 1.39 Δ behind, and the `rigid` scene's drift after 32 frames moves from 0.045% to 0.085% of its
//! diagonal (`surftrack synth`, `track`, `eval` at their defaults).
//!
//! `E` is quadratic; its minimizer solves `A d = b`, found by conjugate gradients preconditioned
//! with `A`'s 3×3 diagonal blocks, warm-started from the previous round's displacements
//! (`register::fine_solve`, as kernels on the GPU backend).

use std::time::Instant;

use glam::DVec3;

use super::RegisterError;
use super::correspond::{Correspond, targets};
use super::cover::Cover;
use super::energy::FitTarget;
use super::fine_solve::{FineSolver, FineSystem};
use super::model::ordered_sum;
use super::options::FineOptions;
use super::report::{FineReport, FineRound};
use super::surface::Surface;
use crate::compute::Backend;
use crate::kernels::shared::FineTarget;
use crate::mesh::IndexedMesh;

/// Moves `start` (solver coordinates) onto the target; returns the new positions. The solves run
/// on `backend`.
pub fn fine(
    backend: &Backend,
    correspond: &dyn Correspond,
    surface: &Surface,
    start: &[DVec3],
    options: &FineOptions,
) -> Result<(Vec<DVec3>, FineReport), RegisterError> {
    let mut d = vec![DVec3::ZERO; start.len()];
    let mut report = FineReport {
        rounds: Vec::new(),
        converged: true,
    };
    // The cover pairs are found once, at the start: a pair is a source triangle with barycentric
    // weights and a target point, so its residual follows the displacements of every round;
    // finding them again would cost a tree over the source and a query per target sample.
    let t = Instant::now();
    let cover = if options.cover_weight > 0.0 {
        let world = IndexedMesh::new(
            start.iter().map(|&p| surface.units.to_world(p)).collect(),
            surface.faces.triangles().to_vec(),
        );
        let pairs = correspond.cover(
            &world,
            options.cover_min_distance as f32,
            options.sigma as f32,
        )?;
        Cover::new(&pairs, surface, start, options)?
    } else {
        Cover::default()
    };
    let mut cover_time = t.elapsed();
    let system = FineSystem::new(&surface.adjacency, start, cover, options)?;
    let mut solver = FineSolver::new(backend, &system, &d)?;
    for _ in 0..options.rounds {
        let t = Instant::now();
        let positions: Vec<DVec3> = start.iter().zip(&d).map(|(p, d)| *p + *d).collect();
        let normals = surface.faces.normals(&positions);
        let found = targets(
            correspond,
            &surface.units,
            &positions,
            &normals,
            options.sigma,
        )?;
        let correspondence = t.elapsed() + std::mem::take(&mut cover_time);
        let t = Instant::now();
        let fine_targets: Vec<FineTarget> = found
            .iter()
            .map(|c| {
                c.map_or(FineTarget::default(), |c| {
                    FineTarget::new(c.point.to_array(), c.normal.to_array())
                })
            })
            .collect();
        let energy_before = energy(&system, &d, &found) + system.cover.energy(&d);
        let solve = solver.solve(&system, &fine_targets, &mut d, options)?;
        let energy = energy(&system, &d, &found) + system.cover.energy(&d);
        let kept = found.iter().filter(|c| c.is_some()).count();
        report.converged &= solve.converged;
        report.rounds.push(FineRound {
            kept,
            pruned: found.len() - kept,
            cover: system.cover.len(),
            energy_before,
            energy,
            cg_iterations: solve.iterations,
            residual: solve.residual,
            converged: solve.converged,
            correspondence,
            solve: t.elapsed(),
        });
    }
    let positions = start.iter().zip(&d).map(|(p, d)| *p + *d).collect();
    Ok((positions, report))
}

/// The energy `E(d)` without the cover term, with correspondences `found`.
fn energy(system: &FineSystem, d: &[DVec3], found: &[Option<FitTarget>]) -> f64 {
    let o = &system.params;
    ordered_sum(d.len(), |v| {
        let p = system.start[v] + d[v];
        let fit = found[v].map_or(0.0, |c| {
            let r = p - c.point;
            o.plane_weight * c.normal.dot(r).powi(2) + o.point_weight * r.length_squared()
        });
        let reg: f64 = system
            .neighbours(v)
            .iter()
            .zip(system.directions(v))
            .filter(|&(&u, _)| u as usize > v)
            .map(|(&u, &e)| {
                let diff = d[v] - d[u as usize];
                o.disp_weight * diff.length_squared() + o.edge_weight * e.dot(diff).powi(2)
            })
            .sum();
        fit + reg
    })
}
