//! CPU twin of `kernels/triangle_bounds.wgsl`: the bounding box of every triangle.

use glam::Vec3;
use rayon::prelude::*;

use crate::kernels::shared::Aabb;

/// CPU twin of `kernels/triangle_bounds.wgsl`: one closure call per kernel invocation `t`.
pub(in crate::project) fn triangle_bounds_cpu(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
) -> Vec<Aabb> {
    let load_position = |v: u32| positions[v as usize];
    triangles
        .par_iter()
        .map(|tri| {
            let a = load_position(tri[0]);
            let b = load_position(tri[1]);
            let c = load_position(tri[2]);
            Aabb::new(a.min(b).min(c), a.max(b).max(c))
        })
        .collect()
}
