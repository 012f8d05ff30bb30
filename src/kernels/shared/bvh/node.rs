gpu_struct! {
    mirrors BVH;
    /// One node of the flattened 4-wide BVH that both the CPU traversal and the WGSL kernels read.
    ///
    /// Mirrors `struct BvhNode` in `kernels/shared/bvh.wgsl`. The four children's boxes are stored
    /// axis by axis (`min_x[k]` … `max_z[k]` for child `k`), so one SIMD step tests all four; with
    /// 128 bytes aligned to 64, a node is two whole cache lines.
    #[repr(align(64))]
    pub struct BvhNode {
        pub min_x: [f32; 4],
        pub min_y: [f32; 4],
        pub min_z: [f32; 4],
        pub max_x: [f32; 4],
        pub max_y: [f32; 4],
        pub max_z: [f32; 4],
        /// Per child: the node index of an interior child, the first triangle slot of a leaf.
        pub child: [u32; 4],
        /// Per child: 0 for an interior node, the number of triangles of a leaf, or
        /// [`BvhNode::EMPTY`] for an unused slot.
        pub count: [u32; 4],
    }
}

/// One child of a node, as [`BvhNode::children`] lists it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BvhChild {
    Node { index: u32 },
    Leaf { first: u32, count: u32 },
}

impl BvhNode {
    /// `count` of an unused child slot (`EMPTY_CHILD` in `kernels/shared/bvh.wgsl`).
    pub const EMPTY: u32 = u32::MAX;

    /// A node whose four slots are all unused.
    pub const fn empty() -> Self {
        Self {
            min_x: [0.0; 4],
            min_y: [0.0; 4],
            min_z: [0.0; 4],
            max_x: [0.0; 4],
            max_y: [0.0; 4],
            max_z: [0.0; 4],
            child: [0; 4],
            count: [Self::EMPTY; 4],
        }
    }

    /// The box of child `k`, as (min, max).
    pub fn bounds(&self, k: usize) -> ([f32; 3], [f32; 3]) {
        (
            [self.min_x[k], self.min_y[k], self.min_z[k]],
            [self.max_x[k], self.max_y[k], self.max_z[k]],
        )
    }

    /// The used child slots, in slot order, with their index `k`.
    pub fn children(&self) -> impl Iterator<Item = (usize, BvhChild)> + '_ {
        (0..4).filter_map(|k| match self.count[k] {
            Self::EMPTY => None,
            0 => Some((
                k,
                BvhChild::Node {
                    index: self.child[k],
                },
            )),
            count => Some((
                k,
                BvhChild::Leaf {
                    first: self.child[k],
                    count,
                },
            )),
        })
    }
}
