//! Exact point–triangle distance (Ericson, "Real-Time Collision Detection" §5.1.5): the closest point
//! is found by the Voronoi region of the triangle the point projects into, so it is exact for every
//! triangle, degenerate ones included. The work is done in f64: marching-cubes slivers make the
//! barycentric denominators tiny, and f32 would misplace the closest point by far more than rounding.

use glam::{DVec3, Vec3};

/// Distance from `p` to triangle `(a, b, c)`.
pub fn point_triangle_distance(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f32 {
    let [p, a, b, c] = [p, a, b, c].map(|v| v.as_dvec3());
    p.distance(closest(p, a, b, c)) as f32
}

/// The point of triangle `(a, b, c)` closest to `p`.
fn closest(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom <= 0.0 {
        return nearest_on_edges(p, a, b, c);
    }
    let v = vb / denom;
    let w = vc / denom;
    a + ab * v + ac * w
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
