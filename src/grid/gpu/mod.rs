//! GPU hosts of the grid kernels: buffers, dispatch and readback, one file per kernel.

mod distance;
mod rasterize;
mod sweep;

pub(crate) use distance::GpuDistance;
pub use rasterize::GpuRasterize;
pub use sweep::GpuSweep;
