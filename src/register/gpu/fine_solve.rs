//! GPU host of the fine stage's solve: the kernels of `register::fine_solve` in its order, with
//! every vector and matrix resident on the device for the whole stage.
//!
//! The stage's fixed parts (start positions, adjacency and edge directions, cover pairs) and the
//! displacements are uploaded once; each round uploads its correspondences and reads back the
//! solution. In between, nothing but the 48-byte [`CgState`] crosses: the iterations are submitted
//! in batches of [`ITERATIONS_PER_BATCH`], the state is read after each batch, and the kernels of
//! iterations past the solve's end do nothing (they test `done`), so the device stops exactly where
//! the CPU twin's loop does.

use glam::{DMat3, DVec3};

use crate::compute::{Batch, Bound, ComputeError, GpuContext};
use crate::kernels::shared::{
    CgState, FineTarget, PHASE_ALPHA, PHASE_BEGIN, PHASE_BETA, PHASE_NORM,
};
use crate::kernels::{
    FINE_APPLY, FINE_COVER, FINE_DIRECTION, FINE_REDUCE, FINE_SCALARS, FINE_START, FINE_SYSTEM,
    FINE_UPDATE,
};
#[cfg(test)]
use crate::register::fine_solve::CpuFineSolve;
use crate::register::fine_solve::{FineSystem, Operand};

/// Iterations submitted between two reads of the state. Each read waits for the device; the
/// iterations submitted past the end cost one early return per invocation.
const ITERATIONS_PER_BATCH: u32 = 8;

/// One stage's buffers on the device, and its kernels bound to them.
#[derive(Debug)]
pub struct GpuFineSolve {
    buffers: Buffers,
    kernels: Kernels,
    vertices: usize,
    pairs: u64,
    chunks: u64,
    max_iterations: u32,
}

#[derive(Debug)]
struct Buffers {
    params: wgpu::Buffer,
    state: wgpu::Buffer,
    phases: [wgpu::Buffer; 4],
    start: wgpu::Buffer,
    targets: wgpu::Buffer,
    offsets: wgpu::Buffer,
    neighbours: wgpu::Buffer,
    directions: wgpu::Buffer,
    cover: CoverBuffers,
    fit: wgpu::Buffer,
    b: wgpu::Buffer,
    preconditioner: wgpu::Buffer,
    terms: wgpu::Buffer,
    partials: wgpu::Buffer,
    ad: wgpu::Buffer,
    d: wgpu::Buffer,
    r: wgpu::Buffer,
    z: wgpu::Buffer,
    p: wgpu::Buffer,
}

/// Every dispatch of a solve, bound once per stage; `cover` and `apply` by [`Operand`].
#[derive(Debug)]
struct Kernels {
    system: Bound,
    cover: [Bound; 2],
    apply: [Bound; 2],
    start: Bound,
    update: Bound,
    direction: Bound,
    reduce: Bound,
    /// By phase.
    scalars: [Bound; 4],
}

#[derive(Debug)]
struct CoverBuffers {
    corners: wgpu::Buffer,
    weights: wgpu::Buffer,
    matrices: wgpu::Buffer,
    pulls: wgpu::Buffer,
    offsets: wgpu::Buffer,
    entries: wgpu::Buffer,
    moved: wgpu::Buffer,
}

/// `data`, or one zeroed element where it is empty: a binding cannot be empty, and the kernels
/// read no element past the counts in their parameters.
fn at_least_one<T: bytemuck::Pod + bytemuck::Zeroable>(data: &[T]) -> Vec<T> {
    if data.is_empty() {
        vec![T::zeroed()]
    } else {
        data.to_vec()
    }
}

