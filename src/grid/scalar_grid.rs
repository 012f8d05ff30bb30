use glam::Vec3;
use rayon::prelude::*;
use thiserror::Error;

/// Largest number of grid corners: every corner owns at most three crossed edges, and each crossing
/// becomes one vertex addressed by a `u32` index, so extraction can never overflow an index.
pub const MAX_CORNERS: usize = (u32::MAX / 3) as usize;

/// Why a scalar grid could not be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GridError {
    #[error("grid spacing must be finite and positive, got {0}")]
    Spacing(f32),
    #[error("grid origin must be finite, got {0:?}")]
    Origin([f32; 3]),
    #[error("grid of {dims:?} corners exceeds the limit of {MAX_CORNERS} corners")]
    TooLarge { dims: [usize; 3] },
    #[error("grid of {dims:?} corners needs {expected} values, got {got}")]
    ValueCount {
        dims: [usize; 3],
        expected: usize,
        got: usize,
    },
}

/// Samples of a scalar field at the corners of a regular grid.
///
/// Corner `(i, j, k)` sits at `origin + spacing * (i, j, k)` and its value is
/// `values[i + dims[0] * (j + dims[1] * k)]` (x fastest). The fields are private so the value count
/// always matches `dims`; read them through the accessors.
#[derive(Debug, Clone, PartialEq)]
pub struct ScalarGrid {
    origin: Vec3,
    spacing: f32,
    dims: [usize; 3],
    values: Vec<f32>,
}

impl ScalarGrid {
    /// A grid from its samples; `dims` counts corners (cells + 1) along x, y, z.
    pub fn new(
        origin: Vec3,
        spacing: f32,
        dims: [usize; 3],
        values: Vec<f32>,
    ) -> Result<Self, GridError> {
        let expected = Self::check_shape(origin, spacing, dims)?;
        if values.len() != expected {
            return Err(GridError::ValueCount {
                dims,
                expected,
                got: values.len(),
            });
        }
        Ok(Self {
            origin,
            spacing,
            dims,
            values,
        })
    }

    /// A grid sampling `field` at every corner, evaluated in parallel (one z plane per task).
    pub fn from_fn<F>(
        origin: Vec3,
        spacing: f32,
        dims: [usize; 3],
        field: F,
    ) -> Result<Self, GridError>
    where
        F: Fn(Vec3) -> f32 + Sync,
    {
        let count = Self::check_shape(origin, spacing, dims)?;
        let values = sample_box(dims, count, |[i, j, k]| {
            field(origin + spacing * Vec3::new(i as f32, j as f32, k as f32))
        });
        Ok(Self {
            origin,
            spacing,
            dims,
            values,
        })
    }

    fn check_shape(origin: Vec3, spacing: f32, dims: [usize; 3]) -> Result<usize, GridError> {
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(GridError::Spacing(spacing));
        }
        if !origin.is_finite() {
            return Err(GridError::Origin(origin.to_array()));
        }
        dims.iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .filter(|&n| n <= MAX_CORNERS)
            .ok_or(GridError::TooLarge { dims })
    }

    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// Corner counts along x, y, z.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// All samples, x fastest, then y, then z.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// Mutable samples; the count is fixed by `dims`.
    pub fn values_mut(&mut self) -> &mut [f32] {
        &mut self.values
    }

    /// The sample at corner `(i, j, k)`, or `None` outside the grid.
    pub fn value(&self, i: usize, j: usize, k: usize) -> Option<f32> {
        let [nx, ny, nz] = self.dims;
        (i < nx && j < ny && k < nz).then(|| self.values[i + nx * (j + ny * k)])
    }

    /// World position of corner `(i, j, k)`.
    pub fn corner_position(&self, i: usize, j: usize, k: usize) -> Vec3 {
        self.origin + self.spacing * Vec3::new(i as f32, j as f32, k as f32)
    }
}

/// `f` at every corner `[i, j, k]` of a box of `dims` corners (`count` in all), x fastest, one z
/// plane per task.
pub(crate) fn sample_box(
    dims: [usize; 3],
    count: usize,
    f: impl Fn([usize; 3]) -> f32 + Sync,
) -> Vec<f32> {
    let mut values = vec![0.0f32; count];
    let plane = dims[0] * dims[1];
    if plane > 0 {
        values
            .par_chunks_mut(plane)
            .enumerate()
            .for_each(|(k, slice)| {
                for (n, value) in slice.iter_mut().enumerate() {
                    *value = f([n % dims[0], n / dims[0], k]);
                }
            });
    }
    values
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_fn_samples_corners_x_fastest() {
        let grid = ScalarGrid::from_fn(Vec3::new(1.0, 2.0, 3.0), 0.5, [3, 4, 5], |p| {
            p.x + 10.0 * p.y + 100.0 * p.z
        })
        .unwrap();
        assert_eq!(grid.values().len(), 60);
        let p = grid.corner_position(2, 1, 3);
        assert_eq!(p, Vec3::new(2.0, 2.5, 4.5));
        assert_eq!(grid.value(2, 1, 3), Some(p.x + 10.0 * p.y + 100.0 * p.z));
        assert_eq!(
            grid.values()[2 + 3 * (1 + 4 * 3)],
            grid.value(2, 1, 3).unwrap()
        );
        assert_eq!(grid.value(3, 0, 0), None);
    }

    #[test]
    fn rejects_bad_shapes() {
        let o = Vec3::ZERO;
        assert_eq!(
            ScalarGrid::new(o, 0.0, [2, 2, 2], vec![0.0; 8]),
            Err(GridError::Spacing(0.0))
        );
        assert!(matches!(
            ScalarGrid::new(o, f32::NAN, [2, 2, 2], vec![0.0; 8]),
            Err(GridError::Spacing(_))
        ));
        assert!(matches!(
            ScalarGrid::new(Vec3::splat(f32::INFINITY), 1.0, [2, 2, 2], vec![0.0; 8]),
            Err(GridError::Origin(_))
        ));
        assert_eq!(
            ScalarGrid::new(o, 1.0, [2, 2, 2], vec![0.0; 7]),
            Err(GridError::ValueCount {
                dims: [2, 2, 2],
                expected: 8,
                got: 7
            })
        );
        assert_eq!(
            ScalarGrid::new(o, 1.0, [usize::MAX, 2, 1], vec![]),
            Err(GridError::TooLarge {
                dims: [usize::MAX, 2, 1]
            })
        );
    }
}
