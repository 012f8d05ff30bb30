//! The coarse stage (paper §4.2, thesis §3.3.3): Gauss-Newton over the deformation graph's affine
//! node transformations, with `α_reg` relaxed tenfold whenever the energy stops falling.
//!
//! Each iteration forms `Jᵀr`, solves `(JᵀJ + λ I) δ = −Jᵀr` with faer's sparse Cholesky
//! factorization (the symbolic analysis is done once per graph; see [`LinearSolver`] for the two
//! ways the factor is used), and accepts the step only if it lowers `E_tot`. A non-positive pivot,
//! or a rise, adds Levenberg-Marquardt damping and tries again; the damping follows the energy's
//! actual against its predicted fall (`damping`: Nielsen's update), so it settles where the steps
//! fit instead of swinging tenfold each iteration, and a retry solves from the factor it has.
//! Correspondences are re-projected from the deformed surface after every step (non-rigid ICP, Li
//! et al. 2009). Within a stage a vertex's correspondence is replaced only when the new one fits
//! the vertex better, so the stage's energy can only fall (every term is then no larger than
//! before); each new stage starts from a complete fresh projection. While a stage iterates, the
//! matrices of the next two stages are factored on threads of their own, and precondition those
//! stages.

use std::sync::Arc;
use std::thread::{Scope, ScopedJoinHandle};
use std::time::{Duration, Instant};

use faer::Par;
use faer::linalg::cholesky::llt::factor::LltError;
use glam::{DVec3, Vec3};

use super::assemble::{assemble, damp, damp_in_place};
use super::cholesky::Cholesky;
use super::correspond::{Correspond, Projector, targets};
use super::damping::{Damping, gain_ratio};
use super::energy::{CoarseWeights, FitTarget, energy, fit_energy, fit_pulls, gradient};
use super::geodesic::sample;
use super::graph::{DeformationGraph, check_indices, surface_area};
use super::model::{Model, ordered_sum};
use super::operator::GaussNewton;
use super::options::{CoarseOptions, LinearSolver, RegisterOptions};
use super::pattern::{Coupling, Pattern};
use super::pcg::{Solve, pcg};
use super::report::{CoarseReport, IterationReport, StageReport, StepTimes};
use super::rigid::{Rigid, node_unknowns, prealign};
use super::small_blocks::SmallBlocks;
use super::surface::Surface;
use super::{FactorizationError, RegisterError};
use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::project::Bvh;

/// Retries with raised damping before an iteration gives up.
const MAX_RETRIES: usize = 12;

/// A rise this small relative to the energy is rounding: the stage has converged.
const ROUNDING: f64 = 1e-12;

/// The vertices carrying `E_fit`: a geodesic Poisson-disk sample `spacing` mean edge lengths
/// apart, or every vertex for a spacing of 0.
fn fit_samples(surface: &Surface, spacing: f32) -> Vec<u32> {
    if spacing > 0.0 {
        let rest: Vec<Vec3> = surface.rest.iter().map(|p| p.as_vec3()).collect();
        let mut samples = sample(&surface.adjacency, &rest, spacing);
        samples.sort_unstable();
        samples
    } else {
        (0..surface.rest.len() as u32).collect()
    }
}

/// The coarse stage of one registration, usable step by step: [`CoarseSolver::run`] is the whole
/// schedule; [`project`](CoarseSolver::project), [`assemble`](CoarseSolver::assemble),
/// [`factor`](CoarseSolver::factor) and [`solve`](CoarseSolver::solve) are its sub-steps, each of
/// which can be repeated at the current state (benchmarks time them one by one).
pub struct CoarseSolver<'a> {
    correspond: Box<dyn Correspond + Send + 'a>,
    surface: Surface,
    options: CoarseOptions,
    samples: Vec<u32>,
    /// Graph over the samples (the energy) and over every vertex (the output).
    model: Model,
    whole: Model,
    pattern: Arc<Pattern>,
    cholesky: Cholesky,
    /// A spray's droplets, factored exactly at every solve (none when the factor is of `JᵀJ`
    /// itself and refreshed every iteration, or when droplets are a small part of the graph).
    small: SmallBlocks,
    /// Factorization buffers not in use, for the factors of later stages.
    spare: Vec<Cholesky>,
    refactor_after: usize,
    /// Where [`CoarseSolver::run`] starts every node from.
    rigid: Option<RigidStart>,
    weights: CoarseWeights,
    x: Vec<f64>,
    deformed: Vec<DVec3>,
    current: Vec<Option<FitTarget>>,
    fit: Vec<[[f64; 3]; 3]>,
    rhs: Vec<f64>,
    delta: Vec<f64>,
    values: Vec<f64>,
    damped: Vec<f64>,
    damping: Damping,
    scale: f64,
    /// The factor does not match the current weights (new stage) or has become a poor
    /// preconditioner.
    stale: bool,
    /// In this stage a factor kept from an earlier iteration has failed to solve within
    /// `refactor_after` iterations: every later iteration of the stage refactors first.
    eager: bool,
    factorizations: usize,
    retries: usize,
    report: CoarseReport,
}

