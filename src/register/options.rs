//! Parameters of a registration. Distances are in mean edge lengths of the source mesh, so the
//! same options mean the same at any scale.

use super::RegisterError;
use super::graph::GraphOptions;

/// Everything [`super::register`] can be told.
#[derive(Debug, Clone, PartialEq)]
pub struct RegisterOptions {
    pub graph: GraphOptions,
    pub coarse: CoarseOptions,
    pub fine: FineOptions,
    /// Correspondences whose source and target normals differ by more than this are pruned
    /// (paper §4.2: 60°).
    pub max_angle_degrees: f32,
}

impl Default for RegisterOptions {
    fn default() -> Self {
        Self {
            graph: GraphOptions::default(),
            coarse: CoarseOptions::default(),
            fine: FineOptions::default(),
            max_angle_degrees: 60.0,
        }
    }
}

/// The coarse deformation-graph stage (paper §4.2, thesis §3.3.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoarseOptions {
    /// `α_fit` (paper: 0.1).
    pub alpha_fit: f64,
    /// `α_reg` of the first stage (paper: 1000).
    pub alpha_reg_start: f64,
    /// `α_reg` of the last stage: relaxation stops once a stage at or below it has converged.
    pub alpha_reg_floor: f64,
    /// Weight of `E_plane` within `E_fit` (paper: 1).
    pub plane_weight: f64,
    /// Weight of `E_point` within `E_fit` (paper: 0.1).
    pub point_weight: f64,
    /// Weight of `E_smooth` within `E_reg` (paper: 0.1).
    pub smooth_weight: f64,
    /// A stage ends, and `α_reg` is divided by 10, when an iteration lowers the energy by less than
    /// this fraction (thesis §3.3.3: σ = 0.005).
    pub relax_threshold: f64,
    /// Most Gauss-Newton iterations in one stage.
    pub max_stage_iterations: usize,
    /// Correspondences farther than this (mean edge lengths) are pruned; unbounded by default, as
    /// the coarse stage must recover large motions and relies on the normal test instead.
    pub max_distance: f64,
    /// `E_fit` runs over vertices sampled this far apart along the surface (mean edge lengths; 0
    /// for every vertex). The graph has 12 unknowns per node and a node per ~18 vertices, so a
    /// uniformly spread subset fixes it as well as all vertices do (issue 5 allows it), at a
    /// fraction of the projection and assembly cost; the fine stage then fits every vertex.
    pub sample_spacing: f32,
    /// Iterations of rigid point-to-plane ICP before the graph stages (0: none); see
    /// `register::rigid`.
    pub rigid_iterations: usize,
    /// How each Gauss-Newton system is solved.
    pub solver: LinearSolver,
    /// Conjugate gradients stop at this residual relative to `|Jᵀr|`. A Gauss-Newton step need
    /// not be solved exactly (an inexact Newton method's forcing term): every step is still
    /// accepted only if it lowers `E_tot`, and the stages end on the energy's relative change.
    /// 10⁻² leaves the energies of the `register` bench frames equal to four digits against 10⁻⁴,
    /// with one solve of every two saved.
    pub cg_tolerance: f64,
    pub max_cg_iterations: usize,
}

/// How the coarse stage solves `(JᵀJ + λ I) δ = −Jᵀr`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearSolver {
    /// Factor the exact `JᵀJ` every iteration (paper §4.2). Its pattern couples every pair of nodes
    /// that skin a common vertex, about twice as wide as the graph, so its factor fills about
    /// three times as much. The factor is single precision (see `register::cholesky`), so
    /// conjugate gradients still take about one iteration to reach `cg_tolerance`.
    Cholesky,
    /// Conjugate gradients on the exact system, preconditioned by the Cholesky factor of an upper
    /// bound of `JᵀJ` with the graph's own sparsity; the factor is kept across iterations and
    /// refreshed at each new `α_reg` or once a solve needs more than `refactor_after` iterations.
    PreconditionedCg { refactor_after: usize },
}

impl Default for CoarseOptions {
    fn default() -> Self {
        Self {
            alpha_fit: 0.1,
            alpha_reg_start: 1000.0,
            alpha_reg_floor: 0.1,
            plane_weight: 1.0,
            point_weight: 0.1,
            smooth_weight: 0.1,
            relax_threshold: 0.005,
            max_stage_iterations: 50,
            max_distance: f64::INFINITY,
            sample_spacing: 2.0,
            rigid_iterations: 50,
            solver: LinearSolver::PreconditionedCg { refactor_after: 8 },
            cg_tolerance: 1e-2,
            max_cg_iterations: 200,
        }
    }
}

/// The default [`FineOptions::cover_growth`]. On the SPH dam break's splash (frames 20–44, each
/// tracked alone from one fixed run) a flat cover term keeps 80.93% of the vertices per frame and
/// this one 82.80%: a sheet or strand no source ray reaches lies a cell or more from the source,
/// and pulling it harder keeps the mesh on it, where the topology step would otherwise re-sample
/// it. A flat weight raised instead (24: 83.68%) also pulls hard on the samples just past the
/// minimum distance, which are mostly the target's triangulation noise: the synth `rigid`
/// scene's drift doubles, where with growth it does not (docs/performance.md).
const COVER_GROWTH: f64 = 1.0;

