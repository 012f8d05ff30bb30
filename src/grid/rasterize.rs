//! Rasterization: every crossing of a triangle with a grid edge (thesis §3.4.2, paper §4.3).
//!
//! Kernel: `kernels/rasterize.wgsl`, its CPU twin `cpu/rasterize.rs`, its GPU host
//! `gpu/rasterize.rs`. Both backends walk the same candidates: for each triangle, each
//! axis, the grid lines through the triangle's cell range (the lines strictly inside its projected
//! bounding box, row by row), and decide each with [`line_crossing`], whose exact predicates make the
//! two backends agree on every crossing, its grid edge and its direction. The crossings are then
//! sorted into lines ([`Crossings`]), which also makes their order independent of GPU scheduling.

use super::RasterError;
use super::cpu::rasterize::rasterize_cpu;
use super::gpu::GpuRasterize;
use super::lattice::LatticeMesh;
use super::sparse::Crossings;
use crate::compute::{Backend, kernel_time};

/// Every grid-edge crossing of `mesh`, grouped by grid line.
///
/// Fails only when the GPU backend cannot run the kernel.
pub fn rasterize(backend: &Backend, mesh: &LatticeMesh) -> Result<Crossings, RasterError> {
    let crossings = kernel_time::timed(|| match backend {
        Backend::Cpu => Ok(rasterize_cpu(mesh)),
        Backend::Gpu(context) => GpuRasterize::run(context, mesh),
    })?;
    Ok(Crossings::from_unsorted(crossings))
}