impl GpuFineSolve {
    /// Uploads the stage's fixed parts and its starting displacements `d`.
    pub fn upload(
        context: &GpuContext,
        system: &FineSystem,
        d: &[DVec3],
    ) -> Result<Self, ComputeError> {
        let n = system.len();
        let cover = &system.cover;
        let chunks = system.params.chunks as usize;
        let buffers = Buffers {
            params: context.upload("fine params", &[system.params])?,
            state: context.upload("fine state", &[CgState::default()])?,
            phases: [
                context.upload("phase", &[PHASE_NORM])?,
                context.upload("phase", &[PHASE_BEGIN])?,
                context.upload("phase", &[PHASE_ALPHA])?,
                context.upload("phase", &[PHASE_BETA])?,
            ],
            start: context.upload("fine start", &at_least_one(system.start))?,
            targets: context.output::<FineTarget>("fine targets", n.max(1))?,
            offsets: context.upload("fine offsets", system.adjacency.offsets())?,
            neighbours: context.upload(
                "fine neighbours",
                &at_least_one(system.adjacency.all_neighbours()),
            )?,
            directions: context.upload("fine directions", &at_least_one(&system.directions))?,
            cover: CoverBuffers {
                corners: context.upload("cover corners", &at_least_one(&cover.corners))?,
                weights: context.upload("cover weights", &at_least_one(&cover.weights))?,
                matrices: context.upload("cover matrices", &at_least_one(&cover.matrices))?,
                pulls: context.upload("cover pulls", &at_least_one(&cover.pulls))?,
                offsets: context.upload("cover offsets", &cover_offsets(cover, n))?,
                entries: context.upload("cover entries", &at_least_one(&cover.entries))?,
                moved: context.output::<DVec3>("cover moved", cover.len().max(1))?,
            },
            fit: context.output::<DMat3>("fine fit", n.max(1))?,
            b: context.output::<DVec3>("fine b", n.max(1))?,
            preconditioner: context.output::<DMat3>("fine preconditioner", n.max(1))?,
            terms: context.output::<[f64; 2]>("fine terms", n.max(1))?,
            partials: context.output::<[f64; 2]>("fine partials", chunks.max(1))?,
            ad: context.output::<DVec3>("fine ad", n.max(1))?,
            d: context.upload("fine d", &at_least_one(d))?,
            r: context.output::<DVec3>("fine r", n.max(1))?,
            z: context.output::<DVec3>("fine z", n.max(1))?,
            p: context.output::<DVec3>("fine p", n.max(1))?,
        };
        Ok(Self {
            kernels: Kernels::bind(context, &buffers)?,
            buffers,
            vertices: n,
            pairs: u64::from(system.params.pairs),
            chunks: chunks as u64,
            max_iterations: system.params.max_iterations,
        })
    }

    /// One solve for the correspondences `targets` from the displacements on the device: the final
    /// state and the solution, which stays on the device for the next round.
    pub fn solve(
        &self,
        context: &GpuContext,
        targets: &[FineTarget],
    ) -> Result<(CgState, Vec<DVec3>), ComputeError> {
        if self.vertices == 0 {
            return Ok((CgState::default(), Vec::new()));
        }
        self.write_targets(context, targets)?;
        let mut batch = context.batch();
        self.system(&mut batch)?;
        self.reduce(&mut batch, PHASE_NORM)?;
        self.apply(&mut batch, Operand::D)?;
        self.start(&mut batch)?;
        self.reduce(&mut batch, PHASE_BEGIN)?;
        // Every batch ends the solve or spends ITERATIONS_PER_BATCH of its iterations.
        let batches = self.max_iterations / ITERATIONS_PER_BATCH + 2;
        let mut state = None;
        for _ in 0..batches {
            for _ in 0..ITERATIONS_PER_BATCH {
                self.apply(&mut batch, Operand::P)?;
                self.reduce(&mut batch, PHASE_ALPHA)?;
                self.update(&mut batch)?;
                self.reduce(&mut batch, PHASE_BETA)?;
                self.direction(&mut batch)?;
            }
            batch.submit()?;
            let now = context.read_back::<CgState>(&self.buffers.state, 1)?;
            if now.first().is_some_and(|s| s.done != 0) {
                state = now.first().copied();
                break;
            }
            batch = context.batch();
        }
        let state = state.ok_or_else(|| {
            ComputeError::Gpu(format!(
                "the fine stage's solve did not end within {} iterations",
                batches * ITERATIONS_PER_BATCH
            ))
        })?;
        Ok((
            state,
            context.read_back::<DVec3>(&self.buffers.d, self.vertices)?,
        ))
    }

    /// Replaces the correspondences on the device.
    pub fn write_targets(
        &self,
        context: &GpuContext,
        targets: &[FineTarget],
    ) -> Result<(), ComputeError> {
        if targets.len() != self.vertices {
            return Err(ComputeError::Gpu(format!(
                "{} fine-stage targets for {} vertices",
                targets.len(),
                self.vertices
            )));
        }
        context.write(&self.buffers.targets, targets)
    }

    /// `fine_system`.
    pub fn system(&self, batch: &mut Batch) -> Result<(), ComputeError> {
        batch.dispatch_bound(&self.kernels.system, self.vertices as u64)
    }

    /// `fine_start`.
    pub fn start(&self, batch: &mut Batch) -> Result<(), ComputeError> {
        batch.dispatch_bound(&self.kernels.start, self.vertices as u64)
    }

    /// `fine_update`.
    pub fn update(&self, batch: &mut Batch) -> Result<(), ComputeError> {
        batch.dispatch_bound(&self.kernels.update, self.vertices as u64)
    }

    /// `fine_direction`.
    pub fn direction(&self, batch: &mut Batch) -> Result<(), ComputeError> {
        batch.dispatch_bound(&self.kernels.direction, self.vertices as u64)
    }

