//! The measures improvement acts on: edge length, interior angle, dihedral angle, face normal.

use super::params::Limits;
use glam::Vec3;

/// Unnormalized face normal (twice the area), counter-clockwise seen from outside.
pub(super) fn face_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a)
}

/// Smallest interior angle in degrees (the same measure `IndexedMesh::quality` reports).
pub(super) fn min_angle([a, b, c]: [Vec3; 3]) -> f32 {
    crate::mesh::min_angle_degrees(a, b, c)
}

/// Interior dihedral angle in degrees between two faces sharing an edge: 180° where they are coplanar,
/// 0° where they fold onto each other. `None` when a face has no normal.
pub(super) fn dihedral_degrees(first: Vec3, second: Vec3) -> Option<f32> {
    let n = (first.length_squared() * second.length_squared()).sqrt();
    (n > 0.0).then(|| 180.0 - (first.dot(second) / n).clamp(-1.0, 1.0).acos().to_degrees())
}

/// Shortest and longest edge of a triangle.
pub(super) fn edge_extremes([a, b, c]: [Vec3; 3]) -> (f32, f32) {
    let l = [a.distance(b), b.distance(c), c.distance(a)];
    (l[0].min(l[1]).min(l[2]), l[0].max(l[1]).max(l[2]))
}

/// How well a triangle meets the angle and short-edge criteria, as one number: the smallest of
/// `angle / min_angle` and `shortest / min_edge`, capped at 1 (meets both). Collapses and flips must
/// not lower the worst value around them, which lets a collapse trade a short edge for a less severe
/// small angle that a later flip or collapse removes.
pub(super) fn quality(p: [Vec3; 3], limits: &Limits) -> f32 {
    let (shortest, _) = edge_extremes(p);
    let angle = if limits.min_angle > 0.0 {
        min_angle(p) / limits.min_angle
    } else {
        1.0
    };
    angle.min(shortest / limits.min_edge).min(1.0)
}

/// Smallest interior angle (degrees) among those opposite an edge at least `min_edge` long: the angles a
/// collapse cannot remove by itself. An angle opposite a shorter edge goes when that edge is collapsed,
/// so it does not count (180 when every edge is short).
pub(super) fn angle_beyond_short_edges([a, b, c]: [Vec3; 3], min_edge: f32) -> f32 {
    let p = [a, b, c];
    (0..3)
        .filter(|&k| p[(k + 1) % 3].distance(p[(k + 2) % 3]) >= min_edge)
        .map(|k| (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]).to_degrees())
        .fold(180.0, f32::min)
}