impl<'a> CoarseSolver<'a> {
    /// Sets up the coarse stage of `source` against the target behind `bvh`, projecting on
    /// `backend`: deformation graph, rigid pre-alignment, sparsity pattern and symbolic
    /// factorization.
    pub fn new(
        backend: &'a Backend,
        bvh: &'a Bvh,
        source: &IndexedMesh,
        options: &RegisterOptions,
    ) -> Result<Self, RegisterError> {
        let projector = Projector {
            backend,
            bvh,
            max_angle_degrees: options.max_angle_degrees,
        };
        let (setup, rigid) = Setup::build(source, options, |surface, samples| {
            rigid_start(&projector, surface, samples, &options.coarse)
        })?;
        Self::from_setup(Box::new(projector), setup, rigid?, &options.coarse)
    }

    /// The coarse stage of `setup` starting from `rigid`, against any correspondence source.
    pub(crate) fn from_setup(
        correspond: Box<dyn Correspond + Send + 'a>,
        setup: Setup,
        rigid: Option<RigidStart>,
        options: &CoarseOptions,
    ) -> Result<Self, RegisterError> {
        let Setup {
            surface,
            graph,
            samples,
            analysis,
        } = setup;
        let started = Instant::now();
        let all: Vec<u32> = (0..surface.rest.len() as u32).collect();
        let model = Model::new(&graph, &surface.rest, &samples, &surface.units);
        let whole = Model::new(&graph, &surface.rest, &all, &surface.units);
        let (coupling, refactor_after) = match options.solver {
            LinearSolver::Cholesky => (Coupling::Full, 0),
            LinearSolver::PreconditionedCg { refactor_after } => (Coupling::Graph, refactor_after),
        };
        let pattern = Pattern::new(&model, coupling)?;
        let small = match coupling {
            Coupling::Graph => SmallBlocks::new(&pattern),
            Coupling::Full => SmallBlocks::none(),
        };
        // Sequential: faer's parallel supernodal factorization meets at spinning barriers, which on
        // two cores shared with other work cost more than the second core gains (measured on the
        // `register` bench frames: 16k vertices 110 ms vs 200 ms for five factorizations, 100k 1.5 s
        // vs 2.2 s); the assembly and projections around it stay parallel.
        let cholesky = match analysis {
            Some(analysis) if analysis.fits(&pattern) => analysis.cholesky,
            _ => Cholesky::analyze(&pattern, Par::Seq)?,
        };
        let report = CoarseReport {
            nodes: model.node_count(),
            samples: samples.len(),
            graph_edges: model.edges.len(),
            unknowns: model.unknowns(),
            matrix_nonzeros: pattern.row_idx.len(),
            factor_nonzeros: cholesky.factor_nonzeros(),
            setup: started.elapsed(),
            converged: true,
            ..CoarseReport::default()
        };
        let x = model.identity();
        let deformed = model.deform(&x);
        let n = model.unknowns();
        Ok(Self {
            correspond,
            weights: CoarseWeights {
                fit: options.alpha_fit,
                plane: options.plane_weight,
                point: options.point_weight,
                reg: options.alpha_reg_start,
                smooth: options.smooth_weight,
            },
            options: *options,
            current: vec![None; samples.len()],
            fit: Vec::new(),
            samples,
            values: vec![0.0; pattern.row_idx.len()],
            damped: Vec::new(),
            rhs: vec![0.0; n],
            delta: vec![0.0; n],
            model,
            whole,
            pattern: Arc::new(pattern),
            cholesky,
            small,
            spare: Vec::new(),
            refactor_after,
            rigid,
            x,
            deformed,
            damping: Damping::none(),
            scale: 1.0,
            stale: true,
            eager: false,
            factorizations: 0,
            retries: 0,
            surface,
            report,
        })
    }

