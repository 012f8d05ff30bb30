//! The fine stage's linear solve, `A d = b` by Jacobi-preconditioned conjugate gradients (see
//! `register::fine`), on either backend, as one sequence of kernels: `fine_system` (per round),
//! `fine_cover` + `fine_apply` + `fine_start` (the start), then per iteration `fine_cover` +
//! `fine_apply` (`A p`), `fine_scalars` (α), `fine_update`, `fine_scalars` (β, residual, whether to
//! go on) and `fine_direction`, each sum taken by `fine_reduce` in a fixed order. The CPU runs the
//! kernels' twins (`register::cpu`) in that order; the GPU runs the kernels with every vector and
//! matrix resident on the device for the whole stage (`register::gpu`).
//!
//! Both backends compute in f64 and sum in the same order (chunks of 1,024 vertices in vertex
//! order, then the chunks in order), so they differ only where the device rounds an operation
//! differently: by fusing a multiply and an add, or in `sqrt` and division, which Vulkan lets a
//! driver compute to a few ulps. The solve's discrete decisions — when it stops, which
//! preconditioner blocks are singular — are taken by the same comparisons on both; they can
//! differ only where a value lies within such rounding of its threshold. The stage's next round
//! casts its correspondences from `start + d` rounded to f32, so a `d` that differs in its last
//! bits changes them only where a position rounds to a different f32 and that moves a ray across
//! a pruning threshold (on the synth scenes tracked on lavapipe, never: frames and events are
//! byte-identical to the CPU's).
//!
//! Where the device has no f64 arithmetic (`GpuContext::has_f64`), the GPU backend runs this stage
//! on the CPU, and says so in its description.

use std::sync::Arc;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::RegisterError;
use super::adjacency::VertexAdjacency;
use super::cover::Cover;
use super::cpu::fine_apply::fine_apply;
use super::cpu::fine_cover::fine_cover;
use super::cpu::fine_direction::fine_direction;
use super::cpu::fine_reduce::fine_reduce;
use super::cpu::fine_scalars::fine_scalars;
use super::cpu::fine_start::{Iterates, fine_start};
use super::cpu::fine_system::fine_system;
use super::cpu::fine_update::fine_update;
use super::gpu::GpuFineSolve;
use super::model::CHUNK;
use super::options::FineOptions;
use crate::compute::{Backend, GpuContext, kernel_time};
use crate::kernels::shared::{
    CgState, FineParams, FineTarget, PHASE_ALPHA, PHASE_BEGIN, PHASE_BETA, PHASE_NORM, REDUCE_CHUNK,
};

// The kernels' sums must be `ordered_sum`'s, chunk for chunk.
const _: () = assert!(REDUCE_CHUNK as usize == CHUNK);

/// `v vᵀ`.
pub fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// How a conjugate-gradient solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solve {
    pub iterations: usize,
    /// `|b − A d| / |b|` at the end.
    pub residual: f64,
    pub converged: bool,
}

impl Solve {
    fn of(state: &CgState, options: &FineOptions) -> Self {
        Self {
            iterations: state.iterations as usize,
            residual: state.residual,
            converged: state.residual <= options.tolerance,
        }
    }
}

/// The fine energy's fixed parts for one stage: the starting positions, the mesh edges with their
/// directions `ê` (before the stage), the cover term and the weights.
pub struct FineSystem<'a> {
    pub params: FineParams,
    pub start: &'a [DVec3],
    pub adjacency: &'a VertexAdjacency,
    /// `ê` for every adjacency entry, in the adjacency's order.
    pub directions: Vec<DVec3>,
    pub cover: Cover,
}

impl<'a> FineSystem<'a> {
    /// Fails when the mesh is too large for the kernels' 32-bit counts.
    pub fn new(
        adjacency: &'a VertexAdjacency,
        start: &'a [DVec3],
        cover: Cover,
        options: &FineOptions,
    ) -> Result<Self, RegisterError> {
        let count = |what: &'static str, count: usize| {
            u32::try_from(count).map_err(|_| RegisterError::TooLarge { what, count })
        };
        let params = FineParams {
            disp_weight: options.disp_weight,
            edge_weight: options.edge_weight,
            plane_weight: options.plane_weight,
            point_weight: options.point_weight,
            tolerance: options.tolerance,
            vertices: count("vertices", start.len())?,
            pairs: count("cover pairs", cover.len())?,
            chunks: count("vertex chunks", start.len().div_ceil(CHUNK))?,
            // More than 2³² iterations is no limit at all.
            max_iterations: u32::try_from(options.max_cg_iterations).unwrap_or(u32::MAX),
        };
        let directions = (0..start.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .flat_map_iter(|v| {
                adjacency
                    .neighbours(v)
                    .iter()
                    .map(move |&u| (start[v] - start[u as usize]).normalize_or_zero())
            })
            .collect();
        Ok(Self {
            params,
            start,
            adjacency,
            directions,
            cover,
        })
    }

    pub fn len(&self) -> usize {
        self.start.len()
    }

    pub fn neighbours(&self, v: usize) -> &[u32] {
        self.adjacency.neighbours(v)
    }

    pub fn directions(&self, v: usize) -> &[DVec3] {
        let offsets = self.adjacency.offsets();
        &self.directions[offsets[v] as usize..offsets[v + 1] as usize]
    }
}

/// The vector the fine system's matrix is applied to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Operand {
    /// The displacements, for the starting residual.
    D = 0,
    /// The search direction, in every iteration.
    P = 1,
}

