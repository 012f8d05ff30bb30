//! Texture coordinates from a projection of the start frame: what gives an image or a UV layout to a
//! surface that has none. Coordinates are computed once, on the start frame, and then carried like
//! any other per-vertex value, so the texture moves with the material (paper §4.6, Fig. 11).

use glam::{Vec2, Vec3};
use serde::Serialize;
use std::f32::consts::PI;

/// Axis-aligned bounds of a point set.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    /// Bounds of `points`; `None` when there is no finite point.
    pub fn of(points: &[Vec3]) -> Option<Self> {
        let mut finite = points.iter().filter(|p| p.is_finite());
        let first = *finite.next()?;
        let (min, max) = finite.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        Some(Self { min, max })
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    pub fn diagonal(&self) -> f32 {
        self.extent().length()
    }
}

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    fn index(self) -> usize {
        match self {
            Self::X => 0,
            Self::Y => 1,
            Self::Z => 2,
        }
    }
}

/// How a point of the start frame gets texture coordinates `(u, v)` in `[0, 1]²`, relative to the
/// start frame's bounds (so the mapping does not depend on the scene's units).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Projection {
    /// Along an axis: the bounds' two other sides, in right-handed order (X: `(y, z)`, Y: `(z, x)`,
    /// Z: `(x, y)`), are each stretched onto `[0, 1]`.
    Planar(Axis),
    /// Longitude and latitude about the bounds' centre, `y` up: `u` runs once around, from −x through
    /// +z; `v` runs from the south pole (0) to the north pole (1). Vertices on either side of the
    /// `u = 0 | 1` seam get distant coordinates, as in any per-vertex spherical mapping.
    Spherical,
}

impl Projection {
    pub fn uv(&self, p: Vec3, bounds: &Bounds) -> Vec2 {
        match *self {
            Self::Planar(axis) => {
                let a = axis.index();
                let (i, j) = ((a + 1) % 3, (a + 2) % 3);
                let rel = p - bounds.min;
                let ext = bounds.extent();
                let unit = |x: f32, e: f32| if e > 0.0 { x / e } else { 0.5 };
                Vec2::new(unit(rel[i], ext[i]), unit(rel[j], ext[j]))
            }
            Self::Spherical => {
                let d = p - bounds.center();
                let r = d.length();
                if r == 0.0 || !r.is_finite() {
                    return Vec2::splat(0.5);
                }
                let u = 0.5 + d.z.atan2(-d.x) / (2.0 * PI);
                let v = 0.5 + (d.y / r).clamp(-1.0, 1.0).asin() / PI;
                Vec2::new(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Bounds {
        Bounds {
            min: Vec3::new(-1.0, -2.0, 0.0),
            max: Vec3::new(1.0, 2.0, 4.0),
        }
    }

    #[test]
    fn planar_maps_the_bounds_onto_the_unit_square() {
        let b = unit_box();
        let z = Projection::Planar(Axis::Z);
        assert_eq!(z.uv(b.min, &b), Vec2::ZERO);
        assert_eq!(z.uv(b.max, &b), Vec2::ONE);
        assert_eq!(z.uv(Vec3::new(0.0, 1.0, 3.0), &b), Vec2::new(0.5, 0.75));
        let x = Projection::Planar(Axis::X);
        assert_eq!(x.uv(Vec3::new(0.0, 1.0, 3.0), &b), Vec2::new(0.75, 0.75));
        let y = Projection::Planar(Axis::Y);
        assert_eq!(y.uv(Vec3::new(0.0, 1.0, 3.0), &b), Vec2::new(0.75, 0.5));
    }

    #[test]
    fn spherical_poles_equator_and_meridians() {
        let b = Bounds {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        };
        let s = Projection::Spherical;
        assert!((s.uv(Vec3::Y, &b).y - 1.0).abs() < 1e-6);
        assert!(s.uv(-Vec3::Y, &b).y.abs() < 1e-6);
        let cases = [(-Vec3::X, 0.5), (Vec3::Z, 0.75), (-Vec3::Z, 0.25)];
        for (p, u) in cases {
            let uv = s.uv(p, &b);
            assert!(
                (uv.x - u).abs() < 1e-6 && (uv.y - 0.5).abs() < 1e-6,
                "{p} → {uv}"
            );
        }
        assert_eq!(s.uv(Vec3::ZERO, &b), Vec2::splat(0.5));
    }

    #[test]
    fn bounds_skip_non_finite_points() {
        let b = Bounds::of(&[Vec3::ONE, Vec3::NAN, -Vec3::ONE]).unwrap();
        assert_eq!((b.min, b.max), (-Vec3::ONE, Vec3::ONE));
        assert!((b.diagonal() - 12f32.sqrt()).abs() < 1e-6);
        assert_eq!(Bounds::of(&[Vec3::INFINITY]), None);
    }
}