    pub fn node_count(&self) -> usize {
        self.model.node_count()
    }

    pub fn unknowns(&self) -> usize {
        self.model.unknowns()
    }

    pub(crate) fn surface(&self) -> &Surface {
        &self.surface
    }

    /// Every vertex at the current state, in solver coordinates.
    pub(crate) fn solver_positions(&self) -> Vec<DVec3> {
        self.whole.deform(&self.x)
    }

    /// Every vertex at the current state.
    pub fn positions(&self) -> Vec<Vec3> {
        self.solver_positions()
            .iter()
            .map(|&p| self.surface.units.to_world(p))
            .collect()
    }

    /// Correspondences of the samples at the current state: vertex normals of the deformed mesh,
    /// rays cast onto the target. They replace the current ones.
    pub fn project(&mut self) -> Result<(), RegisterError> {
        self.current = self.fresh()?;
        Ok(())
    }

    fn fresh(&self) -> Result<Vec<Option<FitTarget>>, RegisterError> {
        let everywhere = self.whole.deform(&self.x);
        let normals = self.surface.faces.normals_of(&everywhere, &self.samples);
        let points: Vec<DVec3> = self
            .samples
            .iter()
            .map(|&v| everywhere[v as usize])
            .collect();
        targets(
            self.correspond.as_ref(),
            &self.surface.units,
            &points,
            &normals,
            self.options.max_distance,
        )
    }

    /// `Jᵀr` and the matrix to factor (`JᵀJ`, or its graph-pattern bound) at the current state.
    pub fn assemble(&mut self) {
        self.assemble_gradient();
        self.assemble_matrix();
    }

    /// Each sample's fit matrix for its current correspondence (zero without one).
    fn fit_matrices(&self) -> Vec<[[f64; 3]; 3]> {
        let w = &self.weights;
        self.current
            .iter()
            .map(|c| c.map_or([[0.0; 3]; 3], |c| w.fit_matrix(c.normal)))
            .collect()
    }

    fn assemble_gradient(&mut self) {
        self.fit = self.fit_matrices();
        let w = &self.weights;
        let pulls = fit_pulls(&self.deformed, &self.current, w);
        let g = gradient(&self.model, &self.x, &pulls, w);
        self.rhs.iter_mut().zip(&g).for_each(|(r, g)| *r = -g);
    }

    fn assemble_matrix(&mut self) {
        let w = self.weights;
        assemble(
            &self.pattern,
            &self.model,
            &self.x,
            &self.fit,
            &w,
            &mut self.values,
        );
        self.scale = mean_diagonal(&self.pattern, &self.values);
    }

    /// Numeric factorization of the assembled matrix plus the current damping; a non-positive
    /// pivot raises the damping and refactors.
    pub fn factor(&mut self) -> Result<(), RegisterError> {
        loop {
            damp(
                &self.pattern,
                &self.values,
                self.damping.lambda(),
                &mut self.damped,
            );
            self.factorizations += 1;
            match self.cholesky.factor(&self.pattern, &self.damped) {
                Ok(()) => {
                    self.stale = false;
                    return Ok(());
                }
                Err(LltError::NonPositivePivot { index }) => {
                    let lambda = self.damping.lambda();
                    if !self.raise() {
                        return Err(FactorizationError::NotPositiveDefinite {
                            retries: MAX_RETRIES,
                            pivot: index,
                            lambda,
                        }
                        .into());
                    }
                }
            }
        }
    }

    /// The step `δ` of `(JᵀJ + λ I) δ = −Jᵀr` at the current state; returns the conjugate-gradient
    /// iterations it took (about one when the factor is of `JᵀJ` itself: it is a single-precision
    /// factor, see `cholesky`).
    pub fn solve(&mut self) -> Result<usize, RegisterError> {
        let solve = self.solve_within(self.options.max_cg_iterations)?;
        Ok(solve.iterations)
    }

