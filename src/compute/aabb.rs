use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::registry::{GpuStructLayout, SharedWgsl};

/// Axis-aligned bounding box as kernels read and write it.
///
/// Mirrors `struct Aabb` in `kernels/shared/aabb.wgsl`: WGSL aligns `vec3<f32>` to 16 bytes, so
/// each corner carries a trailing `u32` that is always 0, which keeps every byte defined and lets
/// GPU and CPU results be compared bit for bit.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Aabb {
    pub min: Vec3,
    pad_min: u32,
    pub max: Vec3,
    pad_max: u32,
}

impl Aabb {
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self {
            min,
            pad_min: 0,
            max,
            pad_max: 0,
        }
    }

    /// The layout the WGSL mirror must have, checked against naga in `tests/kernels_validate.rs`.
    pub const LAYOUT: GpuStructLayout = GpuStructLayout {
        name: "Aabb",
        wgsl: &SharedWgsl::AABB,
        size: size_of::<Self>(),
        members: &[
            ("min", core::mem::offset_of!(Self, min)),
            ("pad_min", core::mem::offset_of!(Self, pad_min)),
            ("max", core::mem::offset_of!(Self, max)),
            ("pad_max", core::mem::offset_of!(Self, pad_max)),
        ],
    };
}
