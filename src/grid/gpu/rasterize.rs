//! GPU host of `kernels/rasterize.wgsl`: its buffers, upload, dispatch and readback kept apart so each can be timed on
//! its own (see `benches/grid.rs`).

use rayon::prelude::*;

use crate::compute::GpuContext;
use crate::grid::RasterError;
use crate::grid::lattice::LatticeMesh;
use crate::grid::predicates::candidate_counts;
use crate::kernels::RASTERIZE;
use crate::kernels::shared::GridCrossing;

/// A mesh uploaded for `kernels/rasterize.wgsl`, with room for every candidate to cross.
#[derive(Debug)]
pub struct GpuRasterize {
    buffers: Option<Buffers>,
}

#[derive(Debug)]
struct Buffers {
    points: wgpu::Buffer,
    triangles: wgpu::Buffer,
    offsets: wgpu::Buffer,
    crossings: wgpu::Buffer,
    count: wgpu::Buffer,
    candidates: u32,
}

impl GpuRasterize {
    /// Every crossing of `mesh`, by the kernel: upload, dispatch, read back.
    pub fn run(context: &GpuContext, mesh: &LatticeMesh) -> Result<Vec<GridCrossing>, RasterError> {
        let job = Self::upload(context, mesh)?;
        job.dispatch(context)?;
        job.read(context)
    }

    /// Uploads the lattice mesh and the per-triangle candidate offsets (a prefix sum over the
    /// triangles' cell ranges, computed here).
    pub fn upload(context: &GpuContext, mesh: &LatticeMesh) -> Result<Self, RasterError> {
        let counts: Vec<u64> = (0..mesh.triangles().len())
            .into_par_iter()
            .map(|t| {
                let (lo, hi) = mesh.cell_range(t);
                candidate_counts(lo, hi).iter().sum()
            })
            .collect();
        let mut offsets = Vec::with_capacity(counts.len() + 1);
        let mut total = 0u64;
        for c in counts {
            offsets
                .push(u32::try_from(total).map_err(|_| RasterError::TooManyItems(total as usize))?);
            total += c;
        }
        let candidates =
            u32::try_from(total).map_err(|_| RasterError::TooManyItems(total as usize))?;
        offsets.push(candidates);
        if candidates == 0 {
            return Ok(Self { buffers: None });
        }
        Ok(Self {
            buffers: Some(Buffers {
                points: context.upload("points", mesh.points())?,
                triangles: context.upload("triangles", mesh.triangles())?,
                offsets: context.upload("offsets", &offsets)?,
                crossings: context.output::<GridCrossing>("crossings", candidates as usize)?,
                count: context.upload("count", &[0u32])?,
                candidates,
            }),
        })
    }

    /// Submits the kernel; [`Self::read`] waits for it. Each dispatch appends to the output, so a
    /// job is dispatched once.
    pub fn dispatch(&self, context: &GpuContext) -> Result<(), RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(());
        };
        context.dispatch(
            &RASTERIZE,
            &[&b.points, &b.triangles, &b.offsets, &b.crossings, &b.count],
            u64::from(b.candidates),
        )?;
        Ok(())
    }

    /// The crossings, in the order the GPU appended them.
    pub fn read(&self, context: &GpuContext) -> Result<Vec<GridCrossing>, RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(Vec::new());
        };
        let count = context.read_back::<u32>(&b.count, 1)?[0].min(b.candidates);
        Ok(context.read_back::<GridCrossing>(&b.crossings, count as usize)?)
    }
}
