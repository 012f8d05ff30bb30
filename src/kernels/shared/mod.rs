//! Rust mirrors of the structs in `kernels/shared/`, one file (or folder) per WGSL file: plain
//! `#[repr(C)]` + `bytemuck::Pod` data that both backends read and write, with the layout each must
//! have ([`GPU_STRUCTS`](super::GPU_STRUCTS), compared with naga's in `tests/kernels_validate.rs`).
//! The stages add their behaviour in `impl` blocks of their own; this module imports none of them.

/// Declares a struct mirrored in WGSL together with its `LAYOUT`, so each member is named once.
macro_rules! gpu_struct {
    (
        mirrors $wgsl:ident;
        $(#[$attr:meta])*
        $vis:vis struct $name:ident {
            $($(#[$field_attr:meta])* $field_vis:vis $field:ident: $ty:ty),* $(,)?
        }
    ) => {
        #[repr(C)]
        #[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        $(#[$attr])*
        $vis struct $name {
            $($(#[$field_attr])* $field_vis $field: $ty),*
        }

        impl $name {
            /// The layout the WGSL mirror must have, checked against naga in
            /// `tests/kernels_validate.rs`.
            pub const LAYOUT: $crate::compute::GpuStructLayout = $crate::compute::GpuStructLayout {
                name: stringify!($name),
                wgsl: &$crate::compute::SharedWgsl::$wgsl,
                size: size_of::<Self>(),
                members: &[$((stringify!($field), core::mem::offset_of!(Self, $field))),*],
            };
        }
    };
}

mod aabb;
mod bvh;
mod crossing;
mod distance;
mod fine;
mod lattice;

pub use aabb::Aabb;
pub use bvh::{
    BvhChild, BvhNode, BvhTriangle, Correspondence, NormalTriple, PseudoNormals, QueryParams,
    Status,
};
pub use crossing::{ENTER_BIT, GridCrossing, WindingRun};
pub use distance::{
    BandChunk, BandTile, DistanceParams, GATHER_CAPACITY, Nearest, PLANE_SLACK, TreeNode,
    TreeTriangle, TriangleBox,
};
pub use fine::{
    CgState, FineParams, FineTarget, PHASE_ALPHA, PHASE_BEGIN, PHASE_BETA, PHASE_NORM, REDUCE_CHUNK,
};
pub use lattice::{CELL_UNITS, FRACTION_BITS, LatticePoint, MAX_CELL_INDEX, MAX_TRIANGLE_SPAN};
