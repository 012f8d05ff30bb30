use glam::Vec3;

use super::Bvh;
use super::cpu::project::nearest_hit;
use crate::kernels::shared::{Correspondence, Status};

impl Bvh {
    /// The first hit of the ray `origin + t·direction`, `0 <= t <= max_t` (both faces count),
    /// on the CPU: the single-ray form of [`super::project`], without pruning by normal. `t` is
    /// in units of `|direction|`. `None` when nothing is hit or `direction` is zero or not finite.
    pub fn cast_ray(&self, origin: Vec3, direction: Vec3, max_t: f32) -> Option<Correspondence> {
        if !(origin.is_finite() && direction.is_finite()) || direction == Vec3::ZERO {
            return None;
        }
        let hit = nearest_hit(self, origin, direction, 0.0, max_t)?;
        let slot = hit.slot as usize;
        Some(Correspondence::new(
            origin + direction * hit.t,
            hit.t,
            self.normals()[slot].blend(hit.weights),
            self.triangles()[slot].id,
            Vec3::from_array(hit.weights),
            Status::Accepted,
        ))
    }
}
