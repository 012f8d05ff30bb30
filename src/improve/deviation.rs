//! How far an operation moves the surface: the new faces are sampled and each sample must lie within
//! the limit of the faces they replace. The thesis (§3.2.1) guards flips with the swept volume; a
//! distance bound is scale-free, applies to collapses as well, and bounds the swept volume by
//! distance × area.

use super::distance::point_triangle_distance;
use glam::Vec3;

/// How far the faces `new` lie from the faces `old` they replace — the largest distance from a sample
/// of `new` to the nearest face of `old` — or `None` when that exceeds `limit`. Samples are each face's
/// centroid, edge midpoints and the points halfway from the centroid to each corner; corners are
/// skipped, as every operation keeps them on the old surface.
pub(super) fn deviation(new: &[[Vec3; 3]], old: &[[Vec3; 3]], limit: f32) -> Option<f32> {
    let mut worst = 0.0f32;
    for &[a, b, c] in new {
        let g = (a + b + c) / 3.0;
        let samples = [
            g,
            (a + b) * 0.5,
            (b + c) * 0.5,
            (c + a) * 0.5,
            (g + a) * 0.5,
            (g + b) * 0.5,
            (g + c) * 0.5,
        ];
        for p in samples {
            let nearest = old
                .iter()
                .map(|&[x, y, z]| point_triangle_distance(p, x, y, z))
                .fold(f32::INFINITY, f32::min);
            if nearest > limit {
                return None;
            }
            worst = worst.max(nearest);
        }
    }
    Some(worst)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_retriangulation_moves_nothing_and_a_bent_one_moves_by_its_bend() {
        let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        let old = [[a, b, c], [a, c, d]];
        assert_eq!(deviation(&[[a, b, d], [b, c, d]], &old, 1e-6), Some(0.0));
        let lifted = Vec3::new(0.5, 0.5, 0.1);
        let bent = [[a, b, lifted], [b, c, lifted], [c, d, lifted], [d, a, lifted]];
        let moved = deviation(&bent, &old, 1.0).unwrap();
        assert!((moved - (0.1 + 0.1 / 3.0) / 2.0).abs() < 1e-6, "{moved}");
        assert_eq!(deviation(&bent, &old, 0.05), None);
    }
}