    /// [`CoarseSolver::solve`] stopped after `most` conjugate-gradient iterations.
    fn solve_within(&mut self, most: usize) -> Result<Solve, RegisterError> {
        let operator = GaussNewton {
            model: &self.model,
            x: &self.x,
            fit: &self.fit,
            weights: self.weights,
            damping: self.damping.lambda(),
        };
        self.small.refresh(
            &self.pattern,
            &self.model,
            &self.x,
            &self.fit,
            &self.weights,
            self.damping.lambda(),
        );
        self.delta.copy_from_slice(&self.rhs);
        self.cholesky.solve(&mut self.delta)?;
        self.small.apply(&self.rhs, &mut self.delta);
        let (cholesky, small) = (&mut self.cholesky, &self.small);
        let mut failed = None;
        let solve = pcg(
            |v, out| operator.apply(v, out),
            |r, z| {
                z.copy_from_slice(r);
                if let Err(e) = cholesky.solve(z) {
                    failed = Some(e);
                }
                small.apply(r, z);
            },
            &self.rhs,
            &mut self.delta,
            self.options.cg_tolerance,
            most,
        );
        if let Some(e) = failed {
            return Err(e);
        }
        if solve.iterations > self.refactor_after {
            self.stale = true;
        }
        Ok(solve)
    }

    /// Raises the damping for another try; false when the retries are spent. After a rejected step
    /// the factor is kept: the damping only adds to the diagonal, so a factor of the less damped
    /// matrix still preconditions the new one, and a retry costs conjugate gradients instead of a
    /// factorization; a solve that needs more than `refactor_after` iterations marks the factor
    /// stale as usual. (A non-positive pivot refactors at the raised damping in `factor`.)
    fn raise(&mut self) -> bool {
        self.retries += 1;
        if self.retries > MAX_RETRIES {
            return false;
        }
        self.damping.raise(self.scale);
        true
    }

    /// Lowers the damping after an accepted step that lowered the energy by `actual`, by how well
    /// that matched the fall its linearization predicted.
    fn lower(&mut self, actual: f64) {
        let (rhs, delta) = (&self.rhs, &self.delta);
        let along = ordered_sum(delta.len(), |i| rhs[i] * delta[i]);
        let length = ordered_sum(delta.len(), |i| delta[i] * delta[i]);
        let gain = gain_ratio(actual, along, length, self.damping.lambda());
        self.damping.lower(gain, self.scale);
    }

    /// Factorization buffers for a factor computed on another thread: a spare, or new ones.
    fn spare_cholesky(&mut self) -> Result<Cholesky, RegisterError> {
        match self.spare.pop() {
            Some(c) => Ok(c),
            None => self.cholesky.sibling(),
        }
    }

    /// The factorization, into `cholesky`, of the matrix at the current unknowns with fit
    /// matrices `fit` and weights `weights`, damped by `lambda`: to run on another thread.
    fn factor_job(
        &self,
        cholesky: Cholesky,
        fit: &[[[f64; 3]; 3]],
        weights: &CoarseWeights,
        lambda: f64,
    ) -> NextFactor {
        let mut values = vec![0.0; self.pattern.row_idx.len()];
        assemble(
            &self.pattern,
            &self.model,
            &self.x,
            fit,
            weights,
            &mut values,
        );
        NextFactor {
            pattern: Arc::clone(&self.pattern),
            scale: mean_diagonal(&self.pattern, &values),
            lambda,
            values,
            cholesky,
        }
    }

    fn total(&self) -> f64 {
        let w = &self.weights;
        energy(&self.model, &self.x, &self.deformed, &self.current, w).total(w)
    }

    /// Every node at the rigid pre-alignment's motion.
    fn prealign(&mut self) {
        if let Some(start) = &self.rigid {
            self.x = node_unknowns(&start.pose, &self.model.nodes);
            self.deformed = self.model.deform(&self.x);
            self.report.rigid_energies = start.energies.clone();
            self.report.rigid_time = start.time;
        }
    }

    /// The whole schedule: rigid pre-alignment, then stages of Gauss-Newton iterations from
    /// `α_reg` start down to the floor.
    pub fn run(&mut self) -> Result<CoarseReport, RegisterError> {
        self.prealign();
        let t = Instant::now();
        let fresh = self.fresh()?;
        let carried = Carried {
            times: StepTimes {
                correspondence: t.elapsed(),
                ..StepTimes::default()
            },
            factorizations: 0,
        };
        std::thread::scope(|scope| self.stages(scope, fresh, carried))?;
        Ok(self.report.clone())
    }

