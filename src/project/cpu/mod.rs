//! CPU twins of the project stage's kernels, one file each with the kernel's name, loop shape and
//! variable names, so each can be read beside its WGSL.

pub(super) mod closest_point;
pub mod project;
pub(super) mod traversal;
pub(super) mod triangle_bounds;
