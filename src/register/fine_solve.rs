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
//! differ only where a value lies within such rounding of its threshold.
//!
//! Where the device has no f64 arithmetic (`GpuContext::has_f64`), the GPU backend runs this stage
//! on the CPU, and says so in its description.

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
use crate::compute::{Backend, kernel_time};
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
        let too_large = RegisterError::CoverTooLarge { pairs: cover.len() };
        let count = |n: usize| u32::try_from(n).map_err(|_| too_large.clone());
        let params = FineParams {
            disp_weight: options.disp_weight,
            edge_weight: options.edge_weight,
            plane_weight: options.plane_weight,
            point_weight: options.point_weight,
            tolerance: options.tolerance,
            vertices: count(start.len())?,
            pairs: count(cover.len())?,
            chunks: count(start.len().div_ceil(CHUNK))?,
            max_iterations: count(options.max_cg_iterations)?,
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

/// Where the solves of one stage run: the CPU twins, or the kernels with the stage's buffers
/// uploaded once.
pub enum FineSolver {
    Cpu,
    Gpu(Box<GpuFineSolve>),
}

impl FineSolver {
    /// The solver for `backend`: its kernels where the device has f64 arithmetic, else the CPU
    /// twins. `d` is the stage's starting displacement.
    pub fn new(backend: &Backend, system: &FineSystem, d: &[DVec3]) -> Result<Self, RegisterError> {
        Ok(match backend.gpu() {
            Some(context) if context.has_f64() => Self::Gpu(Box::new(kernel_time::timed(|| {
                GpuFineSolve::upload(context, system, d)
            })?)),
            _ => Self::Cpu,
        })
    }

    /// Solves for the correspondences `targets` from the displacements `d` (the last solve's,
    /// which on the GPU are already on the device), leaving the solution in `d`.
    pub fn solve(
        &mut self,
        backend: &Backend,
        system: &FineSystem,
        targets: &[FineTarget],
        d: &mut [DVec3],
        options: &FineOptions,
    ) -> Result<Solve, RegisterError> {
        kernel_time::timed(|| match (self, backend.gpu()) {
            (Self::Gpu(solve), Some(context)) => {
                let (state, solution) = solve.solve(context, targets)?;
                d.copy_from_slice(&solution);
                Ok(Solve::of(&state, options))
            }
            _ => Ok(Solve::of(&solve_cpu(system, targets, d), options)),
        })
    }
}

/// The kernels' sequence on the CPU twins.
fn solve_cpu(system: &FineSystem, targets: &[FineTarget], d: &mut [DVec3]) -> CgState {
    let n = system.len();
    let params = &system.params;
    let mut fit = vec![DMat3::ZERO; n];
    let mut b = vec![DVec3::ZERO; n];
    let mut preconditioner = vec![DMat3::ZERO; n];
    let mut terms = vec![[0.0; 2]; n];
    let mut partials = vec![[0.0; 2]; params.chunks as usize];
    let mut moved = vec![DVec3::ZERO; system.cover.len()];
    let mut ad = vec![DVec3::ZERO; n];
    let (mut r, mut z, mut p) = (ad.clone(), ad.clone(), ad.clone());
    let mut state = CgState::default();
    fine_system(
        system,
        targets,
        &mut fit,
        &mut b,
        &mut preconditioner,
        &mut terms,
    );
    fine_reduce(&terms, &mut partials);
    fine_scalars(params, PHASE_NORM, &partials, &mut state);
    fine_cover(&state, &system.cover, d, &mut moved);
    fine_apply(system, &state, &fit, &moved, d, &mut ad, &mut terms);
    let iterates = Iterates {
        d: &mut *d,
        r: &mut r,
        z: &mut z,
        p: &mut p,
    };
    fine_start(&state, &b, &preconditioner, &ad, iterates, &mut terms);
    fine_reduce(&terms, &mut partials);
    fine_scalars(params, PHASE_BEGIN, &partials, &mut state);
    while state.done == 0 {
        fine_cover(&state, &system.cover, &p, &mut moved);
        fine_apply(system, &state, &fit, &moved, &p, &mut ad, &mut terms);
        fine_reduce(&terms, &mut partials);
        fine_scalars(params, PHASE_ALPHA, &partials, &mut state);
        let iterates = Iterates {
            d: &mut *d,
            r: &mut r,
            z: &mut z,
            p: &mut p,
        };
        fine_update(&state, &ad, &preconditioner, iterates, &mut terms);
        fine_reduce(&terms, &mut partials);
        fine_scalars(params, PHASE_BETA, &partials, &mut state);
        fine_direction(&state, &z, &mut p);
    }
    state
}
