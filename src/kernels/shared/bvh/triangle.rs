use glam::Vec3;

gpu_struct! {
    mirrors BVH;
    /// A target triangle in BVH leaf order: its corners in the target's winding and its index in the
    /// target mesh.
    ///
    /// Mirrors `struct BvhTriangle` in `kernels/shared/bvh.wgsl`. Corners are stored by value rather
    /// than as vertex indices so a leaf test reads one contiguous record; the padding words are 0.
    pub struct BvhTriangle {
        pub a: Vec3,
        /// Index of the triangle in the target mesh.
        pub id: u32,
        pub b: Vec3,
        pad_b: u32,
        pub c: Vec3,
        pad_c: u32,
    }
}

impl BvhTriangle {
    pub fn new([a, b, c]: [Vec3; 3], id: u32) -> Self {
        Self {
            a,
            id,
            b,
            pad_b: 0,
            c,
            pad_c: 0,
        }
    }

    pub fn corners(&self) -> [Vec3; 3] {
        [self.a, self.b, self.c]
    }
}

gpu_struct! {
    mirrors BVH;
    /// Three unit vectors attached to a triangle in BVH leaf order: one per corner (`a`, `b`, `c`) or
    /// one per edge (`a` for edge ab, `b` for bc, `c` for ca).
    ///
    /// Mirrors `struct NormalTriple` in `kernels/shared/bvh.wgsl`; the padding words are 0.
    pub struct NormalTriple {
        pub a: Vec3,
        pad_a: u32,
        pub b: Vec3,
        pad_b: u32,
        pub c: Vec3,
        pad_c: u32,
    }
}

impl NormalTriple {
    pub fn new([a, b, c]: [Vec3; 3]) -> Self {
        Self {
            a,
            pad_a: 0,
            b,
            pad_b: 0,
            c,
            pad_c: 0,
        }
    }

    /// `wa·a + wb·b + wc·c`, normalised (zero when the blend vanishes); the same operations as
    /// `blend` in `kernels/shared/bvh.wgsl`.
    pub fn blend(&self, [wa, wb, wc]: [f32; 3]) -> Vec3 {
        let n = self.a * wa + self.b * wb + self.c * wc;
        let length2 = n.dot(n);
        if length2 > 0.0 {
            n / length2.sqrt()
        } else {
            Vec3::ZERO
        }
    }
}

gpu_struct! {
    mirrors BVH;
    /// The angle-weighted pseudo-normals of a triangle's corners and edges (Bærentzen & Aanæs 2005):
    /// `dot(p − q, pseudo-normal of the feature holding q)` has the sign of `p`'s side of a closed,
    /// consistently oriented surface, where `q` is the closest surface point to `p`, even when `q` is a
    /// vertex or lies on an edge, where the face normal alone can give the wrong side.
    ///
    /// Mirrors `struct PseudoNormals` in `kernels/shared/bvh.wgsl`.
    pub struct PseudoNormals {
        /// At corners a, b, c: the angle-weighted mean of the incident face normals.
        pub vertices: NormalTriple,
        /// On edges ab, bc, ca: the mean of the two incident face normals.
        pub edges: NormalTriple,
    }
}
