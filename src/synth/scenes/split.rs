//! A dumbbell whose bar breaks in the middle, the two stubs retracting into the bells.

use super::Shape;
use crate::synth::field::{Ball, Capsule, Field};
use crate::synth::schedule::{clear_of_transition, frame_time};
use glam::Vec3;

const BELL_RADIUS: f32 = 0.45;
const BELL_OFFSET: f32 = 0.75;
/// Bar radius at the first frame; it thins linearly to `END_BAR_RADIUS`, but never below 1.25
/// margins, so the bar and the stubs stay resolvable.
const START_BAR_RADIUS: f32 = 0.22;
const END_BAR_RADIUS: f32 = 0.1;
/// Signed gap between the two stubs' tips: negative while they overlap (one bar), positive once
/// broken; at the end the stubs have retracted into the bells.
const START_GAP: f32 = -0.6;
const END_GAP: f32 = 0.6;

pub(super) const BOUNDS: [Vec3; 2] = [
    Vec3::new(-BELL_OFFSET - BELL_RADIUS, -BELL_RADIUS, -BELL_RADIUS),
    Vec3::new(BELL_OFFSET + BELL_RADIUS, BELL_RADIUS, BELL_RADIUS),
];

/// The bar is two capsules, one from each bell's centre toward the other; they form one bar while
/// their tips overlap and break apart when the tips separate. Frames keep an overlap or a gap of
/// at least `margin`.
pub(super) fn shape(index: usize, frames: usize, margin: f32) -> Shape {
    let time = frame_time(index, frames);
    let gap = clear_of_transition(
        time,
        f64::from(START_GAP),
        f64::from(END_GAP),
        0.0,
        -f64::from(margin),
        f64::from(margin),
    ) as f32;
    let linear = START_BAR_RADIUS + time as f32 * (END_BAR_RADIUS - START_BAR_RADIUS);
    let radius = linear.max(1.25 * margin);
    // Segment end of each stub: its tip (end + radius) lies gap / 2 from the middle.
    let end = gap / 2.0 + radius;
    let bells = [-BELL_OFFSET, BELL_OFFSET].map(|x| Ball {
        center: [x, 0.0, 0.0],
        radius: BELL_RADIUS,
    });
    let stubs = [-1.0f32, 1.0].map(|side| Capsule {
        start: [side * BELL_OFFSET, 0.0, 0.0],
        end: [side * end, 0.0, 0.0],
        radius,
    });
    Shape {
        field: Field::Union {
            balls: bells.to_vec(),
            capsules: stubs.to_vec(),
        },
        transform: None,
        components: if gap < 0.0 { 1 } else { 2 },
        genus: 0,
    }
}
