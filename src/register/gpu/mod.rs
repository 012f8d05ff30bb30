//! GPU host of the fine stage's kernels (`kernels/fine_*.wgsl`): buffers, dispatch sequence and
//! readback of the whole solve.

mod fine_solve;

pub use fine_solve::GpuFineSolve;