/// The fine per-vertex stage (paper §4.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FineOptions {
    /// Correspondences farther than σ mean edge lengths are pruned "to avoid self intersections"
    /// (paper: σ = 0.1 in its scenes' units). 1.5 rather than 1: a droplet only two edges across
    /// that the coarse graph (one node) leaves a little too long has its far ends more than one
    /// edge from the target, and with σ = 1 nothing pulls them in (synth `droplets` frame 17 ended
    /// 1.22 Δ from its input; with 1.5 every synth scene stays within 0.82 Δ, see `track`).
    pub sigma: f64,
    pub plane_weight: f64,
    pub point_weight: f64,
    /// Weight of `E_disp`: squared differences of adjacent displacements.
    pub disp_weight: f64,
    /// Weight of `E_edge`: squared (linearized) changes of edge lengths.
    pub edge_weight: f64,
    /// Weight of the cover term (target samples pulling their nearest source points, see
    /// `register::fine`) relative to `E_fit` (3: measured on the synth scenes, see there); 0 leaves
    /// the paper's one-sided fit.
    pub cover_weight: f64,
    /// Target samples nearer the source than this (mean edge lengths) take no part in the cover
    /// term: the source already reaches them.
    pub cover_min_distance: f64,
    /// How much harder a cover pair pulls the farther its target sample lies from the source: its
    /// weight is multiplied by `(gap / cover_min_distance)^cover_growth` (see `register::cover`);
    /// 0 weighs every pair alike.
    pub cover_growth: f64,
    /// Rounds of (correspondences, conjugate-gradient solve), each warm-started from the last.
    pub rounds: usize,
    /// Conjugate gradients stop when the residual falls below this fraction of the right-hand side.
    pub tolerance: f64,
    pub max_cg_iterations: usize,
}

impl Default for FineOptions {
    fn default() -> Self {
        Self {
            sigma: 1.5,
            plane_weight: 1.0,
            point_weight: 0.1,
            disp_weight: 1.0,
            edge_weight: 1.0,
            cover_weight: 3.0,
            cover_min_distance: 0.25,
            cover_growth: COVER_GROWTH,
            rounds: 2,
            tolerance: 1e-4,
            max_cg_iterations: 200,
        }
    }
}

/// `Ok` when `holds`, else the option error naming `name`, what it must be and its `value`.
fn require(
    holds: bool,
    name: &'static str,
    expected: &'static str,
    value: f64,
) -> Result<(), RegisterError> {
    if holds {
        Ok(())
    } else {
        Err(RegisterError::Option {
            name,
            expected,
            value,
        })
    }
}

/// A check of one numeric option.
type Check = fn(&'static str, f64) -> Result<(), RegisterError>;

fn positive(name: &'static str, value: f64) -> Result<(), RegisterError> {
    require(
        value.is_finite() && value > 0.0,
        name,
        "finite and positive",
        value,
    )
}

fn non_negative(name: &'static str, value: f64) -> Result<(), RegisterError> {
    require(
        value.is_finite() && value >= 0.0,
        name,
        "finite and non-negative",
        value,
    )
}

impl RegisterOptions {
    pub fn check(&self) -> Result<(), RegisterError> {
        self.graph.check()?;
        let angle = f64::from(self.max_angle_degrees);
        let within = (0.0..=180.0).contains(&angle);
        require(within, "max angle", "between 0 and 180 degrees", angle)?;
        let (c, f) = (&self.coarse, &self.fine);
        let iterations = c.max_stage_iterations > 0;
        require(iterations, "coarse max stage iterations", "at least 1", 0.0)?;
        let (distance, expected) = (c.max_distance, "positive (infinity for no limit)");
        require(distance > 0.0, "coarse max distance", expected, distance)?;
        let checks = [
            ("coarse alpha_fit", c.alpha_fit, positive as Check),
            ("coarse alpha_reg_start", c.alpha_reg_start, positive),
            ("coarse alpha_reg_floor", c.alpha_reg_floor, positive),
            ("coarse plane weight", c.plane_weight, non_negative),
            ("coarse point weight", c.point_weight, positive),
            ("coarse smooth weight", c.smooth_weight, non_negative),
            ("coarse relax threshold", c.relax_threshold, positive),
            (
                "coarse sample spacing",
                f64::from(c.sample_spacing),
                non_negative,
            ),
            ("coarse cg tolerance", c.cg_tolerance, positive),
            ("fine sigma", f.sigma, positive),
            ("fine plane weight", f.plane_weight, non_negative),
            ("fine point weight", f.point_weight, positive),
            ("fine disp weight", f.disp_weight, non_negative),
            ("fine edge weight", f.edge_weight, non_negative),
            ("fine cover weight", f.cover_weight, non_negative),
            (
                "fine cover minimum distance",
                f.cover_min_distance,
                non_negative,
            ),
            ("fine cover growth", f.cover_growth, non_negative),
            ("fine tolerance", f.tolerance, positive),
        ];
        for (name, value, check) in checks {
            check(name, value)?;
        }
        // The growth is measured in minimum distances.
        require(
            f.cover_growth == 0.0 || f.cover_min_distance > 0.0,
            "fine cover minimum distance",
            "positive where the cover weight grows with the gap",
            f.cover_min_distance,
        )
    }
}
