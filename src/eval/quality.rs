//! Triangle quality of a tracked frame: the minimum-angle criterion mesh improvement enforces (paper
//! §4.1: 10°) and the aspect ratio, as histograms.

use crate::geometry::{ANGLE_BUCKETS, bucket};
use crate::mesh::{IndexedMesh, aspect_ratio, min_angle_degrees};
use serde::Serialize;

/// Upper ends of the aspect-ratio buckets (1 = equilateral); the last bucket (≥ 10) is open.
pub const ASPECT_BUCKETS: [f32; 5] = [1.5, 2.0, 3.0, 5.0, 10.0];

/// The triangle quality of one frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TriangleQuality {
    /// Smallest interior angle of any triangle (degrees).
    pub min_angle: f32,
    /// Fraction of triangles whose smallest angle is at least the threshold.
    pub above_threshold: f64,
    /// Largest aspect ratio of any triangle.
    pub max_aspect: f32,
    /// Triangles per `ANGLE_BUCKETS` bucket (one more for the rest).
    pub min_angle_histogram: Vec<usize>,
    /// Triangles per `ASPECT_BUCKETS` bucket (one more for the rest).
    pub aspect_histogram: Vec<usize>,
}

/// Measures every triangle of `mesh`; `threshold` is the minimum angle (degrees) counted as good.
pub fn triangle_quality(mesh: &IndexedMesh, threshold: f32) -> TriangleQuality {
    let mut out = TriangleQuality {
        min_angle: if mesh.triangles.is_empty() {
            0.0
        } else {
            f32::INFINITY
        },
        above_threshold: 1.0,
        max_aspect: 0.0,
        min_angle_histogram: vec![0; ANGLE_BUCKETS.len() + 1],
        aspect_histogram: vec![0; ASPECT_BUCKETS.len() + 1],
    };
    let mut above = 0usize;
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|v| mesh.positions[v as usize]);
        let angle = min_angle_degrees(a, b, c);
        let aspect = aspect_ratio(a, b, c);
        out.min_angle = out.min_angle.min(angle);
        out.max_aspect = out.max_aspect.max(aspect);
        above += usize::from(angle >= threshold);
        out.min_angle_histogram[bucket(&ANGLE_BUCKETS, angle)] += 1;
        out.aspect_histogram[bucket(&ASPECT_BUCKETS, aspect)] += 1;
    }
    if !mesh.triangles.is_empty() {
        out.above_threshold = above as f64 / mesh.triangles.len() as f64;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn an_icosahedron_is_all_equilateral_and_a_sliver_is_flagged() {
        let icosahedron = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 0);
        let q = triangle_quality(&icosahedron, 10.0);
        assert!((q.min_angle - 60.0).abs() < 1e-3);
        assert!((q.max_aspect - 1.0).abs() < 1e-4);
        assert_eq!(q.above_threshold, 1.0);
        assert_eq!(q.min_angle_histogram[ANGLE_BUCKETS.len()], 20);
        assert_eq!(q.aspect_histogram[0], 20);

        let sliver = IndexedMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(0.5, 0.02, 0.0)],
            vec![[0, 1, 2]],
        );
        let q = triangle_quality(&sliver, 10.0);
        assert_eq!(q.above_threshold, 0.0);
        assert_eq!(q.min_angle_histogram[1], 1);
        assert_eq!(q.aspect_histogram[5], 1);
    }
}
