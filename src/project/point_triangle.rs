//! The point of a triangle nearest to a query point (Ericson 2005, "Real-Time Collision
//! Detection" §5.1.5), with the feature it lies on, which decides the sign of the distance.

use glam::Vec3;

use super::{BvhTriangle, PseudoNormals};

/// Where on the triangle the nearest point lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Feature {
    /// Corner 0, 1 or 2 (a, b, c).
    Vertex(usize),
    /// Edge 0 (ab), 1 (bc) or 2 (ca).
    Edge(usize),
    Face,
}

/// The nearest point, its barycentric weights and its feature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Nearest {
    pub point: Vec3,
    pub weights: [f32; 3],
    pub feature: Feature,
}

/// The point of `tri` nearest to `p`, found by Voronoi regions: vertex, edge, then face.
#[inline(always)]
pub(super) fn closest_on_triangle(p: Vec3, tri: &BvhTriangle) -> Nearest {
    let [a, b, c] = tri.corners();
    let at = |weights: [f32; 3], feature| Nearest {
        point: a * weights[0] + b * weights[1] + c * weights[2],
        weights,
        feature,
    };
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return Nearest {
            point: a,
            weights: [1.0, 0.0, 0.0],
            feature: Feature::Vertex(0),
        };
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return Nearest {
            point: b,
            weights: [0.0, 1.0, 0.0],
            feature: Feature::Vertex(1),
        };
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let s = d1 / (d1 - d3);
        return at([1.0 - s, s, 0.0], Feature::Edge(0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return Nearest {
            point: c,
            weights: [0.0, 0.0, 1.0],
            feature: Feature::Vertex(2),
        };
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let s = d2 / (d2 - d6);
        return at([1.0 - s, 0.0, s], Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at([0.0, 1.0 - s, s], Feature::Edge(1));
    }
    let sum = va + vb + vc;
    if sum.is_nan() || sum <= 0.0 {
        // Only a degenerate (zero-area) triangle gets here; its corner a is as good as any point.
        return Nearest {
            point: a,
            weights: [1.0, 0.0, 0.0],
            feature: Feature::Vertex(0),
        };
    }
    let v = vb / sum;
    let w = vc / sum;
    at([1.0 - v - w, v, w], Feature::Face)
}

/// The normal whose side of the surface `p` is on when its nearest point is `nearest`: the face
/// normal inside the face, the pseudo-normal on an edge or at a corner.
pub(super) fn side_normal(tri: &BvhTriangle, pseudo: &PseudoNormals, feature: Feature) -> Vec3 {
    let pick = |t: &super::NormalTriple, k: usize| match k {
        0 => t.a,
        1 => t.b,
        _ => t.c,
    };
    match feature {
        Feature::Vertex(k) => pick(&pseudo.vertices, k),
        Feature::Edge(k) => pick(&pseudo.edges, k),
        Feature::Face => (tri.b - tri.a).cross(tri.c - tri.a),
    }
}