    /// `fine_cover` and `fine_apply`: `ad = A x`.
    pub fn apply(&self, batch: &mut Batch, operand: Operand) -> Result<(), ComputeError> {
        let x = operand as usize;
        batch.dispatch_bound(&self.kernels.cover[x], self.pairs)?;
        batch.dispatch_bound(&self.kernels.apply[x], self.vertices as u64)
    }

    /// `fine_reduce`, then `fine_scalars` in `phase`.
    pub fn reduce(&self, batch: &mut Batch, phase: u32) -> Result<(), ComputeError> {
        batch.dispatch_bound(&self.kernels.reduce, self.chunks)?;
        batch.dispatch_bound(&self.kernels.scalars[phase as usize], 1)
    }

    /// Everything on the device, read back into the CPU twins' buffers (parity tests compare them).
    #[cfg(test)]
    pub fn read_all(&self, context: &GpuContext) -> Result<CpuFineSolve, ComputeError> {
        let n = self.vertices;
        let state = context.read_back::<CgState>(&self.buffers.state, 1)?;
        Ok(CpuFineSolve {
            fit: context.read_back(&self.buffers.fit, n)?,
            b: context.read_back(&self.buffers.b, n)?,
            preconditioner: context.read_back(&self.buffers.preconditioner, n)?,
            terms: context.read_back(&self.buffers.terms, n)?,
            partials: context.read_back(&self.buffers.partials, self.chunks as usize)?,
            moved: context.read_back(&self.buffers.cover.moved, self.pairs as usize)?,
            ad: context.read_back(&self.buffers.ad, n)?,
            d: context.read_back(&self.buffers.d, n)?,
            r: context.read_back(&self.buffers.r, n)?,
            z: context.read_back(&self.buffers.z, n)?,
            p: context.read_back(&self.buffers.p, n)?,
            state: state.first().copied().unwrap_or_default(),
        })
    }
}

impl Kernels {
    fn bind(context: &GpuContext, b: &Buffers) -> Result<Self, ComputeError> {
        let c = &b.cover;
        let cover = |x| {
            context.bind(
                &FINE_COVER,
                &[
                    &b.params,
                    &b.state,
                    &c.corners,
                    &c.weights,
                    &c.matrices,
                    x,
                    &c.moved,
                ],
            )
        };
        let apply = |x| {
            context.bind(
                &FINE_APPLY,
                &[
                    &b.params,
                    &b.state,
                    &b.fit,
                    &b.offsets,
                    &b.neighbours,
                    &b.directions,
                    &c.offsets,
                    &c.entries,
                    &c.weights,
                    &c.moved,
                    x,
                    &b.ad,
                    &b.terms,
                ],
            )
        };
        let scalars = |phase: usize| {
            context.bind(
                &FINE_SCALARS,
                &[&b.params, &b.phases[phase], &b.partials, &b.state],
            )
        };
        Ok(Self {
            system: context.bind(
                &FINE_SYSTEM,
                &[
                    &b.params,
                    &b.start,
                    &b.targets,
                    &b.offsets,
                    &b.directions,
                    &c.offsets,
                    &c.entries,
                    &c.weights,
                    &c.matrices,
                    &c.pulls,
                    &b.fit,
                    &b.b,
                    &b.preconditioner,
                    &b.terms,
                ],
            )?,
            cover: [cover(&b.d)?, cover(&b.p)?],
            apply: [apply(&b.d)?, apply(&b.p)?],
            start: context.bind(
                &FINE_START,
                &[
                    &b.params,
                    &b.state,
                    &b.b,
                    &b.preconditioner,
                    &b.ad,
                    &b.d,
                    &b.r,
                    &b.z,
                    &b.p,
                    &b.terms,
                ],
            )?,
            update: context.bind(
                &FINE_UPDATE,
                &[
                    &b.params,
                    &b.state,
                    &b.p,
                    &b.ad,
                    &b.preconditioner,
                    &b.d,
                    &b.r,
                    &b.z,
                    &b.terms,
                ],
            )?,
            direction: context.bind(&FINE_DIRECTION, &[&b.params, &b.state, &b.z, &b.p])?,
            reduce: context.bind(&FINE_REDUCE, &[&b.params, &b.terms, &b.partials])?,
            scalars: [scalars(0)?, scalars(1)?, scalars(2)?, scalars(3)?],
        })
    }
}

/// The cover's row offsets, all zero where the term is empty.
fn cover_offsets(cover: &crate::register::cover::Cover, vertices: usize) -> Vec<u32> {
    if cover.offsets.is_empty() {
        vec![0; vertices + 1]
    } else {
        cover.offsets.clone()
    }
}