/// Where the solves of one stage run: the CPU twins or the kernels, each with the stage's buffers
/// made (and on the GPU uploaded) once.
pub enum FineSolver {
    Cpu(Box<CpuFineSolve>),
    Gpu {
        solve: Box<GpuFineSolve>,
        context: Arc<GpuContext>,
    },
}

impl FineSolver {
    /// The solver for `backend`: its kernels where the device has f64 arithmetic, else the CPU
    /// twins. `d` is the stage's starting displacement.
    pub fn new(backend: &Backend, system: &FineSystem, d: &[DVec3]) -> Result<Self, RegisterError> {
        Ok(match backend.gpu() {
            Some(context) if context.has_f64() => Self::Gpu {
                solve: Box::new(kernel_time::timed(|| {
                    GpuFineSolve::upload(context, system, d)
                })?),
                context: Arc::clone(context),
            },
            _ => Self::Cpu(Box::new(CpuFineSolve::new(system, d))),
        })
    }

    /// Solves for the correspondences `targets` from the last solve's displacements (the stage's
    /// start for the first), and copies the solution into `d`.
    pub fn solve(
        &mut self,
        system: &FineSystem,
        targets: &[FineTarget],
        d: &mut [DVec3],
        options: &FineOptions,
    ) -> Result<Solve, RegisterError> {
        kernel_time::timed(|| {
            let state = match self {
                Self::Gpu { solve, context } => {
                    let (state, solution) = solve.solve(context, targets)?;
                    d.copy_from_slice(&solution);
                    state
                }
                Self::Cpu(solve) => {
                    let state = solve.solve(system, targets);
                    d.copy_from_slice(&solve.d);
                    state
                }
            };
            Ok::<_, RegisterError>(Solve::of(&state, options))
        })
    }
}

/// The CPU twins' buffers, the same the GPU path keeps on the device, and the kernels' sequence
/// over them: one method per dispatch (or pair of dispatches) of [`GpuFineSolve`].
#[derive(Debug, Clone)]
pub struct CpuFineSolve {
    pub fit: Vec<DMat3>,
    pub b: Vec<DVec3>,
    pub preconditioner: Vec<DMat3>,
    pub terms: Vec<[f64; 2]>,
    pub partials: Vec<[f64; 2]>,
    pub moved: Vec<DVec3>,
    pub ad: Vec<DVec3>,
    pub d: Vec<DVec3>,
    pub r: Vec<DVec3>,
    pub z: Vec<DVec3>,
    pub p: Vec<DVec3>,
    pub state: CgState,
}

impl CpuFineSolve {
    /// Buffers for `system` with displacements `d`.
    pub fn new(system: &FineSystem, d: &[DVec3]) -> Self {
        let n = system.len();
        Self {
            fit: vec![DMat3::ZERO; n],
            b: vec![DVec3::ZERO; n],
            preconditioner: vec![DMat3::ZERO; n],
            terms: vec![[0.0; 2]; n],
            partials: vec![[0.0; 2]; system.params.chunks as usize],
            moved: vec![DVec3::ZERO; system.cover.len()],
            ad: vec![DVec3::ZERO; n],
            d: d.to_vec(),
            r: vec![DVec3::ZERO; n],
            z: vec![DVec3::ZERO; n],
            p: vec![DVec3::ZERO; n],
            state: CgState::default(),
        }
    }

    /// One solve from the displacements in `self.d`; returns the final state.
    pub fn solve(&mut self, system: &FineSystem, targets: &[FineTarget]) -> CgState {
        self.system(system, targets);
        self.reduce(system, PHASE_NORM);
        self.apply(system, Operand::D);
        self.start();
        self.reduce(system, PHASE_BEGIN);
        while self.state.done == 0 {
            self.apply(system, Operand::P);
            self.reduce(system, PHASE_ALPHA);
            self.update();
            self.reduce(system, PHASE_BETA);
            self.direction();
        }
        self.state
    }

    /// `fine_system`.
    pub fn system(&mut self, system: &FineSystem, targets: &[FineTarget]) {
        fine_system(
            system,
            targets,
            &mut self.fit,
            &mut self.b,
            &mut self.preconditioner,
            &mut self.terms,
        );
    }

    /// `fine_reduce`, then `fine_scalars` in `phase`.
    pub fn reduce(&mut self, system: &FineSystem, phase: u32) {
        fine_reduce(&self.terms, &mut self.partials);
        fine_scalars(&system.params, phase, &self.partials, &mut self.state);
    }

    /// `fine_cover` and `fine_apply`: `ad = A x`.
    pub fn apply(&mut self, system: &FineSystem, operand: Operand) {
        let x = match operand {
            Operand::D => &self.d,
            Operand::P => &self.p,
        };
        fine_cover(&self.state, &system.cover, x, &mut self.moved);
        fine_apply(
            system,
            &self.state,
            &self.fit,
            &self.moved,
            x,
            &mut self.ad,
            &mut self.terms,
        );
    }

    /// `fine_start`.
    pub fn start(&mut self) {
        let iterates = Iterates {
            d: &mut self.d,
            r: &mut self.r,
            z: &mut self.z,
            p: &mut self.p,
        };
        fine_start(
            &self.state,
            &self.b,
            &self.preconditioner,
            &self.ad,
            iterates,
            &mut self.terms,
        );
    }

    /// `fine_update`.
    pub fn update(&mut self) {
        let iterates = Iterates {
            d: &mut self.d,
            r: &mut self.r,
            z: &mut self.z,
            p: &mut self.p,
        };
        fine_update(
            &self.state,
            &self.ad,
            &self.preconditioner,
            iterates,
            &mut self.terms,
        );
    }

    /// `fine_direction`.
    pub fn direction(&mut self) {
        fine_direction(&self.state, &self.z, &mut self.p);
    }
}
