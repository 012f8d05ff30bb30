//! CPU twins of the fine stage's kernels (`kernels/fine_*.wgsl`), one file each with the kernel's
//! name, loop shape and variable names, so each can be read beside its WGSL. Each function is one
//! dispatch: its closure is one kernel invocation.

pub(super) mod fine_apply;
pub(super) mod fine_cover;
pub(super) mod fine_direction;
pub(super) mod fine_reduce;
pub(super) mod fine_scalars;
pub(super) mod fine_start;
pub(super) mod fine_system;
pub(super) mod fine_update;
