//! CPU twins of the grid kernels, one file each with the kernel's name, loop shape and variable
//! names, so each can be read beside its WGSL; `distance_tiled.rs` is a variant of the distance
//! twin, tested against it.

pub mod distance;
pub mod distance_tiled;
pub mod rasterize;
pub mod sweep;
