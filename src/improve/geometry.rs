//! The measures improvement acts on: edge length, interior angle, dihedral angle, face normal.

use glam::Vec3;

/// Unnormalized face normal (twice the area), counter-clockwise seen from outside.
pub(super) fn face_normal([a, b, c]: [Vec3; 3]) -> Vec3 {
    (b - a).cross(c - a)
}

/// Smallest interior angle in degrees (the same measure `IndexedMesh::quality` reports).
pub(super) fn min_angle([a, b, c]: [Vec3; 3]) -> f32 {
    crate::mesh::min_angle_degrees(a, b, c)
}

/// Interior dihedral angle in degrees between two faces sharing an edge, from their normals: 180°
/// where they are coplanar, 0° where they fold onto each other. `None` when a face has no normal.
pub(super) fn dihedral_degrees(first: Vec3, second: Vec3) -> Option<f32> {
    let n = (first.length_squared() * second.length_squared()).sqrt();
    (n > 0.0).then(|| 180.0 - (first.dot(second) / n).clamp(-1.0, 1.0).acos().to_degrees())
}

/// Sine of the smallest interior angle: twice the area over the product of the two longest edges.
/// The smallest angle is at most 60°, where the sine grows with the angle, so comparing sines
/// compares smallest angles without inverse trigonometry.
pub(super) fn min_angle_sine([a, b, c]: [Vec3; 3]) -> f32 {
    let [x, y, z] = [a.distance(b), b.distance(c), c.distance(a)];
    // The largest pairwise product is the product of the two longest edges.
    let product = (x * y).max(y * z).max(z * x);
    if product > 0.0 {
        (b - a).cross(c - a).length() / product
    } else {
        0.0
    }
}

/// Shortest and longest edge of a triangle.
pub(super) fn edge_extremes([a, b, c]: [Vec3; 3]) -> (f32, f32) {
    let l = [a.distance(b), b.distance(c), c.distance(a)];
    (l[0].min(l[1]).min(l[2]), l[0].max(l[1]).max(l[2]))
}

/// Whether a triangle breaks the per-triangle criteria: an angle below `min_angle` degrees, or a
/// longest edge more than `edge_ratio` times its shortest.
pub(super) fn fails(p: [Vec3; 3], min_angle_degrees: f32, edge_ratio: f32) -> bool {
    let (shortest, longest) = edge_extremes(p);
    min_angle(p) < min_angle_degrees || longest > edge_ratio * shortest
}

/// Whether some interior angle's cosine exceeds `cos_limit` (the angle is smaller than the limit),
/// without trigonometry: the cheap filter before an angle is measured.
pub(super) fn has_angle_below(p: [Vec3; 3], cos_limit: f32) -> bool {
    (0..3).any(|k| {
        let (e1, e2) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
        let d = e1.dot(e2);
        d > 0.0 && d * d > cos_limit * cos_limit * e1.length_squared() * e2.length_squared()
    })
}

/// Whether two face normals meet at a dihedral angle below the one whose cosine is `cos_limit`
/// (the normals are more than 180° minus that angle apart), without inverse trigonometry. A face
/// without a normal folds onto anything.
pub(super) fn folds_beyond(first: Vec3, second: Vec3, cos_limit: f32) -> bool {
    let n = (first.length_squared() * second.length_squared()).sqrt();
    n == 0.0 || first.dot(second) < -cos_limit * n
}

/// Below this sine of its smallest angle (about 0.6°) a face's normal is dominated by rounding: a
/// sliver left by a topology patch or a marching-cubes frame says nothing about which way the
/// surface faces, so the checks below do not trust it.
const RELIABLE_NORMAL_SINE: f32 = 0.01;

/// The face's normal when its shape makes it meaningful (see `RELIABLE_NORMAL_SINE`).
pub(super) fn reliable_normal(p: [Vec3; 3]) -> Option<Vec3> {
    (min_angle_sine(p) >= RELIABLE_NORMAL_SINE).then(|| face_normal(p))
}

/// How sharply two faces fold at their shared edge: the negated cosine between their normals, so
/// −1 where they are coplanar and 1 where they fold flat onto each other. `None` when either normal
/// is unreliable. A fold sharper than the dihedral limit has a measure above its cosine.
pub(super) fn fold(first: Option<Vec3>, second: Option<Vec3>) -> Option<f32> {
    let (a, b) = (first?, second?);
    let n = (a.length_squared() * b.length_squared()).sqrt();
    (n > 0.0).then(|| -a.dot(b) / n)
}

/// Whether an operation whose sharpest new fold is `after` must be refused, given `before`, the
/// sharpest fold among the faces it replaces and their neighbours: a fold beyond the dihedral limit
/// (cosine `cos_limit`) is refused only when it is sharper than what was there, so a crease that is
/// already in the mesh does not freeze every fix around it.
pub(super) fn folds_worse(after: f32, before: f32, cos_limit: f32) -> bool {
    after > cos_limit && after > before
}
