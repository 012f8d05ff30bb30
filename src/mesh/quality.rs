//! Triangle quality: the measures mesh improvement (paper §4.1: minimum angle 10°) and `eval` use.

use super::IndexedMesh;
use glam::Vec3;
use serde::Serialize;

/// Smallest interior angle of a triangle, in degrees (0 for a degenerate one).
///
/// The smallest angle has the largest cosine, so only the corners whose cosine comes within
/// [`COSINE_MARGIN`] of the largest have their arc cosine taken (usually one of three; the graft's
/// strips evaluate this a million times per loop pair). The result is the minimum over all three
/// corners exactly, ties and rounding included: glam's arc cosine lies within 4.4·10⁻⁷ of the
/// true one over every `f32` in [−1, 1], whose slope is at least 1 in magnitude, so a corner
/// whose cosine lies farther below the largest cannot have the smallest angle. Corners with an
/// edge of no length (a NaN cosine) are skipped as `f32::min` skips their NaN angle.
pub fn min_angle_degrees(a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let p = [a, b, c];
    let edges = |k: usize| (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
    let cosines = [0, 1, 2].map(|k| {
        let (e1, e2) = edges(k);
        e1.dot(e2) / (e1.length_squared() * e2.length_squared()).sqrt()
    });
    let largest = cosines.into_iter().fold(f32::NEG_INFINITY, f32::max);
    (0..3)
        .filter(|&k| cosines[k] >= largest - COSINE_MARGIN)
        .map(|k| {
            let (e1, e2) = edges(k);
            e1.angle_between(e2).to_degrees()
        })
        .fold(f32::INFINITY, f32::min)
        .min(180.0)
}

/// How far below the largest cosine a corner's may lie and still be measured: twenty times the
/// arc cosine's largest error on either side.
const COSINE_MARGIN: f32 = 1.0e-5;

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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every corner's angle measured, the smallest taken: what `min_angle_degrees` must give.
    fn every_corner(a: Vec3, b: Vec3, c: Vec3) -> f32 {
        let p = [a, b, c];
        (0..3)
            .map(|k| (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]))
            .map(f32::to_degrees)
            .fold(f32::INFINITY, f32::min)
            .min(180.0)
    }

    /// Bit for bit the smallest of the three angles, on random triangles and on the cases where
    /// the corners' cosines tie or are missing: equilateral and isosceles ones, slivers, needles,
    /// collinear corners, two or three corners at one place.
    #[test]
    fn the_smallest_angle_is_the_smallest_of_all_three_bit_for_bit() {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32 - 0.5
        };
        let mut triangles = vec![
            [Vec3::ZERO, Vec3::X, Vec3::new(0.5, 0.75f32.sqrt(), 0.0)],
            [Vec3::ZERO, Vec3::X, Vec3::new(0.5, 3.0, 0.0)],
            [Vec3::ZERO, Vec3::X, Vec3::new(0.5, 1e-4, 0.0)],
            [Vec3::ZERO, Vec3::X, Vec3::new(2.0, 1e-7, 0.0)],
            [Vec3::ZERO, Vec3::X, Vec3::X * 3.0],
            [Vec3::ZERO, Vec3::ZERO, Vec3::Y],
            [Vec3::ONE, Vec3::ONE, Vec3::ONE],
        ];
        for _ in 0..100_000 {
            let a = Vec3::new(next(), next(), next());
            let b = Vec3::new(next(), next(), next());
            let c = Vec3::new(next(), next(), next());
            triangles.push([a, b, c]);
            // Nearly isosceles: two cosines within rounding of each other.
            let apex = (a + b) * 0.5 + (b - a).cross(Vec3::Z) * next() * 4.0;
            triangles.push([a, b, apex + Vec3::splat(next() * 1e-6)]);
        }
        for [a, b, c] in triangles {
            assert_eq!(
                min_angle_degrees(a, b, c).to_bits(),
                every_corner(a, b, c).to_bits(),
                "{a} {b} {c}"
            );
        }
    }
}
