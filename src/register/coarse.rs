//! The coarse stage (paper §4.2, thesis §3.3.3): Gauss-Newton over the deformation graph's affine
//! node transformations, with `α_reg` relaxed tenfold whenever the energy stops falling.
//!
//! Each iteration forms `Jᵀr`, solves `(JᵀJ + λ I) δ = −Jᵀr` with faer's sparse Cholesky
//! factorization (the symbolic analysis is done once per graph; see [`LinearSolver`] for the two
//! ways the factor is used), and accepts the step only if it lowers `E_tot`. A non-positive pivot,
//! or a rise, adds Levenberg-Marquardt damping and tries again. Correspondences are re-projected
//! from the deformed surface after every step (non-rigid ICP, Li et al. 2009). Within a stage a
//! vertex's correspondence is replaced only when the new one fits the vertex better, so the
//! stage's energy can only fall (every term is then no larger than before); each new stage starts
//! from a complete fresh projection.

use std::time::Instant;

use faer::Par;
use faer::linalg::cholesky::llt::factor::LltError;
use glam::DVec3;

use super::RegisterError;
use super::assemble::{assemble, damp};
use super::cholesky::Cholesky;
use super::correspond::{Correspond, targets};
use super::energy::{CoarseWeights, FitTarget, energy, fit_energy, fit_pulls, gradient};
use super::geodesic::sample;
use super::graph::DeformationGraph;
use super::model::Model;
use super::operator::GaussNewton;
use super::options::{CoarseOptions, LinearSolver};
use super::pattern::{Coupling, Pattern};
use super::pcg::pcg;
use super::report::{CoarseReport, IterationReport, StageReport, StepTimes};
use super::surface::Surface;

/// Retries with raised damping before an iteration gives up.
const MAX_RETRIES: usize = 12;

/// Damping relative to the mean diagonal of `JᵀJ` on the first retry; each further retry ×10.
const FIRST_DAMPING: f64 = 1e-6;

/// A rise this small relative to the energy is rounding: the stage has converged.
const ROUNDING: f64 = 1e-12;

/// The vertices carrying `E_fit`: a geodesic Poisson-disk sample `spacing` mean edge lengths
/// apart, or every vertex for a spacing of 0.
fn fit_samples(surface: &Surface, spacing: f32) -> Vec<u32> {
    if spacing > 0.0 {
        let rest: Vec<glam::Vec3> = surface.rest.iter().map(|p| p.as_vec3()).collect();
        let mut samples = sample(&surface.adjacency, &rest, spacing);
        samples.sort_unstable();
        samples
    } else {
        (0..surface.rest.len() as u32).collect()
    }
}

