use glam::{Mat4, Quat, Vec3};
use serde::{Deserialize, Serialize};

/// A rigid motion `p ↦ rotation · p + translation`, from a scene's object space to world space.
///
/// `matrix` is the same motion as a column-major 4×4 matrix (`matrix[column][row]`), stored for
/// readers that prefer it; the motion between frames `a` and `b` is `T_b · T_a⁻¹`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidTransform {
    /// Unit quaternion `[x, y, z, w]`.
    pub rotation: [f32; 4],
    pub translation: [f32; 3],
    pub matrix: [[f32; 4]; 4],
}

impl RigidTransform {
    pub fn new(rotation: Quat, translation: Vec3) -> Self {
        Self {
            rotation: rotation.to_array(),
            translation: translation.to_array(),
            matrix: Mat4::from_rotation_translation(rotation, translation).to_cols_array_2d(),
        }
    }

    pub fn rotation(&self) -> Quat {
        Quat::from_array(self.rotation)
    }

    pub fn translation(&self) -> Vec3 {
        Vec3::from_array(self.translation)
    }

    /// World position of an object-space point.
    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.rotation() * p + self.translation()
    }

    /// Object-space position of a world point.
    pub fn inverse_apply(&self, p: Vec3) -> Vec3 {
        self.rotation().inverse() * (p - self.translation())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_quaternion_and_inverse_agree() {
        let rotation = Quat::from_axis_angle(Vec3::new(0.3, 1.0, 0.5).normalize(), 1.1);
        let t = RigidTransform::new(rotation, Vec3::new(0.5, -0.2, 0.1));
        let p = Vec3::new(0.7, -0.4, 0.25);
        let by_matrix = Mat4::from_cols_array_2d(&t.matrix).transform_point3(p);
        assert!((by_matrix - t.apply(p)).length() < 1e-6);
        assert!((t.inverse_apply(t.apply(p)) - p).length() < 1e-6);
    }
}
