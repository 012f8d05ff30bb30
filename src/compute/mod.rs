//! Where the data-parallel stages run: a [`Backend`] is either the CPU (rayon) or a wgpu device.
//!
//! Every kernel in `kernels/` is listed in [`registry::KERNELS`] together with its CPU twin, a
//! Rust function with the same name and loop shape (vello's `shader/<stage>.wgsl` beside
//! `src/cpu/<stage>.rs`), so the two can be read side by side and compared by the [`parity`]
//! harness. Kernel outputs are exact where the arithmetic allows (min/max, integer counts), so the
//! two backends agree bit for bit there.

mod aabb;
mod backend;
mod context;
mod dispatch;
mod error;
pub mod parity;
pub mod registry;
mod triangle_bounds;

pub use aabb::Aabb;
pub use backend::{Backend, BackendChoice};
pub use context::GpuContext;
pub use error::{ComputeError, LAVAPIPE_HINT};
pub use triangle_bounds::{GpuTriangleBounds, triangle_bounds};
