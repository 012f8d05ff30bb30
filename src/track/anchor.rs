//! Where the tracker's coordinates start. Single precision resolves about 6·10⁻⁸ of a
//! coordinate's magnitude: a cache placed far from the world's origin (a tank modelled in
//! centimetres 40 m away, a thousand cells from the origin) has every point the topology step
//! constructs on a cell face rounded by a sizeable fraction of its distance to the nearest vertex,
//! so its patches come out with slivers of zero area that fail the step's check, and each retry
//! re-samples a wider region (the dam break shifted by 1,000: frame 1's region grew to 11,689
//! cells, against 484 unshifted). The grid's placement also moves with the world's origin. So the
//! tracker works relative to an anchor near the first frame, fixed for the run, and every frame it
//! writes is in world coordinates.
//!
//! Near the world's origin the anchor is 0 and nothing changes: coordinates are the world's own.

use glam::Vec3;

use crate::geometry::bounds;
use crate::mesh::IndexedMesh;

/// The anchor of a run whose first frame is `first`: per axis, the centre of its bounding box
/// rounded to a multiple of the smallest power of two at least the box's diagonal. A frame whose
/// centre lies within half that power of the origin keeps anchor 0; shifting the input by a
/// multiple of the power shifts the anchor by the same amount. Powers of two keep the subtraction
/// exact for every coordinate within a factor of two of the anchor.
pub fn anchor_of(first: &IndexedMesh) -> Vec3 {
    let (lo, hi) = bounds(&first.positions);
    let diagonal = (hi - lo).length();
    if !(diagonal.is_finite() && diagonal > 0.0) {
        return Vec3::ZERO;
    }
    let power = 2f32.powi(diagonal.log2().ceil() as i32);
    let centre = (lo + hi) * 0.5;
    // Adding 0 turns a rounded −0 into 0.
    (centre / power).round() * power + Vec3::ZERO
}

/// `mesh` moved so that `anchor` is its origin.
pub fn localized(mesh: &IndexedMesh, anchor: Vec3) -> IndexedMesh {
    localize(mesh.clone(), anchor)
}

/// [`localized`], in place.
pub fn localize(mut mesh: IndexedMesh, anchor: Vec3) -> IndexedMesh {
    if anchor != Vec3::ZERO {
        for p in &mut mesh.positions {
            *p -= anchor;
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_near_the_origin_keeps_world_coordinates_and_a_shifted_one_moves_its_anchor() {
        let near = IndexedMesh::icosphere(Vec3::new(3.0, -2.0, 1.0), 4.0, 1);
        assert_eq!(anchor_of(&near), Vec3::ZERO);
        // The sphere's box has a diagonal of about 13.9: the power is 16.
        let shift = Vec3::new(4096.0, -1024.0, 160.0);
        let far = localized(&near, -shift);
        assert_eq!(anchor_of(&far), shift);
        // Back near the origin, within what shifting the sphere rounded.
        let back = localized(&far, anchor_of(&far));
        for (a, b) in back.positions.iter().zip(&near.positions) {
            assert!((*a - *b).abs().max_element() <= 4096.0 * f32::EPSILON);
        }
        assert_eq!(
            anchor_of(&IndexedMesh::new(Vec::new(), Vec::new())),
            Vec3::ZERO
        );
    }
}
