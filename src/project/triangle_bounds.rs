//! Per-triangle axis-aligned bounding boxes, the leaves of a BVH over a target mesh.
//!
//! Kernel: `kernels/triangle_bounds.wgsl`; its CPU twin is `cpu/triangle_bounds.rs`, with the same
//! per-triangle body, and its GPU host `gpu/triangle_bounds.rs`. Min and max are exact in f32, so
//! both backends return identical bits (for finite coordinates, which every validated mesh has).

use glam::Vec3;

use super::cpu::triangle_bounds::triangle_bounds_cpu;
use super::gpu::GpuTriangleBounds;
use super::indices::check_indices;
use crate::compute::{Backend, ComputeError, kernel_time};
use crate::kernels::shared::Aabb;

/// The bounding box of every triangle, in triangle order.
///
/// Fails with [`ComputeError::IndexOutOfRange`] when a triangle references a missing position,
/// and with a GPU error when the GPU backend cannot run the kernel.
pub fn triangle_bounds(
    backend: &Backend,
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> Result<Vec<Aabb>, ComputeError> {
    kernel_time::timed(|| match backend {
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
    })
}