/// Registers `surface` onto the target seen through `correspond`; returns the deformed vertex
/// positions (solver coordinates) and what happened.
pub fn coarse(
    correspond: &dyn Correspond,
    surface: &Surface,
    graph: &DeformationGraph,
    options: &CoarseOptions,
    par: Par,
) -> Result<(Vec<DVec3>, CoarseReport), RegisterError> {
    let setup_start = Instant::now();
    let samples = fit_samples(surface, options.sample_spacing);
    let all: Vec<u32> = (0..surface.rest.len() as u32).collect();
    let model = Model::new(graph, &surface.rest, &samples, &surface.units);
    let whole = Model::new(graph, &surface.rest, &all, &surface.units);
    let (coupling, refactor_after) = match options.solver {
        LinearSolver::Cholesky => (Coupling::Full, 0),
        LinearSolver::PreconditionedCg { refactor_after } => (Coupling::Graph, refactor_after),
    };
    let pattern = Pattern::new(&model, coupling)?;
    let cholesky = Cholesky::analyze(&pattern, par)?;
    let mut report = CoarseReport {
        nodes: model.node_count(),
        samples: samples.len(),
        graph_edges: model.edges.len(),
        unknowns: model.unknowns(),
        matrix_nonzeros: pattern.row_idx.len(),
        factor_nonzeros: cholesky.factor_nonzeros(),
        setup: setup_start.elapsed(),
        converged: true,
        ..CoarseReport::default()
    };
    let mut solver = Solver {
        model: &model,
        pattern: &pattern,
        cholesky,
        values: vec![0.0; pattern.row_idx.len()],
        damped: Vec::new(),
        lambda: 0.0,
        stale: true,
        refactor_after,
        options,
    };
    let project = |x: &[f64]| -> Result<Vec<Option<FitTarget>>, RegisterError> {
        let everywhere = whole.deform(x);
        let normals = surface.faces.normals_of(&everywhere, &samples);
        let points: Vec<DVec3> = samples.iter().map(|&v| everywhere[v as usize]).collect();
        targets(
            correspond,
            &surface.units,
            &points,
            &normals,
            options.max_distance,
        )
    };
    let mut x = model.identity();
    let mut deformed = model.deform(&x);
    let start = Instant::now();
    let mut fresh = project(&x)?;
    let mut pending_correspondence = start.elapsed();
    let mut alpha_reg = options.alpha_reg_start;
    loop {
        let w = CoarseWeights {
            fit: options.alpha_fit,
            plane: options.plane_weight,
            point: options.point_weight,
            reg: alpha_reg,
            smooth: options.smooth_weight,
        };
        let mut current = fresh.clone();
        let mut e = energy(&model, &x, &deformed, &current, &w).total(&w);
        let mut stage = StageReport {
            alpha_reg,
            energy_start: e,
            iterations: Vec::new(),
            converged: false,
        };
        solver.stale = true;
        while stage.iterations.len() < options.max_stage_iterations {
            let mut times = StepTimes {
                correspondence: std::mem::take(&mut pending_correspondence),
                ..StepTimes::default()
            };
            let mut counts = Counts::default();
            let step = match solver.step(&x, &deformed, &current, &w, e, &mut times, &mut counts)? {
                Outcome::Step(step) => step,
                Outcome::Converged => {
                    stage.converged = true;
                    break;
                }
                Outcome::Stuck => break,
            };
            x = step.x;
            deformed = step.deformed;
            let t = Instant::now();
            fresh = project(&x)?;
            let replaced = keep_better(&mut current, &fresh, &deformed, &w);
            times.correspondence += t.elapsed();
            let t = Instant::now();
            let terms = energy(&model, &x, &deformed, &current, &w);
            times.evaluation += t.elapsed();
            let after = terms.total(&w);
            let kept = current.iter().filter(|c| c.is_some()).count();
            stage.iterations.push(IterationReport {
                energy_before: e,
                energy: after,
                fit: terms.fit,
                rigid: terms.rigid,
                smooth: terms.smooth,
                kept,
                pruned: current.len() - kept,
                replaced,
                damping: step.damping,
                retries: counts.retries,
                factorizations: counts.factorizations,
                cg_iterations: counts.cg_iterations,
                times,
            });
            report.times += times;
            let relative = if e > 0.0 { (e - after) / e } else { 0.0 };
            e = after;
            if relative < options.relax_threshold {
                stage.converged = true;
                break;
            }
        }
        report.converged &= stage.converged;
        report.stages.push(stage);
        if alpha_reg <= options.alpha_reg_floor * (1.0 + 1e-9) {
            break;
        }
        alpha_reg = (alpha_reg / 10.0).max(options.alpha_reg_floor);
    }
    Ok((whole.deform(&x), report))
}

/// Replaces each vertex's correspondence by its fresh one where that fits the vertex's current
/// position at least as well; a vertex without a correspondence gets none (that would add a term).
/// Returns how many were replaced.
fn keep_better(
    current: &mut [Option<FitTarget>],
    fresh: &[Option<FitTarget>],
    deformed: &[DVec3],
    w: &CoarseWeights,
) -> usize {
    let mut replaced = 0;
    for ((slot, new), &p) in current.iter_mut().zip(fresh).zip(deformed) {
        if let (Some(old), Some(new)) = (slot.as_ref(), new) {
            if old != new && fit_energy(new, p, w) <= fit_energy(old, p, w) {
                *slot = Some(*new);
                replaced += 1;
            }
        }
    }
    replaced
}

/// What one attempted iteration produced.
enum Outcome {
    Step(Step),
    /// No step lowers the energy by more than rounding: the stage has converged.
    Converged,
    /// Every damping tried raised the energy: the stage cannot make progress (reported, since the
    /// stage then ends unconverged).
    Stuck,
}

/// An accepted step.
struct Step {
    x: Vec<f64>,
    deformed: Vec<DVec3>,
    damping: f64,
}

