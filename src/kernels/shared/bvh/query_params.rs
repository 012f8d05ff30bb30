/// Largest closest-point search radius: its square, 10³⁶, is still a finite f32.
const MAX_CLOSEST_DISTANCE: f32 = 1e18;

gpu_struct! {
    mirrors BVH;
    /// Per-dispatch parameters of the query kernels.
    ///
    /// Mirrors `struct QueryParams` in `kernels/shared/bvh.wgsl`.
    pub struct QueryParams {
        /// Largest `|t|` (projection) or distance (closest point) searched, in the target's units.
        pub max_distance: f32,
        /// Hits whose interpolated normal has a smaller dot product with the source normal are
        /// pruned.
        pub cos_max_angle: f32,
        pad: [u32; 2],
    }
}

impl QueryParams {
    pub fn new(max_distance: f32, cos_max_angle: f32) -> Self {
        Self {
            max_distance,
            cos_max_angle,
            pad: [0; 2],
        }
    }

    /// Parameters of a closest-point search up to `max_distance` (in the target's units).
    ///
    /// Kernels square the bound, so it is capped where the square stays finite.
    pub fn closest(max_distance: f32) -> Self {
        Self::new(max_distance.min(MAX_CLOSEST_DISTANCE), -2.0)
    }
}
