//! Stam & Schmidt's benchmark (paper §6): three blended metaballs rotating rigidly.

use super::Shape;
use crate::synth::field::Field;
use crate::synth::transform::RigidTransform;
use glam::{Quat, Vec3};
use std::f32::consts::TAU;

pub(super) const BOUNDS: [Vec3; 2] = [Vec3::splat(-0.9), Vec3::splat(0.9)];

/// Blob centres in object space, deliberately asymmetric so every rotation is distinguishable.
const CENTERS: [[f32; 3]; 3] = [
    [0.42, 0.0, 0.05],
    [-0.22, 0.36, -0.08],
    [-0.18, -0.34, 0.12],
];
const WIDTH: f32 = 0.32;
/// Low enough that the three blobs always form one body without a hole between them.
const THRESHOLD: f32 = 0.45;

/// Rotation by `index / frames` of a full turn about a tilted axis through the origin, so frame
/// `frames` would coincide with frame 0.
pub(super) fn shape(index: usize, frames: usize) -> Shape {
    let axis = Vec3::new(0.25, 1.0, 0.35).normalize();
    let angle = TAU * index as f32 / frames.max(1) as f32;
    let transform = RigidTransform::new(Quat::from_axis_angle(axis, angle), Vec3::ZERO);
    Shape {
        field: Field::Metaballs {
            centers: CENTERS.to_vec(),
            width: WIDTH,
            threshold: THRESHOLD,
            transform,
        },
        transform: Some(transform),
        components: 1,
        genus: 0,
    }
}
