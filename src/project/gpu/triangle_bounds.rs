//! GPU host of `kernels/triangle_bounds.wgsl`.

use glam::Vec3;

use crate::compute::{ComputeError, GpuContext};
use crate::kernels::TRIANGLE_BOUNDS;
use crate::kernels::shared::Aabb;
use crate::project::indices::check_indices;

/// The kernel's buffers on the GPU, split into upload, dispatch and readback so each step can be
/// timed on its own (see `benches/triangle_bounds.rs`).
///
/// Positions are uploaded as they are (`Vec3` is three packed f32, read in WGSL as
/// `array<f32, 3>`), so no padded copy is made on the host. Triangles run in chunks small enough
/// that each chunk's triangles and boxes fit one storage binding (128 MiB, about 4.2 M boxes, on
/// GPUs at the WebGPU minimum); positions are bound whole.
#[derive(Debug)]
pub struct GpuTriangleBounds {
    positions: wgpu::Buffer,
    chunks: Vec<Chunk>,
}

/// One run of consecutive triangles and the boxes the kernel writes for them.
#[derive(Debug)]
struct Chunk {
    triangles: wgpu::Buffer,
    bounds: wgpu::Buffer,
    count: usize,
}

impl GpuTriangleBounds {
    pub fn upload(
        context: &GpuContext,
        positions: &[Vec3],
        triangles: &[[u32; 3]],
    ) -> Result<Self, ComputeError> {
        check_indices(positions.len(), triangles)?;
        let chunk_len = context
            .max_binding_len::<Aabb>()
            .min(context.max_binding_len::<[u32; 3]>());
        let chunks = triangles
            .chunks(chunk_len)
            .map(|chunk| {
                Ok(Chunk {
                    triangles: context.upload("triangles", chunk)?,
                    bounds: context.output::<Aabb>("bounds", chunk.len())?,
                    count: chunk.len(),
                })
            })
            .collect::<Result<_, ComputeError>>()?;
        Ok(Self {
            positions: context.upload("positions", positions)?,
            chunks,
        })
    }

    /// Submits the kernel over every chunk; [`Self::read`] or [`GpuContext::wait`] waits for it.
    pub fn dispatch(&self, context: &GpuContext) -> Result<(), ComputeError> {
        for chunk in &self.chunks {
            context.dispatch(
                &TRIANGLE_BOUNDS,
                &[&self.positions, &chunk.triangles, &chunk.bounds],
                chunk.count as u64,
            )?;
        }
        Ok(())
    }

    /// The boxes of all chunks, in triangle order.
    pub fn read(&self, context: &GpuContext) -> Result<Vec<Aabb>, ComputeError> {
        let mut bounds = Vec::with_capacity(self.chunks.iter().map(|c| c.count).sum());
        for chunk in &self.chunks {
            bounds.extend(context.read_back::<Aabb>(&chunk.bounds, chunk.count)?);
        }
        Ok(bounds)
    }
}