    /// The stages of [`CoarseSolver::run`], with later stages' factors running on threads of
    /// `scope`.
    fn stages<'s>(
        &mut self,
        scope: &'s Scope<'s, '_>,
        mut fresh: Vec<Option<FitTarget>>,
        mut carried: Carried,
    ) -> Result<(), RegisterError> {
        let mut running = Vec::new();
        loop {
            self.current = fresh.clone();
            let mut e = self.total();
            let mut stage = StageReport {
                alpha_reg: self.weights.reg,
                energy_start: e,
                iterations: Vec::new(),
                converged: false,
            };
            self.take_prepared(&mut running, &mut carried);
            self.start_factor(scope, &mut running, 1, &mut carried.times)?;
            self.stage_iterations(
                scope,
                &mut running,
                &mut stage,
                &mut e,
                &mut fresh,
                &mut carried,
            )?;
            self.report.converged &= stage.converged;
            self.report.stages.push(stage);
            match self.alpha_ahead(1) {
                Some(next) => self.weights.reg = next,
                None => return Ok(()),
            }
        }
    }

    /// The iterations of one stage, from energy `e` (updated as they go), until the energy stops
    /// falling; `fresh` is the last projection, and `carried` what was done for the first
    /// iteration before it (reported with it). The factor of the stage after next starts at the
    /// second iteration: the first moves far, the later ones little, so from then on the state is
    /// nearly the one the next stage starts from.
    fn stage_iterations<'s>(
        &mut self,
        scope: &'s Scope<'s, '_>,
        running: &mut Vec<Running<'s>>,
        stage: &mut StageReport,
        e: &mut f64,
        fresh: &mut Vec<Option<FitTarget>>,
        carried: &mut Carried,
    ) -> Result<(), RegisterError> {
        while stage.iterations.len() < self.options.max_stage_iterations {
            let Carried {
                mut times,
                factorizations,
            } = std::mem::take(carried);
            if stage.iterations.len() == 1 {
                self.start_factor(scope, running, 2, &mut times)?;
            }
            self.factorizations = factorizations;
            self.retries = 0;
            let mut cg_iterations = 0;
            let outcome = self.iterate(*e, &mut times, &mut cg_iterations)?;
            let damping = match outcome {
                Outcome::Accepted { damping } => damping,
                Outcome::Converged => {
                    stage.converged = true;
                    break;
                }
                Outcome::Stuck => break,
            };
            let t = Instant::now();
            *fresh = self.fresh()?;
            let replaced = keep_better(&mut self.current, fresh, &self.deformed, &self.weights);
            times.correspondence += t.elapsed();
            let t = Instant::now();
            let terms = energy(
                &self.model,
                &self.x,
                &self.deformed,
                &self.current,
                &self.weights,
            );
            times.evaluation += t.elapsed();
            let after = terms.total(&self.weights);
            let kept = self.current.iter().filter(|c| c.is_some()).count();
            stage.iterations.push(IterationReport {
                energy_before: *e,
                energy: after,
                fit: terms.fit,
                rigid: terms.rigid,
                smooth: terms.smooth,
                kept,
                pruned: self.current.len() - kept,
                replaced,
                damping,
                retries: self.retries,
                factorizations: self.factorizations,
                cg_iterations,
                times,
            });
            self.report.times += times;
            let relative = if *e > 0.0 { (*e - after) / *e } else { 0.0 };
            *e = after;
            if relative < self.options.relax_threshold {
                stage.converged = true;
                break;
            }
        }
        Ok(())
    }

    /// The `α_reg` of the stage `ahead` stages after this one, if there is one: the schedule
    /// divides it by 10 down to the floor. The stages advance by this too, so a factor started
    /// for a later stage is found by exact equality.
    fn alpha_ahead(&self, ahead: usize) -> Option<f64> {
        let floor = self.options.alpha_reg_floor;
        let mut reg = self.weights.reg;
        for _ in 0..ahead {
            if reg <= floor * (1.0 + 1e-9) {
                return None;
            }
            reg = (reg / 10.0).max(floor);
        }
        Some(reg)
    }

    /// Starts a stage: with the factor prepared for its `α_reg` if there is one (taken at a state
    /// near this one, so it still preconditions well; a poor one is refreshed after
    /// `refactor_after` iterations), else with a fresh factorization. Waiting for that factor, and
    /// its time, go to `carried`.
    fn take_prepared(&mut self, running: &mut Vec<Running<'_>>, carried: &mut Carried) {
        self.stale = true;
        self.eager = false;
        let Some(at) = running.iter().position(|r| r.alpha_reg == self.weights.reg) else {
            return;
        };
        let (prepared, time) = match running.remove(at).handle.join() {
            Ok(done) => done,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        carried.times.factorization += time;
        carried.factorizations += 1;
        match prepared {
            Ok(prepared) => self.adopt(prepared),
            Err(cholesky) => self.spare.push(cholesky),
        }
    }

    /// Makes a factor computed on another thread the current one; the buffers it replaces become
    /// a spare.
    fn adopt(&mut self, prepared: Prepared) {
        let used = std::mem::replace(&mut self.cholesky, prepared.cholesky);
        self.spare.push(used);
        self.scale = prepared.scale;
        self.stale = false;
    }

    /// Starts factoring, on a thread of `scope`, the matrix of the stage `ahead` stages on,
    /// assembled at the current state (its time goes to `times`), unless that stage's factor is
    /// already running or there is no such stage, or every iteration factors anyway
    /// (`refactor_after` 0). The sparse factorization runs on one core (see `from_setup`), and a
    /// stage's iterations take less time than it does, so factoring later stages' matrices while
    /// this one iterates takes every factorization but the first off the critical path. On the
    /// `register` bench frames every solve still converges in one or two iterations of conjugate
    /// gradients with these factors.
    fn start_factor<'s>(
        &mut self,
        scope: &'s Scope<'s, '_>,
        running: &mut Vec<Running<'s>>,
        ahead: usize,
        times: &mut StepTimes,
    ) -> Result<(), RegisterError> {
        let Some(alpha_reg) = self.alpha_ahead(ahead) else {
            return Ok(());
        };
        if self.refactor_after == 0 || running.iter().any(|r| r.alpha_reg == alpha_reg) {
            return Ok(());
        }
        let t = Instant::now();
        let cholesky = self.spare_cholesky()?;
        let weights = CoarseWeights {
            reg: alpha_reg,
            ..self.weights
        };
        let job = self.factor_job(
            cholesky,
            &self.fit_matrices(),
            &weights,
            self.damping.lambda(),
        );
        times.assembly += t.elapsed();
        running.push(Running {
            alpha_reg,
            handle: scope.spawn(move || job.run()),
        });
        Ok(())
    }

    /// One damped Gauss-Newton step from the current state (energy `e`): solved from the current
    /// factor (refactored first where it is stale), accepted if it lowers the energy, else retried
    /// with raised damping from the same factor (see [`CoarseSolver::raise`]).
    ///
    /// A factor kept from an earlier iteration solves within `refactor_after` iterations or not
    /// at all: where the step moved the correspondences far (real fluid frames), such a solve
    /// took 30–110 iterations, each a pair of triangular solves through the whole factor, where
    /// a fresh factor costs about ten and then solves in one. So the solve stops there, the
    /// factor is refreshed and the step solved again, and the rest of the stage refactors every
    /// iteration (`eager`) rather than paying for the stopped solve again.
    fn iterate(
        &mut self,
        e: f64,
        times: &mut StepTimes,
        cg_iterations: &mut usize,
    ) -> Result<Outcome, RegisterError> {
        let t = Instant::now();
        self.assemble_gradient();
        times.assembly += t.elapsed();
        let mut factored = false;
        loop {
            if self.stale || self.refactor_after == 0 || (self.eager && !factored) {
                let t = Instant::now();
                self.assemble_matrix();
                times.assembly += t.elapsed();
                let t = Instant::now();
                self.factor()?;
                times.factorization += t.elapsed();
                factored = true;
            }
            let most = if factored {
                self.options.max_cg_iterations
            } else {
                self.refactor_after.min(self.options.max_cg_iterations)
            };
            let Some((trial, trial_deformed, trial_e)) = self.trial(most, times, cg_iterations)?
            else {
                self.eager = true;
                continue;
            };
            if trial_e.is_finite() && trial_e <= e {
                let damping = self.damping.lambda();
                self.lower(e - trial_e);
                self.x = trial;
                self.deformed = trial_deformed;
                return Ok(Outcome::Accepted { damping });
            }
            if trial_e.is_finite() && trial_e - e <= ROUNDING * e {
                return Ok(Outcome::Converged);
            }
            if !self.raise() {
                return Ok(Outcome::Stuck);
            }
        }
    }

    /// The step from the current factor, and where it leads: unknowns, deformed samples, energy.
    /// `None` where the solve stopped at `most` iterations short of both the tolerance and the
    /// options' own limit: the factor is to be refreshed.
    fn trial(
        &mut self,
        most: usize,
        times: &mut StepTimes,
        cg_iterations: &mut usize,
    ) -> Result<Option<Trial>, RegisterError> {
        let t = Instant::now();
        let solve = self.solve_within(most)?;
        *cg_iterations += solve.iterations;
        times.solve += t.elapsed();
        if !solve.converged && most < self.options.max_cg_iterations {
            return Ok(None);
        }
        let t = Instant::now();
        let trial: Vec<f64> = self.x.iter().zip(&self.delta).map(|(a, d)| a + d).collect();
        let trial_deformed = self.model.deform(&trial);
        let w = &self.weights;
        let trial_e = energy(&self.model, &trial, &trial_deformed, &self.current, w).total(w);
        times.evaluation += t.elapsed();
        Ok(Some((trial, trial_deformed, trial_e)))
    }
}

