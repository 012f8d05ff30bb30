//! A featured shape moving rigidly: the ground truth for registration.

use super::Shape;
use crate::synth::field::{Ball, Field};
use crate::synth::schedule::frame_time;
use crate::synth::transform::RigidTransform;
use glam::{Quat, Vec3};
use std::f32::consts::PI;

const HALF_EXTENTS: [f32; 3] = [0.55, 0.35, 0.3];
const ROUNDING: f32 = 0.08;
/// A half ball sticking out of the middle of the +x face. Like the notch it stays clear of the
/// rounded edges: a feature cutting into an edge would leave walls or gaps thinner than a cell.
const BUMP: Ball = Ball {
    center: [0.55, 0.0, 0.0],
    radius: 0.16,
};
/// A half-ball dimple carved into the +z face, a third as deep as the box is thick.
const NOTCH: Ball = Ball {
    center: [-0.2, 0.0, 0.3],
    radius: 0.18,
};
const START: Vec3 = Vec3::new(-0.35, -0.1, 0.05);
const END: Vec3 = Vec3::new(0.35, 0.15, -0.05);
/// Total rotation over the sequence, about a tilted axis through the shape's centre.
const TURN: f32 = 1.5 * PI;

/// The shape reaches at most 0.72 from its centre (the bump's tip 0.71, the rounded box's corners
/// 0.67), and its centre moves from START to END.
pub(super) const BOUNDS: [Vec3; 2] = [Vec3::new(-1.1, -0.85, -0.8), Vec3::new(1.1, 0.9, 0.8)];

pub(super) fn shape(index: usize, frames: usize) -> Shape {
    let time = frame_time(index, frames) as f32;
    let axis = Vec3::new(0.3, 1.0, 0.5).normalize();
    let transform = RigidTransform::new(
        Quat::from_axis_angle(axis, TURN * time),
        START.lerp(END, time),
    );
    Shape {
        field: Field::FeaturedBox {
            half_extents: HALF_EXTENTS,
            rounding: ROUNDING,
            bump: BUMP,
            notch: NOTCH,
            transform,
        },
        transform: Some(transform),
        components: 1,
        genus: 0,
    }
}