#[derive(Default)]
struct Counts {
    retries: usize,
    factorizations: usize,
    cg_iterations: usize,
}

/// The Gauss-Newton machinery of one registration: pattern, factorization and damping state.
struct Solver<'a> {
    model: &'a Model,
    pattern: &'a Pattern,
    cholesky: Cholesky,
    values: Vec<f64>,
    damped: Vec<f64>,
    lambda: f64,
    /// The factor no longer matches the weights (new stage) or has become a poor preconditioner.
    stale: bool,
    refactor_after: usize,
    options: &'a CoarseOptions,
}

impl Solver<'_> {
    /// One damped Gauss-Newton step from `x` (energy `e`).
    #[allow(clippy::too_many_arguments)]
    fn step(
        &mut self,
        x: &[f64],
        deformed: &[DVec3],
        current: &[Option<FitTarget>],
        w: &CoarseWeights,
        e: f64,
        times: &mut StepTimes,
        counts: &mut Counts,
    ) -> Result<Outcome, RegisterError> {
        let t = Instant::now();
        let fit: Vec<[[f64; 3]; 3]> = current
            .iter()
            .map(|c| c.map_or([[0.0; 3]; 3], |c| w.fit_matrix(c.normal)))
            .collect();
        let pulls = fit_pulls(deformed, current, w);
        let rhs: Vec<f64> = gradient(self.model, x, &pulls, w)
            .iter()
            .map(|g| -g)
            .collect();
        times.assembly += t.elapsed();
        let mut scale = 1.0;
        loop {
            if self.stale || self.refactor_after == 0 {
                let t = Instant::now();
                assemble(self.pattern, self.model, x, &fit, w, &mut self.values);
                times.assembly += t.elapsed();
                scale = self.mean_diagonal();
                let t = Instant::now();
                damp(self.pattern, &self.values, self.lambda, &mut self.damped);
                let factored = self.cholesky.factor(self.pattern, &self.damped);
                times.factorization += t.elapsed();
                counts.factorizations += 1;
                if let Err(LltError::NonPositivePivot { .. }) = factored {
                    if !self.raise(scale, &mut counts.retries) {
                        return Err(RegisterError::Factorization(format!(
                            "no positive definite system after {MAX_RETRIES} damping increases"
                        )));
                    }
                    self.stale = true;
                    continue;
                }
                self.stale = false;
            }
            let t = Instant::now();
            let operator = GaussNewton {
                model: self.model,
                x,
                fit: &fit,
                weights: *w,
                damping: self.lambda,
            };
            let mut delta = rhs.clone();
            self.cholesky.solve(&mut delta)?;
            let cholesky = &mut self.cholesky;
            let solve = pcg(
                |v, out| operator.apply(v, out),
                |r, z| {
                    z.copy_from_slice(r);
                    // The factor is valid here, so the solve cannot fail.
                    let _ = cholesky.solve(z);
                },
                &rhs,
                &mut delta,
                self.options.cg_tolerance,
                self.options.max_cg_iterations,
            );
            counts.cg_iterations += solve.iterations;
            if solve.iterations > self.refactor_after {
                self.stale = true;
            }
            times.solve += t.elapsed();
            let t = Instant::now();
            let trial: Vec<f64> = x.iter().zip(&delta).map(|(a, d)| a + d).collect();
            let trial_deformed = self.model.deform(&trial);
            let trial_e = energy(self.model, &trial, &trial_deformed, current, w).total(w);
            times.evaluation += t.elapsed();
            if trial_e.is_finite() && trial_e <= e {
                let damping = self.lambda;
                self.lambda = if self.lambda > scale * FIRST_DAMPING {
                    self.lambda / 10.0
                } else {
                    0.0
                };
                return Ok(Outcome::Step(Step {
                    x: trial,
                    deformed: trial_deformed,
                    damping,
                }));
            }
            if trial_e.is_finite() && trial_e - e <= ROUNDING * e {
                return Ok(Outcome::Converged);
            }
            if !self.raise(scale, &mut counts.retries) {
                return Ok(Outcome::Stuck);
            }
        }
    }

    /// Mean of the diagonal of the last assembled matrix: the scale damping is measured against.
    fn mean_diagonal(&self) -> f64 {
        let n = self.pattern.dimension();
        let mean = (0..n)
            .map(|c| self.values[self.pattern.col_ptr[c + 1] as usize - 1])
            .sum::<f64>()
            / n.max(1) as f64;
        if mean > 0.0 { mean } else { 1.0 }
    }

    /// Raises the damping for another try; false when the retries are spent.
    fn raise(&mut self, scale: f64, retries: &mut usize) -> bool {
        *retries += 1;
        if *retries > MAX_RETRIES {
            return false;
        }
        self.lambda = if self.lambda > 0.0 {
            self.lambda * 10.0
        } else {
            scale * FIRST_DAMPING
        };
        true
    }
}

