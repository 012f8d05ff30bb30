//! Where the data-parallel stages run: a [`Backend`] is either the CPU (rayon) or a wgpu device.
//!
//! This is the ground floor: it runs whatever kernel it is handed ([`KernelInfo`]) and imports no
//! stage. The kernels themselves, their CPU twins and the structs they share are listed in
//! `crate::kernels`; the [`parity`] harness compares a kernel's output with its twin's. Kernel
//! outputs are exact where the arithmetic allows (min/max, integer counts), so the two backends
//! agree bit for bit there.

mod backend;
mod context;
mod dispatch;
mod error;
mod kernel;
pub mod kernel_time;
pub mod parity;

pub use backend::{Backend, BackendChoice};
pub use context::{Batch, Bound, GpuContext};
pub use error::{ComputeError, LAVAPIPE_HINT};
pub use kernel::{Access, Binding, GpuStructLayout, KernelInfo, SharedWgsl};
