//! The ray directions of a projection, shared by both backends.

use glam::Vec3;
use rayon::prelude::*;

use super::ProjectError;

/// The unit direction of each query, or zero where the point or its normal is unusable, computed
/// once on the host so both backends cast exactly the same rays.
pub(super) fn directions(points: &[Vec3], normals: &[Vec3]) -> Result<Vec<Vec3>, ProjectError> {
    if points.len() != normals.len() {
        return Err(ProjectError::LengthMismatch {
            points: points.len(),
            normals: normals.len(),
        });
    }
    Ok(points
        .par_iter()
        .zip(normals)
        .map(|(p, n)| {
            if p.is_finite() {
                n.normalize_or_zero()
            } else {
                Vec3::ZERO
            }
        })
        .collect())
}