#[cfg(test)]
mod probe {
    use super::*;
    use crate::compute::Backend;
    use crate::grid::{ScalarGrid, marching_cubes};
    use crate::project::Bvh;
    use crate::register::correspond::Projector;
    use glam::Vec3;

    fn bar(p: Vec3) -> f32 {
        let mut sum = 0.0;
        for k in 0..7 {
            let x = -0.6 + 0.2 * k as f32;
            sum += (-(p - Vec3::new(x, 0.0, 0.0)).length_squared() / 0.04).exp();
            let side = if k % 2 == 0 { 0.12 } else { -0.12 };
            sum += 0.6 * (-(p - Vec3::new(x + 0.1, side, 0.05)).length_squared() / 0.015).exp();
        }
        0.5 - sum
    }

    #[test]
    #[ignore]
    fn probe_truth_energy() {
        let kappa = 0.4f32;
        let forward = move |p: Vec3| {
            let theta = kappa * p.x;
            let (s, c) = theta.sin_cos();
            Vec3::new(s / kappa - p.y * s, (1.0 - c) / kappa + p.y * c, p.z)
        };
        let spacing = 0.02;
        let origin = Vec3::new(-0.95, -0.45, -0.4);
        let grid = ScalarGrid::from_fn(origin, spacing, [96, 46, 42], bar).unwrap();
        let source = marching_cubes(&grid, 0.0);
        let mut target = source.clone();
        for p in &mut target.positions {
            *p = forward(*p);
        }
        let unit = source.mean_edge_length();
        let surface = Surface::new(&source.positions, &source.triangles, unit);
        let graph = DeformationGraph::from_adjacency(&source.positions, &surface.adjacency, 4.0 * unit, 4);
        let all: Vec<u32> = (0..source.positions.len() as u32).collect();
        let model = Model::new(&graph, &surface.rest, &all, &surface.units);
        // node transforms of the truth: A = dB (finite differences), b = B(g) - g, in local units
        let units = surface.units;
        let mut x = model.identity();
        for (i, &g) in model.nodes.iter().enumerate() {
            let gw = units.to_world(g);
            let h = 1e-3f32;
            for c in 0..3 {
                let mut e = Vec3::ZERO;
                e[c] = h;
                let col = (forward(gw + e) - forward(gw - e)) / (2.0 * h);
                for k in 0..3 {
                    x[12 * i + 3 * c + k] = f64::from(col[k]);
                }
            }
            let b = units.to_local(forward(gw)) - g;
            x[12 * i + 9] = b.x;
            x[12 * i + 10] = b.y;
            x[12 * i + 11] = b.z;
        }
        let bvh = Bvh::build(&target).unwrap();
        let backend = Backend::Cpu;
        let projector = Projector { backend: &backend, bvh: &bvh, max_angle_degrees: 60.0 };
        let deformed = model.deform(&x);
        let truth: Vec<DVec3> = source.positions.iter().map(|&p| units.to_local(forward(p))).collect();
        let err: f64 = deformed.iter().zip(&truth).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max);
        let normals = surface.faces.normals(&deformed);
        let found = targets(&projector, &units, &deformed, &normals, f64::INFINITY).unwrap();
        for reg in [1000.0, 100.0, 10.0, 1.0, 0.1] {
            let w = CoarseWeights { fit: 0.1, plane: 1.0, point: 0.1, reg, smooth: 0.1 };
            let t = energy(&model, &x, &deformed, &found, &w);
            println!("truth: skinning max error {err:.3} e; α_reg {reg}: fit {:.4e} rigid {:.4e} smooth {:.4e} total {:.4e}", t.fit, t.rigid, t.smooth, t.total(&w));
        }
    }
}
