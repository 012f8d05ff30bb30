use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use crate::compute::registry::{GpuStructLayout, SharedWgsl};

/// One node of the flattened BVH that both the CPU traversal and `kernels/project.wgsl` read.
///
/// Mirrors `struct BvhNode` in `kernels/shared/bvh.wgsl`. The two children of an interior node are
/// stored side by side (`index`, `index + 1`), so one node array with 32-byte entries serves both
/// backends and a traversal step touches one 64-byte pair.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub min: Vec3,
    /// Leaf: the first of its triangle slots. Interior: the left child; the right one follows it.
    pub index: u32,
    pub max: Vec3,
    /// Number of triangles of a leaf; 0 marks an interior node.
    pub count: u32,
}

impl BvhNode {
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    /// The layout the WGSL mirror must have, checked against naga in `tests/kernels_validate.rs`.
    pub const LAYOUT: GpuStructLayout = GpuStructLayout {
        name: "BvhNode",
        wgsl: &SharedWgsl::BVH,
        size: size_of::<Self>(),
        members: &[
            ("min", core::mem::offset_of!(Self, min)),
            ("index", core::mem::offset_of!(Self, index)),
            ("max", core::mem::offset_of!(Self, max)),
            ("count", core::mem::offset_of!(Self, count)),
        ],
    };
}

/// Two sibling nodes, the unit of storage: 64 bytes aligned to 64, so a traversal step that tests
/// both children of a node reads exactly one cache line.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub(super) struct NodePair(pub [BvhNode; 2]);
