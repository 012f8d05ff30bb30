//! Per-triangle axis-aligned bounding boxes, the leaves of a BVH over a target mesh.
//!
//! Kernel: `kernels/triangle_bounds.wgsl`. [`triangle_bounds_cpu`] is its twin, with the same
//! per-triangle body. Min and max are exact in f32, so both backends return identical bits (for
//! finite coordinates, which every validated mesh has).

use glam::Vec3;
use rayon::prelude::*;

use super::{Aabb, Backend, ComputeError, GpuContext};

/// The bounding box of every triangle, in triangle order.
///
/// Fails with [`ComputeError::IndexOutOfRange`] when a triangle references a missing position,
/// and with a GPU error when the GPU backend cannot run the kernel.
pub fn triangle_bounds(
    backend: &Backend,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> Result<Vec<Aabb>, ComputeError> {
    match backend {
        Backend::Cpu => {
            check_indices(positions.len(), triangles)?;
            Ok(triangle_bounds_cpu(positions, triangles))
        }
        Backend::Gpu(context) => {
            // `upload` checks the indices.
            let job = GpuTriangleBounds::upload(context, positions, triangles)?;
            job.dispatch(context)?;
            job.read(context)
        }
    }
}

/// CPU twin of `kernels/triangle_bounds.wgsl`: one closure call per kernel invocation `t`.
fn triangle_bounds_cpu(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Aabb> {
    let load_position = |v: u32| positions[v as usize];
    triangles
        .par_iter()
        .map(|tri| {
            let a = load_position(tri[0]);
            let b = load_position(tri[1]);
            let c = load_position(tri[2]);
            Aabb::new(a.min(b).min(c), a.max(b).max(c))
        })
        .collect()
}

/// The first triangle (in order, whatever the thread count) with an index past `count`.
fn check_indices(count: usize, triangles: &[[u32; 3]]) -> Result<(), ComputeError> {
    let bad = triangles
        .par_iter()
        .enumerate()
        .find_first(|(_, tri)| tri.iter().any(|&v| v as usize >= count));
    match bad {
        None => Ok(()),
        Some((triangle, tri)) => Err(ComputeError::IndexOutOfRange {
            triangle,
            vertex: tri
                .iter()
                .copied()
                .find(|&v| v as usize >= count)
                .unwrap_or(tri[0]),
            count,
        }),
    }
}

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
                "triangle_bounds",
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
