//! How far an operation moves the surface: the new faces are sampled and each sample must lie within
//! the limit of the faces they replace. The thesis (§3.2.1) guards flips with the swept volume; a
//! distance bound is scale-free, applies to collapses as well, and bounds the swept volume by
//! distance × area.

use crate::geometry::point_triangle_distance;
use glam::Vec3;

/// True when every sample of `new` lies within `limit` of some face of `old`, where `old[i]` (when it
/// exists) is the face `new[i]` replaces and is tried first. In every face of `new` the edge from
/// corner 0 to corner 1 is new, while its other two edges are old edges or the first edge of another
/// new face; so a face is sampled at its centroid, at the midpoint of its first edge and halfway from
/// its centroid to each corner. Corners are never sampled: every operation keeps them on the old
/// surface.
pub(super) fn within(new: &[[Vec3; 3]], old: &[[Vec3; 3]], limit: f32) -> bool {
    new.iter().enumerate().all(|(i, &[a, b, c])| {
        let g = (a + b + c) / 3.0;
        let samples = [
            g,
            (a + b) * 0.5,
            (g + a) * 0.5,
            (g + b) * 0.5,
            (g + c) * 0.5,
        ];
        samples.iter().all(|&p| {
            let near = |k: usize| {
                let [x, y, z] = old[k];
                point_triangle_distance(p, x, y, z) <= limit
            };
            (i < old.len() && near(i)) || (0..old.len()).any(|k| k != i && near(k))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_flat_retriangulation_moves_nothing_and_a_tent_moves_by_its_samples() {
        let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
        let old = [[a, b, c], [a, c, d]];
        assert!(within(&[[b, d, a], [d, b, c]], &old, 1e-6));
        let apex = Vec3::new(0.5, 0.5, 0.3);
        let tent = [[apex, a, b], [apex, b, c], [apex, c, d], [apex, d, a]];
        // The highest sample is halfway between a centroid (height 0.1) and the apex: 0.2.
        assert!(within(&tent, &old, 0.2 + 1e-6));
        assert!(!within(&tent, &old, 0.2 - 1e-3));
    }
}
