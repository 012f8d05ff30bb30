//! The point of a triangle nearest to a query point (Ericson 2005, "Real-Time Collision
//! Detection" §5.1.5): the Voronoi region of the triangle (corner, edge or face) that the point
//! projects into, with the parameter of the nearest point there. One definition for f32 (the
//! correspondence twins, which mirror `kernels/closest_point.wgsl`) and f64 (mesh improvement,
//! where marching-cubes slivers make the barycentric denominators tiny and f32 would misplace the
//! nearest point by far more than rounding). The narrow-band distance keeps its own form, the
//! mirror of `kernels/shared/distance.wgsl`, whose tests come in another order.

use std::ops::{Add, Div, Mul, Sub};

use glam::{DVec3, Vec3};

/// The arithmetic the region test needs.
pub trait Scalar:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    const ZERO: Self;
}

impl Scalar for f32 {
    const ZERO: Self = 0.0;
}

impl Scalar for f64 {
    const ZERO: Self = 0.0;
}

/// A 3-vector of some precision.
pub trait Vector: Copy + Sub<Output = Self> {
    type Scalar: Scalar;
    fn dot(self, other: Self) -> Self::Scalar;
}

impl Vector for Vec3 {
    type Scalar = f32;
    fn dot(self, other: Self) -> f32 {
        Vec3::dot(self, other)
    }
}

impl Vector for DVec3 {
    type Scalar = f64;
    fn dot(self, other: Self) -> f64 {
        DVec3::dot(self, other)
    }
}

/// Where on triangle `abc` the point nearest to a query lies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Region<S> {
    /// Corner 0, 1 or 2 (a, b, c).
    Vertex(usize),
    /// Edge 0 (ab), 1 (bc) or 2 (ca), at parameter `s` from its first corner (a, b and a: the
    /// point is `a + s·ab`, `b + s·bc`, `a + s·ac`).
    Edge(usize, S),
    /// Inside the face, at `a + v·ab + w·ac`.
    Face(S, S),
    /// A triangle whose area rounds to zero, where the face region's weights are meaningless.
    Degenerate,
}

/// The region of `abc` nearest to `p`: vertex, edge, then face regions, in Ericson's order.
#[inline(always)]
pub fn region<V: Vector>(p: V, a: V, b: V, c: V) -> Region<V::Scalar> {
    let zero = V::Scalar::ZERO;
    let (ab, ac) = (b - a, c - a);
    let dots = |q: V| (ab.dot(q), ac.dot(q));
    let (d1, d2) = dots(p - a);
    let (d3, d4) = dots(p - b);
    let (d5, d6) = dots(p - c);
    let vc = d1 * d4 - d3 * d2;
    let vb = d5 * d2 - d1 * d6;
    let va = d3 * d6 - d5 * d4;
    let sum = va + vb + vc;
    if d1 <= zero && d2 <= zero {
        Region::Vertex(0)
    } else if d3 >= zero && d4 <= d3 {
        Region::Vertex(1)
    } else if vc <= zero && d1 >= zero && d3 <= zero {
        Region::Edge(0, d1 / (d1 - d3))
    } else if d6 >= zero && d5 <= d6 {
        Region::Vertex(2)
    } else if vb <= zero && d2 >= zero && d6 <= zero {
        Region::Edge(2, d2 / (d2 - d6))
    } else if va <= zero && d4 - d3 >= zero && d5 - d6 >= zero {
        Region::Edge(1, (d4 - d3) / ((d4 - d3) + (d5 - d6)))
    } else if sum > zero {
        Region::Face(vb / sum, vc / sum)
    } else {
        // Also a NaN sum.
        Region::Degenerate
    }
}

/// Distance from `p` to triangle `(a, b, c)`, exact for every triangle, degenerate ones included;
/// computed in f64.
pub fn point_triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let [p, a, b, c] = [p, a, b, c].map(|v| v.as_dvec3());
    p.distance(closest(p, a, b, c)) as f32
}

/// The point of triangle `(a, b, c)` closest to `p`.
fn closest(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    match region(p, a, b, c) {
        Region::Vertex(0) => a,
        Region::Vertex(1) => b,
        Region::Vertex(_) => c,
        Region::Edge(0, s) => a + (b - a) * s,
        Region::Edge(1, s) => b + (c - b) * s,
        Region::Edge(_, s) => a + (c - a) * s,
        Region::Face(v, w) => a + (b - a) * v + (c - a) * w,
        Region::Degenerate => nearest_on_edges(p, a, b, c),
    }
}

/// Closest point on the three edges: the answer for a triangle whose area rounds to zero, where the
/// face region's barycentric weights are meaningless.
fn nearest_on_edges(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let on_segment = |s: DVec3, e: DVec3| {
        let d = e - s;
        let len2 = d.length_squared();
        if len2 == 0.0 {
            s
        } else {
            s + d * ((p - s).dot(d) / len2).clamp(0.0, 1.0)
        }
    };
    [on_segment(a, b), on_segment(b, c), on_segment(c, a)]
        .into_iter()
        .min_by(|x, y| p.distance_squared(*x).total_cmp(&p.distance_squared(*y)))
        .unwrap_or(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_voronoi_region_gives_the_analytic_distance() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0);
        let cases = [
            (Vec3::new(0.5, 0.5, 3.0), 3.0),
            (Vec3::new(-1.0, -1.0, 0.0), 2f32.sqrt()),
            (Vec3::new(3.0, -1.0, 0.0), 2f32.sqrt()),
            (Vec3::new(-1.0, 3.0, 0.0), 2f32.sqrt()),
            (Vec3::new(1.0, -2.0, 0.0), 2.0),
            (Vec3::new(-2.0, 1.0, 0.0), 2.0),
            (Vec3::new(2.0, 2.0, 0.0), 2f32.sqrt()),
            (Vec3::new(1.0, 1.0, 0.0), 0.0),
        ];
        for (p, expected) in cases {
            let d = point_triangle_distance(p, a, b, c);
            assert!((d - expected).abs() < 1e-6, "{p}: {d} vs {expected}");
        }
    }

    #[test]
    fn degenerate_triangles_fall_back_to_edges() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::X * 2.0);
        let d = point_triangle_distance(Vec3::new(1.5, 1.0, 0.0), a, b, c);
        assert!((d - 1.0).abs() < 1e-6);
        let p = Vec3::new(0.0, 0.0, 2.0);
        assert!((point_triangle_distance(p, a, a, a) - 2.0).abs() < 1e-6);
    }
}
