//! Watertight ray–triangle intersection (Woop, Benthin & Wald 2013, "Watertight Ray/Triangle
//! Intersection"): the triangle is moved into a frame where the ray is the +z axis, and the hit
//! test becomes three 2-D edge functions at the origin.
//!
//! Every vertex is transformed by the same operations whichever triangle it belongs to, and the
//! edge function of a shared edge is evaluated on the same two transformed points, only in the
//! opposite order, which negates it exactly. So a ray through an edge or a vertex of a closed mesh
//! is inside (or on the boundary of) at least one of the triangles there: it never slips through.

use glam::Vec3;

use crate::kernels::shared::BvhTriangle;

/// The per-ray part of the transform: the axis permutation that makes the largest direction
/// component z (keeping the winding), and the shear that maps the direction to +z.
#[derive(Debug, Clone, Copy)]
pub(super) struct Shear {
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
    origin: [f32; 3],
}

/// A ray–triangle hit: the ray parameter and the corners' barycentric weights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TriangleHit {
    pub t: f32,
    pub weights: [f32; 3],
}

impl Shear {
    /// The transform of the ray `origin + t·direction`; `direction` must not be zero.
    pub(super) fn new(origin: Vec3, direction: Vec3) -> Self {
        let a = direction.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if direction[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let dz = direction[kz];
        Self {
            kx,
            ky,
            kz,
            sx: direction[kx] / dz,
            sy: direction[ky] / dz,
            sz: 1.0 / dz,
            origin: origin.to_array(),
        }
    }

    /// Where the ray meets `tri`, at any `t` (both faces, no interval); `None` when it misses the
    /// triangle or lies in its plane.
    #[inline(always)]
    pub(super) fn intersect(&self, tri: &BvhTriangle) -> Option<TriangleHit> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let o = self.origin;
        let project = |p: Vec3| {
            let p = p.to_array();
            let z = p[kz] - o[kz];
            (
                p[kx] - o[kx] - self.sx * z,
                p[ky] - o[ky] - self.sy * z,
                self.sz * z,
            )
        };
        let (ax, ay, az) = project(tri.a);
        let (bx, by, bz) = project(tri.b);
        let (cx, cy, cz) = project(tri.c);
        // Edge functions of bc, ca, ab: the weights of a, b, c. A product-difference evaluated
        // on the same two points in the other order is its exact negation, which is what makes
        // the test watertight (see the module comment).
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let rcp = 1.0 / det;
        Some(TriangleHit {
            t: (u * az + v * bz + w * cz) * rcp,
            weights: [u * rcp, v * rcp, w * rcp],
        })
    }
}
