//! A sphere's signed distance blended linearly into a torus's: the hole opens at the centre.

use super::Shape;
use crate::synth::field::Field;
use crate::synth::schedule::{clear_of_transition, frame_time};
use glam::Vec3;

const SPHERE_RADIUS: f32 = 0.8;
const TORUS_MAJOR: f32 = 0.6;
const TORUS_MINOR: f32 = 0.3;

pub(super) const BOUNDS: [Vec3; 2] = [
    Vec3::new(-0.95, -0.95, -SPHERE_RADIUS),
    Vec3::new(0.95, 0.95, SPHERE_RADIUS),
];

/// With `f = (1 − s)·sphere + s·torus`, the centre's value is `f₀ = s·(R_s + R − r) − R_s`, so the
/// hole opens at `s* = R_s / (R_s + R − r)`. Near the centre the membrane closing the hole has
/// half-thickness `−f₀ / (1 − s)` (along the axis the torus term is flat), and once open the hole
/// has radius `f₀ / (2s − 1)` (across it the sphere term grows by 1 and the torus term falls by 1
/// per unit). Frames keep both at least `margin`.
pub(super) fn shape(index: usize, frames: usize, margin: f32) -> Shape {
    let (rs, big, small, m) = (
        f64::from(SPHERE_RADIUS),
        f64::from(TORUS_MAJOR),
        f64::from(TORUS_MINOR),
        f64::from(margin),
    );
    let span = rs + big - small;
    let critical = rs / span;
    let before = (rs - m) / (span - m);
    let after = (rs - m) / (span - 2.0 * m);
    let blend = clear_of_transition(frame_time(index, frames), 0.0, 1.0, critical, before, after);
    let center = blend * span - rs;
    Shape {
        field: Field::Morph {
            sphere_radius: SPHERE_RADIUS,
            torus_major: TORUS_MAJOR,
            torus_minor: TORUS_MINOR,
            blend: blend as f32,
        },
        transform: None,
        components: 1,
        genus: if center > 0.0 { 1 } else { 0 },
    }
}
