use super::ProjectError;
use crate::kernels::shared::QueryParams;

/// How [`super::project`] prunes correspondences (paper §4.2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectOptions {
    /// Largest angle, in degrees, between the source normal and the target normal interpolated at
    /// the hit; the paper prunes pairs "more than 60 degrees apart". 180 or more keeps every hit.
    pub max_angle_degrees: f32,
    /// Largest `|t|`, in multiples of the target's mean edge length: hits further away are not
    /// searched for. `f32::INFINITY` searches the whole line. The paper's fine stage prunes at
    /// σ = 0.1 of its scenes' units; a relative bound keeps that meaning at any scale.
    pub max_distance: f32,
}

impl Default for ProjectOptions {
    /// The coarse stage's setting: 60°, unbounded distance.
    fn default() -> Self {
        Self {
            max_angle_degrees: 60.0,
            max_distance: f32::INFINITY,
        }
    }
}

impl ProjectOptions {
    /// The kernel parameters for a target whose mean edge length is `unit`.
    pub(super) fn params(&self, unit: f32) -> Result<QueryParams, ProjectError> {
        let angle = self.max_angle_degrees;
        if angle.is_nan() || angle < 0.0 {
            return Err(ProjectError::InvalidOption {
                name: "max_angle_degrees",
                value: angle,
            });
        }
        // Beyond 180° every pair passes; -2 keeps that true when rounding pushes a dot product
        // of opposite unit vectors below -1.
        let cos_max_angle = if angle >= 180.0 {
            -2.0
        } else {
            angle.to_radians().cos()
        };
        Ok(QueryParams::new(
            absolute_distance(self.max_distance, unit)?,
            cos_max_angle,
        ))
    }
}

/// A relative distance bound in the target's units; unbounded becomes `f32::MAX`, so kernels never
/// see an infinity (WGSL lets implementations assume there are none).
pub(super) fn absolute_distance(relative: f32, unit: f32) -> Result<f32, ProjectError> {
    if relative.is_nan() || relative < 0.0 {
        return Err(ProjectError::InvalidOption {
            name: "max_distance",
            value: relative,
        });
    }
    let absolute = relative * unit;
    Ok(if absolute.is_finite() {
        absolute
    } else {
        f32::MAX
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_scale_with_the_unit_and_infinity_stays_finite() {
        let params = ProjectOptions {
            max_angle_degrees: 60.0,
            max_distance: 2.5,
        }
        .params(0.5)
        .unwrap();
        assert_eq!(params.max_distance, 1.25);
        assert!((params.cos_max_angle - 0.5).abs() < 1e-6);
        let params = ProjectOptions::default().params(0.5).unwrap();
        assert_eq!(params.max_distance, f32::MAX);
        assert_eq!(
            ProjectOptions {
                max_angle_degrees: 270.0,
                max_distance: 1.0
            }
            .params(1.0)
            .unwrap()
            .cos_max_angle,
            -2.0
        );
    }

    #[test]
    fn nan_and_negative_options_are_errors() {
        for (angle, distance, name) in [
            (f32::NAN, 1.0, "max_angle_degrees"),
            (-1.0, 1.0, "max_angle_degrees"),
            (60.0, -0.5, "max_distance"),
            (60.0, f32::NAN, "max_distance"),
        ] {
            let options = ProjectOptions {
                max_angle_degrees: angle,
                max_distance: distance,
            };
            assert!(
                matches!(options.params(1.0), Err(ProjectError::InvalidOption { name: n, .. }) if n == name),
                "{options:?}"
            );
        }
    }
}
