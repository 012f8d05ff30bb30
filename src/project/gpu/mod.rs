//! GPU hosts of the project stage's kernels: buffers, dispatch and readback, one file per
//! dispatcher (`query.rs`, `triangle_bounds.rs` beside this folder).

mod bvh;
mod query;
mod triangle_bounds;

pub use bvh::GpuBvh;
pub use query::GpuQueries;
pub use triangle_bounds::GpuTriangleBounds;
