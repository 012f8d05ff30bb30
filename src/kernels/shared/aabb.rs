use glam::Vec3;

use crate::compute::parity::{ParityValue, Scalar};

gpu_struct! {
    mirrors AABB;
    /// Axis-aligned bounding box as kernels read and write it.
    ///
    /// Mirrors `struct Aabb` in `kernels/shared/aabb.wgsl`: WGSL aligns `vec3<f32>` to 16 bytes, so
    /// each corner carries a trailing `u32` that is always 0, which keeps every byte defined and lets
    /// GPU and CPU results be compared bit for bit.
    pub struct Aabb {
        pub min: Vec3,
        pad_min: u32,
        pub max: Vec3,
        pad_max: u32,
    }
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
}

impl ParityValue for Aabb {
    const LANES: &'static [&'static str] = &["min.x", "min.y", "min.z", "max.x", "max.y", "max.z"];
    fn lane(&self, k: usize) -> Scalar {
        Scalar::F32(if k < 3 { self.min[k] } else { self.max[k - 3] })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compute::parity::ParityReport;

    #[test]
    fn aabb_lanes_name_their_corner() {
        let a = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let b = Aabb::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 3.0));
        let report = ParityReport::gpu_vs_cpu("boxes", &[a], &[b]);
        let lanes: Vec<_> = report
            .differences()
            .iter()
            .map(|d| (d.index, d.lane))
            .collect();
        assert_eq!(lanes, [(0, "max.z")]);
        report.assert_max_abs_lt(3.0);
    }
}
