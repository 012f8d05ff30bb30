//! What a registration did: energies per iteration, correspondences kept and pruned, and the time
//! of every sub-step, so a failure to converge is visible rather than silent.

use std::time::Duration;

/// Time spent in the sub-steps of Gauss-Newton iterations.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepTimes {
    /// Vertex normals and normal-ray projection.
    pub correspondence: Duration,
    /// `JᵀJ` and `Jᵀr`.
    pub assembly: Duration,
    /// Numeric Cholesky factorizations (every damping retry included; a stage's first iteration
    /// also counts the factor computed for it while earlier stages iterated).
    pub factorization: Duration,
    /// Triangular solves.
    pub solve: Duration,
    /// Energy evaluations of trial steps.
    pub evaluation: Duration,
}

impl std::ops::AddAssign for StepTimes {
    fn add_assign(&mut self, o: Self) {
        self.correspondence += o.correspondence;
        self.assembly += o.assembly;
        self.factorization += o.factorization;
        self.solve += o.solve;
        self.evaluation += o.evaluation;
    }
}

/// One Gauss-Newton iteration of the coarse stage.
#[derive(Debug, Clone, PartialEq)]
pub struct IterationReport {
    /// `E_tot` before the step.
    pub energy_before: f64,
    /// `E_tot` after the step and the correspondence update; never above `energy_before`.
    pub energy: f64,
    /// Unweighted `E_fit`, `E_rigid` and `E_smooth` after the iteration.
    pub fit: f64,
    pub rigid: f64,
    pub smooth: f64,
    /// Vertices with a correspondence, and without one (missed or pruned).
    pub kept: usize,
    pub pruned: usize,
    /// Correspondences replaced by a better re-projection after the step.
    pub replaced: usize,
    /// Levenberg-Marquardt damping of the accepted step (0: a plain Gauss-Newton step).
    pub damping: f64,
    /// Steps retried with more damping (non-positive pivot or energy increase).
    pub retries: usize,
    /// Numeric factorizations done in this iteration (a stage's first also counts the factor
    /// computed for it ahead).
    pub factorizations: usize,
    /// Conjugate-gradient iterations over all tries.
    pub cg_iterations: usize,
    pub times: StepTimes,
}

/// One `α_reg` stage of the coarse stage.
#[derive(Debug, Clone, PartialEq)]
pub struct StageReport {
    pub alpha_reg: f64,
    /// `E_tot` at the stage's start (with its fresh correspondences).
    pub energy_start: f64,
    pub iterations: Vec<IterationReport>,
    /// The relative energy change fell below the threshold (rather than the iteration limit
    /// being reached, or no step lowering the energy at any damping).
    pub converged: bool,
}

/// The coarse deformation-graph stage.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CoarseReport {
    pub nodes: usize,
    /// Vertices carrying `E_fit`.
    pub samples: usize,
    pub graph_edges: usize,
    /// Unknowns (12 per node) and stored nonzeros of `JᵀJ` (upper triangle) and of its factor.
    pub unknowns: usize,
    pub matrix_nonzeros: usize,
    pub factor_nonzeros: usize,
    /// Sparsity pattern and symbolic factorization (done once).
    pub setup: Duration,
    /// Fit energy of each pose of the rigid pre-alignment (falling), and its time (it runs beside
    /// the graph build, within the registration's setup).
    pub rigid_energies: Vec<f64>,
    pub rigid_time: Duration,
    pub stages: Vec<StageReport>,
    pub times: StepTimes,
    /// Every stage converged.
    pub converged: bool,
}

impl CoarseReport {
    pub fn iterations(&self) -> usize {
        self.stages.iter().map(|s| s.iterations.len()).sum()
    }
}

/// One round of the fine stage.
#[derive(Debug, Clone, PartialEq)]
pub struct FineRound {
    pub kept: usize,
    pub pruned: usize,
    /// Target samples pulling the source (the cover term).
    pub cover: usize,
    /// The fine energy before and after the solve (same correspondences).
    pub energy_before: f64,
    pub energy: f64,
    pub cg_iterations: usize,
    /// Final residual relative to the right-hand side.
    pub residual: f64,
    pub converged: bool,
    pub correspondence: Duration,
    pub solve: Duration,
}

/// The fine per-vertex stage.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FineReport {
    pub rounds: Vec<FineRound>,
    pub converged: bool,
}

/// Everything [`super::register`] reports.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RegistrationReport {
    pub vertices: usize,
    pub coarse: CoarseReport,
    pub fine: FineReport,
    /// Target BVH (built beside the deformation graph, so within `setup_time`).
    pub bvh_time: Duration,
    /// Deformation graph, with the target BVH and the rigid pre-alignment beside it, then the
    /// sparsity pattern and the symbolic factorization.
    pub setup_time: Duration,
    pub coarse_time: Duration,
    pub fine_time: Duration,
    pub total_time: Duration,
}

impl RegistrationReport {
    /// Both stages converged.
    pub fn converged(&self) -> bool {
        self.coarse.converged && self.fine.converged
    }
}
