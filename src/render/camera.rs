//! One camera for a whole sequence, framed automatically around every frame's bounds so that the
//! rendered frames line up into an animation, or placed by the user.

use glam::{Mat4, Vec3, Vec4};
use serde::Serialize;

/// A perspective camera.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view, in degrees.
    pub fov_degrees: f32,
}

impl Camera {
    /// Looks at the centre of the box `min..max` from direction `view` (centre toward the eye),
    /// far enough that the box's bounding sphere fills `fill` of the image's height and width.
    pub fn framing(min: Vec3, max: Vec3, view: Vec3, fill: f32) -> Self {
        let fov_degrees = 30.0f32;
        let centre = 0.5 * (min + max);
        let radius = (0.5 * (max - min).length()).max(f32::MIN_POSITIVE);
        let half = (0.5 * fov_degrees).to_radians();
        let distance = radius / (fill * half.tan()).atan().sin();
        let direction = view.try_normalize().unwrap_or(Vec3::Z);
        let up = if direction.cross(Vec3::Y).length() < 1e-3 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        Self {
            eye: centre + direction * distance,
            target: centre,
            up,
            fov_degrees,
        }
    }

    /// World to clip space for an image of `aspect` = width / height: a right-handed look-at view and
    /// a perspective projection with depth 0..1, as wgpu wants.
    /// Near and far planes are set around the target so depth precision goes where the surface is.
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        let distance = self.eye.distance(self.target).max(f32::MIN_POSITIVE);
        let (near, far) = (0.01 * distance, 10.0 * distance);
        let h = 1.0 / (0.5 * self.fov_degrees.to_radians()).tan();
        let r = far / (near - far);
        let projection = Mat4::from_cols(
            Vec4::new(h / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, h, 0.0, 0.0),
            Vec4::new(0.0, 0.0, r, -1.0),
            Vec4::new(0.0, 0.0, r * near, 0.0),
        );
        let f = (self.target - self.eye).normalize_or(Vec3::NEG_Z);
        let s = f.cross(self.up).normalize_or(Vec3::X);
        let u = s.cross(f);
        let view = Mat4::from_cols(
            Vec4::new(s.x, u.x, -f.x, 0.0),
            Vec4::new(s.y, u.y, -f.y, 0.0),
            Vec4::new(s.z, u.z, -f.z, 0.0),
            Vec4::new(-s.dot(self.eye), -u.dot(self.eye), f.dot(self.eye), 1.0),
        );
        projection * view
    }

    /// The unit direction from the target toward the eye: the headlight.
    pub fn toward_eye(&self) -> Vec3 {
        (self.eye - self.target).try_normalize().unwrap_or(Vec3::Z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_target_lands_in_the_middle_of_the_image() {
        let camera = Camera::framing(
            Vec3::splat(-1.0),
            Vec3::splat(3.0),
            Vec3::new(1.0, 0.5, 2.0),
            0.8,
        );
        let clip = camera.view_projection(1.5) * camera.target.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        assert!(ndc.x.abs() < 1e-5 && ndc.y.abs() < 1e-5, "{ndc}");
        assert!((0.0..1.0).contains(&ndc.z));
    }
}
