//! A ball with droplets that appear beside it, fly outward, and vanish.

use super::Shape;
use crate::synth::field::{Ball, Field};
use crate::synth::schedule::frame_time;
use glam::Vec3;
use std::f32::consts::PI;

const BODY_RADIUS: f32 = 0.55;
/// Directions the droplets fly in (normalized on use), spread so droplets never come close.
const DIRECTIONS: [[f32; 3]; 5] = [
    [1.0, 0.2, 0.0],
    [-0.3, 1.0, 0.2],
    [-0.5, -0.6, 0.8],
    [0.2, -0.7, -0.9],
    [-0.9, 0.1, -0.6],
];
/// Droplet `k` lives from time `FIRST_BIRTH + k · BIRTH_INTERVAL` for `LIFETIME`.
const FIRST_BIRTH: f32 = 0.05;
const BIRTH_INTERVAL: f32 = 0.12;
const LIFETIME: f32 = 0.4;
/// Distance of a droplet's centre from the body's centre at birth and at death.
const BIRTH_DISTANCE: f32 = 1.0;
const DEATH_DISTANCE: f32 = 1.25;
/// Largest droplet radius, reached halfway through its life.
const MAX_RADIUS: f32 = 0.2;

pub(super) const BOUNDS: [Vec3; 2] = [Vec3::splat(-1.35), Vec3::splat(1.35)];

/// A droplet's radius swells and shrinks as `sin(π · age)`; it exists only while that radius is at
/// least half the margin (one cell): a ball that large always holds grid corners and always comes
/// out of marching cubes as one sphere (tests/marching_cubes.rs), so every droplet present is
/// resolved and every absent one is truly absent. Its gap to the body is at least
/// `BIRTH_DISTANCE − BODY_RADIUS − MAX_RADIUS`, a full margin at the coarsest resolution.
pub(super) fn shape(index: usize, frames: usize, margin: f32) -> Shape {
    let time = frame_time(index, frames) as f32;
    let mut balls = vec![Ball {
        center: [0.0; 3],
        radius: BODY_RADIUS,
    }];
    for (k, direction) in DIRECTIONS.iter().enumerate() {
        let age = (time - FIRST_BIRTH - k as f32 * BIRTH_INTERVAL) / LIFETIME;
        if !(0.0..=1.0).contains(&age) {
            continue;
        }
        let radius = MAX_RADIUS * (PI * age).sin();
        if radius < 0.5 * margin {
            continue;
        }
        let distance = BIRTH_DISTANCE + age * (DEATH_DISTANCE - BIRTH_DISTANCE);
        balls.push(Ball {
            center: (Vec3::from_array(*direction).normalize() * distance).to_array(),
            radius,
        });
    }
    let components = balls.len();
    Shape {
        field: Field::Union {
            balls,
            capsules: Vec::new(),
        },
        transform: None,
        components,
        genus: 0,
    }
}
