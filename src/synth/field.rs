//! The implicit fields the scenes are made of, as plain data: the manifest stores each frame's field
//! so any reader can re-evaluate the exact surface a frame was extracted from.
//!
//! Every field is negative inside and positive outside (the surface is its zero set). The
//! distance-based fields are exact signed distances (or unions and differences of them, which
//! bound the distance), so gaps and overlaps between parts are true distances.

use super::transform::RigidTransform;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A ball: `|p − center| − radius`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ball {
    pub center: [f32; 3],
    pub radius: f32,
}

impl Ball {
    pub fn distance(&self, p: Vec3) -> f32 {
        (p - Vec3::from_array(self.center)).length() - self.radius
    }
}

/// A capsule: points within `radius` of the segment `start`–`end`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Capsule {
    pub start: [f32; 3],
    pub end: [f32; 3],
    pub radius: f32,
}

impl Capsule {
    pub fn distance(&self, p: Vec3) -> f32 {
        let (a, b) = (Vec3::from_array(self.start), Vec3::from_array(self.end));
        let ab = b - a;
        let along = ab.length_squared();
        let s = if along > 0.0 {
            ((p - a).dot(ab) / along).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p - (a + s * ab)).length() - self.radius
    }
}

/// One frame's implicit field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Field {
    /// Blended Gaussian blobs (Blinn): `threshold − Σ exp(−|q − c|² / width²)` with
    /// `q = transform⁻¹(p)`, so the blob set moves rigidly with `transform`.
    Metaballs {
        centers: Vec<[f32; 3]>,
        width: f32,
        threshold: f32,
        transform: RigidTransform,
    },
    /// Union (minimum) of balls and capsules.
    Union {
        balls: Vec<Ball>,
        capsules: Vec<Capsule>,
    },
    /// `(1 − blend) · sphere + blend · torus`: signed distances to a sphere of `sphere_radius` and to
    /// a torus about the z axis with radii `torus_major` and `torus_minor`, both centred at the
    /// origin.
    Morph {
        sphere_radius: f32,
        torus_major: f32,
        torus_minor: f32,
        blend: f32,
    },
    /// A box of `half_extents` with edges rounded by `rounding`, joined with the ball `bump` and
    /// with the ball `notch` carved out, all in object space and moved by `transform`.
    FeaturedBox {
        half_extents: [f32; 3],
        rounding: f32,
        bump: Ball,
        notch: Ball,
        transform: RigidTransform,
    },
}

impl Field {
    /// The field's value at world point `p`.
    pub fn value(&self, p: Vec3) -> f32 {
        match self {
            Field::Metaballs {
                centers,
                width,
                threshold,
                transform,
            } => {
                let q = transform.inverse_apply(p);
                let inv = 1.0 / (width * width);
                let sum: f32 = centers
                    .iter()
                    .map(|c| (-(q - Vec3::from_array(*c)).length_squared() * inv).exp())
                    .sum();
                threshold - sum
            }
            Field::Union { balls, capsules } => {
                let balls = balls.iter().map(|b| b.distance(p));
                let capsules = capsules.iter().map(|c| c.distance(p));
                balls.chain(capsules).fold(f32::INFINITY, f32::min)
            }
            Field::Morph {
                sphere_radius,
                torus_major,
                torus_minor,
                blend,
            } => {
                let sphere = p.length() - sphere_radius;
                let ring = p.truncate().length() - torus_major;
                let torus = (ring * ring + p.z * p.z).sqrt() - torus_minor;
                (1.0 - blend) * sphere + blend * torus
            }
            Field::FeaturedBox {
                half_extents,
                rounding,
                bump,
                notch,
                transform,
            } => {
                let q = transform.inverse_apply(p);
                let inner = Vec3::from_array(*half_extents) - Vec3::splat(*rounding);
                let d = q.abs() - inner;
                let rounded_box = d.max(Vec3::ZERO).length() + d.max_element().min(0.0) - rounding;
                rounded_box.min(bump.distance(q)).max(-notch.distance(q))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    #[test]
    fn primitives_are_signed_distances() {
        let ball = Ball {
            center: [1.0, 0.0, 0.0],
            radius: 0.5,
        };
        assert_eq!(ball.distance(Vec3::new(3.0, 0.0, 0.0)), 1.5);
        assert_eq!(ball.distance(Vec3::new(1.0, 0.0, 0.0)), -0.5);
        let capsule = Capsule {
            start: [0.0, 0.0, 0.0],
            end: [2.0, 0.0, 0.0],
            radius: 0.25,
        };
        assert_eq!(capsule.distance(Vec3::new(1.0, 1.0, 0.0)), 0.75);
        assert_eq!(capsule.distance(Vec3::new(3.0, 0.0, 0.0)), 0.75);
        let morph = |blend| Field::Morph {
            sphere_radius: 0.8,
            torus_major: 0.6,
            torus_minor: 0.3,
            blend,
        };
        assert!((morph(0.0).value(Vec3::new(0.0, 0.0, 1.0)) - 0.2).abs() < 1e-6);
        assert!((morph(1.0).value(Vec3::ZERO) - 0.3).abs() < 1e-6);
        assert!((morph(1.0).value(Vec3::new(0.6, 0.0, 0.0)) + 0.3).abs() < 1e-6);
    }

    #[test]
    fn moved_fields_move_with_their_transform() {
        let transform = RigidTransform::new(Quat::from_rotation_z(0.7), Vec3::new(0.2, -0.1, 0.3));
        let still = RigidTransform::new(Quat::IDENTITY, Vec3::ZERO);
        let ball = Ball {
            center: [0.0; 3],
            radius: 0.0,
        };
        let shape = |transform| Field::FeaturedBox {
            half_extents: [0.5, 0.3, 0.2],
            rounding: 0.05,
            bump: Ball {
                center: [0.5, 0.0, 0.0],
                radius: 0.1,
            },
            notch: ball,
            transform,
        };
        let blobs = |transform| Field::Metaballs {
            centers: vec![[0.3, 0.0, 0.0], [-0.2, 0.1, 0.0]],
            width: 0.3,
            threshold: 0.5,
            transform,
        };
        for q in [
            Vec3::new(0.45, 0.1, 0.0),
            Vec3::new(0.58, 0.02, 0.01),
            Vec3::ZERO,
        ] {
            let p = transform.apply(q);
            let moved = shape(transform).value(p);
            assert!((moved - shape(still).value(q)).abs() < 1e-5);
            assert!((blobs(transform).value(p) - blobs(still).value(q)).abs() < 1e-5);
        }
        assert!((shape(still).value(Vec3::new(0.7, 0.0, 0.0)) - 0.1).abs() < 1e-6);
        assert!((shape(still).value(Vec3::new(0.0, 0.0, 0.5)) - 0.3).abs() < 1e-6);
    }
}