/// What a coarse stage is built on: the source's surface, its deformation graph and the vertices
/// carrying `E_fit`.
pub(crate) struct Setup {
    surface: Surface,
    graph: DeformationGraph,
    samples: Vec<u32>,
    /// The symbolic analysis of the matrix, when its pattern follows from the graph alone
    /// ([`Coupling::Graph`]): then it is done as soon as the graph is.
    analysis: Option<GraphAnalysis>,
}

impl Setup {
    /// The setup of `source`, and `beside(surface, samples)`, which runs while the graph is built:
    /// the graph's nearest-node search is one sequential Dijkstra, and the rigid pre-alignment (and
    /// whatever it waits for, such as the target's tree) needs only the samples.
    pub(crate) fn build<R: Send>(
        source: &IndexedMesh,
        options: &RegisterOptions,
        beside: impl FnOnce(&Surface, &[u32]) -> R + Send,
    ) -> Result<(Self, R), RegisterError> {
        options.check()?;
        check_indices(source, "source")?;
        let unit = source.mean_edge_length();
        if !(unit.is_finite() && unit > 0.0) {
            return Err(RegisterError::NoScale { which: "source" });
        }
        let surface = Surface::new(&source.positions, &source.triangles, unit);
        let spacing = options
            .graph
            .spacing_for(surface_area(&surface.rest, surface.faces.triangles()));
        // The fit samples thin out with the nodes, so each node keeps as many as at the paper's
        // spacing.
        let sample_spacing = options.coarse.sample_spacing * spacing / options.graph.spacing;
        let (built, (samples, result)) = rayon::join(
            || {
                let graph = DeformationGraph::from_adjacency(
                    &source.positions,
                    &surface.adjacency,
                    spacing * unit,
                    options.graph.skinning_nodes,
                );
                let analysis = match options.coarse.solver {
                    LinearSolver::PreconditionedCg { .. } => {
                        Some(analyze_graph_pattern(&graph, &surface))
                    }
                    LinearSolver::Cholesky => None,
                };
                (graph, analysis)
            },
            || {
                let samples = fit_samples(&surface, sample_spacing);
                let result = beside(&surface, &samples);
                (samples, result)
            },
        );
        let (graph, analysis) = built;
        Ok((
            Self {
                surface,
                graph,
                samples,
                analysis: analysis.transpose()?,
            },
            result,
        ))
    }
}

