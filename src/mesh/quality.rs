//! Triangle quality: the measures mesh improvement (paper §4.1: minimum angle 10°) and `eval` use.

use super::IndexedMesh;
use glam::Vec3;
use serde::Serialize;

/// Smallest interior angle of a triangle, in degrees (0 for a degenerate one).
pub fn min_angle_degrees(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let p = [a, b, c];
    (0..3)
        .map(|k| {
            let e1 = p[(k + 1) % 3] - p[k];
            let e2 = p[(k + 2) % 3] - p[k];
            e1.angle_between(e2).to_degrees()
        })
        .fold(f32::INFINITY, f32::min)
        .min(180.0)
}

/// Aspect ratio: longest edge over the altitude onto it, scaled so an equilateral triangle gives 1
/// (∞ for a degenerate one).
pub fn aspect_ratio(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let longest = (b - a).length().max((c - b).length()).max((a - c).length());
    let twice_area = (b - a).cross(c - a).length();
    if twice_area == 0.0 {
        return f32::INFINITY;
    }
    let altitude = twice_area / longest;
    longest / altitude * (3.0f32.sqrt() / 2.0)
}

/// Summary of a mesh's edge lengths and triangle quality.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct QualityStats {
    pub edge_min: f32,
    pub edge_mean: f32,
    pub edge_max: f32,
    pub min_angle: f32,
    pub max_aspect: f32,
    /// Triangles per 10° bucket of minimum angle: [0,10), [10,20), … [50,60].
    pub min_angle_histogram: [usize; 6],
}

impl IndexedMesh {
    pub fn quality(&self) -> QualityStats {
        let edges = self.sorted_edges();
        let (mut lo, mut hi, mut sum, mut count) = (f32::INFINITY, 0.0f32, 0.0f64, 0usize);
        for group in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let l =
                self.positions[group[0].0 as usize].distance(self.positions[group[0].1 as usize]);
            lo = lo.min(l);
            hi = hi.max(l);
            sum += f64::from(l);
            count += 1;
        }
        let mut histogram = [0usize; 6];
        let (mut min_angle, mut max_aspect) = (f32::INFINITY, 0.0f32);
        for tri in &self.triangles {
            let [a, b, c] = tri.map(|v| self.positions[v as usize]);
            let angle = min_angle_degrees(a, b, c);
            min_angle = min_angle.min(angle);
            max_aspect = max_aspect.max(aspect_ratio(a, b, c));
            histogram[((angle / 10.0) as usize).min(5)] += 1;
        }
        QualityStats {
            edge_min: if count == 0 { 0.0 } else { lo },
            edge_mean: if count == 0 {
                0.0
            } else {
                (sum / count as f64) as f32
            },
            edge_max: hi,
            min_angle: if self.triangles.is_empty() {
                0.0
            } else {
                min_angle
            },
            max_aspect,
            min_angle_histogram: histogram,
        }
    }
}
