//! Two spheres approaching along x until they merge.

use super::Shape;
use crate::synth::field::{Ball, Field};
use crate::synth::schedule::{clear_of_transition, frame_time};
use glam::Vec3;

const LEFT_RADIUS: f32 = 0.5;
const RIGHT_RADIUS: f32 = 0.4;
/// Centre distance at the first frame (a gap of half a unit) and at the last (deeply merged).
const START_DISTANCE: f32 = 1.4;
const END_DISTANCE: f32 = 0.45;

pub(super) const BOUNDS: [Vec3; 2] = [
    Vec3::new(
        -START_DISTANCE / 2.0 - LEFT_RADIUS,
        -LEFT_RADIUS,
        -LEFT_RADIUS,
    ),
    Vec3::new(
        START_DISTANCE / 2.0 + RIGHT_RADIUS,
        LEFT_RADIUS,
        LEFT_RADIUS,
    ),
];

/// The spheres touch when the centre distance equals the sum of the radii; frames keep a gap or an
/// overlap of at least `margin` from that moment.
pub(super) fn shape(index: usize, frames: usize, margin: f32) -> Shape {
    let touching = f64::from(LEFT_RADIUS + RIGHT_RADIUS);
    let distance = clear_of_transition(
        frame_time(index, frames),
        f64::from(START_DISTANCE),
        f64::from(END_DISTANCE),
        touching,
        touching + f64::from(margin),
        touching - f64::from(margin),
    ) as f32;
    let balls = vec![
        Ball {
            center: [-distance / 2.0, 0.0, 0.0],
            radius: LEFT_RADIUS,
        },
        Ball {
            center: [distance / 2.0, 0.0, 0.0],
            radius: RIGHT_RADIUS,
        },
    ];
    Shape {
        field: Field::Union {
            balls,
            capsules: Vec::new(),
        },
        transform: None,
        components: if f64::from(distance) > touching { 2 } else { 1 },
        genus: 0,
    }
}