/// The rigid pre-alignment: its motion, the fit energy of each pose it took and its time.
pub(crate) struct RigidStart {
    pose: Rigid,
    energies: Vec<f64>,
    time: Duration,
}

/// Rigid ICP of `samples` from `surface`'s rest pose (none for `rigid_iterations` 0).
pub(crate) fn rigid_start(
    correspond: &dyn Correspond,
    surface: &Surface,
    samples: &[u32],
    options: &CoarseOptions,
) -> Result<Option<RigidStart>, RegisterError> {
    if options.rigid_iterations == 0 {
        return Ok(None);
    }
    let t = Instant::now();
    let rest: Vec<DVec3> = samples.iter().map(|&v| surface.rest[v as usize]).collect();
    let normals = surface.faces.normals_of(&surface.rest, samples);
    let (pose, report) = prealign(
        &rest,
        &normals,
        options.plane_weight,
        options.point_weight,
        options.rigid_iterations,
        |points, normals| {
            targets(
                correspond,
                &surface.units,
                points,
                normals,
                options.max_distance,
            )
        },
    )?;
    Ok(Some(RigidStart {
        pose,
        energies: report.energies,
        time: t.elapsed(),
    }))
}

/// The symbolic analysis of the [`Coupling::Graph`] pattern of `graph`, which has a block for
/// every graph edge and node whichever vertices carry `E_fit`, so it needs no samples (the
/// samples' fit terms go to the diagonal blocks).
fn analyze_graph_pattern(
    graph: &DeformationGraph,
    surface: &Surface,
) -> Result<GraphAnalysis, RegisterError> {
    let model = Model::new(graph, &surface.rest, &[], &surface.units);
    let pattern = Pattern::new(&model, Coupling::Graph)?;
    Ok(GraphAnalysis {
        cholesky: Cholesky::analyze(&pattern, Par::Seq)?,
        block_col_ptr: pattern.block_col_ptr,
        block_rows: pattern.block_rows,
    })
}

