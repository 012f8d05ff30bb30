//! GPU host of `kernels/sweep.wgsl`: its buffers, upload, dispatch and readback kept apart so each can be timed on its
//! own (see `benches/grid.rs`).

use crate::compute::GpuContext;
use crate::grid::RasterError;
use crate::grid::sparse::Crossings;
use crate::kernels::SWEEP;
use crate::kernels::shared::WindingRun;

/// Sorted crossings uploaded for `kernels/sweep.wgsl`, with one run slot per crossing.
#[derive(Debug)]
pub struct GpuSweep {
    buffers: Option<Buffers>,
}

#[derive(Debug)]
struct Buffers {
    crossings: wgpu::Buffer,
    starts: wgpu::Buffer,
    runs: wgpu::Buffer,
    lines: usize,
    slots: usize,
}

impl GpuSweep {
    /// The winding runs of `crossings`, by the kernel: upload, dispatch, read back.
    pub fn run(
        context: &GpuContext,
        crossings: &Crossings,
    ) -> Result<Vec<WindingRun>, RasterError> {
        let job = Self::upload(context, crossings)?;
        job.dispatch(context)?;
        job.read(context)
    }

    pub fn upload(context: &GpuContext, crossings: &Crossings) -> Result<Self, RasterError> {
        if crossings.is_empty() {
            return Ok(Self { buffers: None });
        }
        Ok(Self {
            buffers: Some(Buffers {
                crossings: context.upload("crossings", crossings.all())?,
                starts: context.upload("starts", crossings.index().starts())?,
                runs: context.output::<WindingRun>("runs", crossings.len())?,
                lines: crossings.index().len(),
                slots: crossings.len(),
            }),
        })
    }

    /// Submits the kernel; [`Self::read`] waits for it.
    pub fn dispatch(&self, context: &GpuContext) -> Result<(), RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(());
        };
        context.dispatch(&SWEEP, &[&b.crossings, &b.starts, &b.runs], b.lines as u64)?;
        Ok(())
    }

    /// One slot per crossing, in crossing order.
    pub fn read(&self, context: &GpuContext) -> Result<Vec<WindingRun>, RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(Vec::new());
        };
        Ok(context.read_back::<WindingRun>(&b.runs, b.slots)?)
    }
}