/// A symbolic analysis and the block structure it was made for.
struct GraphAnalysis {
    cholesky: Cholesky,
    block_col_ptr: Vec<u32>,
    block_rows: Vec<u32>,
}

impl GraphAnalysis {
    /// Whether `pattern` has the analysed structure (the scalar pattern follows from the blocks).
    fn fits(&self, pattern: &Pattern) -> bool {
        self.block_col_ptr == pattern.block_col_ptr && self.block_rows == pattern.block_rows
    }
}

/// The mean diagonal of the matrix whose upper triangle is `values`: the scale of damping.
fn mean_diagonal(pattern: &Pattern, values: &[f64]) -> f64 {
    let n = pattern.dimension();
    let mean = (0..n)
        .map(|c| values[pattern.col_ptr[c + 1] as usize - 1])
        .sum::<f64>()
        / n.max(1) as f64;
    if mean > 0.0 { mean } else { 1.0 }
}

/// A factor ready for a later stage, and the damping scale of its matrix.
struct Prepared {
    scale: f64,
    cholesky: Cholesky,
}

/// A later stage's matrix, to be factored into `cholesky` while the current stage iterates.
struct NextFactor {
    pattern: Arc<Pattern>,
    values: Vec<f64>,
    scale: f64,
    lambda: f64,
    cholesky: Cholesky,
}

impl NextFactor {
    /// The prepared factor, or the buffers back when a pivot is not positive (the stage then
    /// factors, and damps, as usual); and the time it took.
    fn run(mut self) -> (Result<Prepared, Cholesky>, Duration) {
        let t = Instant::now();
        damp_in_place(&self.pattern, &mut self.values, self.lambda);
        let result = match self.cholesky.factor(&self.pattern, &self.values) {
            Ok(()) => Ok(Prepared {
                scale: self.scale,
                cholesky: self.cholesky,
            }),
            Err(_) => Err(self.cholesky),
        };
        (result, t.elapsed())
    }
}

/// A later stage's factorization, running.
struct Running<'s> {
    alpha_reg: f64,
    handle: ScopedJoinHandle<'s, (Result<Prepared, Cholesky>, Duration)>,
}

/// A trial step's unknowns, deformed samples and energy.
type Trial = (Vec<f64>, Vec<DVec3>, f64);

/// What was done for an iteration before it began: reported with it.
#[derive(Debug, Default)]
struct Carried {
    times: StepTimes,
    factorizations: usize,
}

/// What one attempted iteration produced.
enum Outcome {
    /// A step lowered the energy; it was taken with this damping.
    Accepted { damping: f64 },
    /// No step lowers the energy by more than rounding: the stage has converged.
    Converged,
    /// Every damping tried raised the energy: the stage cannot make progress (reported, since the
    /// stage then ends unconverged).
    Stuck,
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
        if let (Some(old), Some(new)) = (slot.as_ref(), new)
            && old != new
            && fit_energy(new, p, w) <= fit_energy(old, p, w)
        {
            *slot = Some(*new);
            replaced += 1;
        }
    }
    replaced
}
