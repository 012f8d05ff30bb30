use thiserror::Error;

use crate::compute::ComputeError;
use crate::mesh::MeshError;

/// Why a BVH could not be built or a query could not run.
///
/// A target the BVH cannot be built over, a malformed query and a backend failure are kept apart:
/// the first two are the caller's input to fix, the last may be worth retrying on the CPU.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ProjectError {
    #[error("target mesh: {0}")]
    Target(MeshError),
    #[error("target mesh has {triangles} triangles; a BVH indexes at most {max}")]
    TooManyTriangles { triangles: usize, max: usize },
    #[error("{points} query points but {normals} normals: every point needs its normal")]
    LengthMismatch { points: usize, normals: usize },
    #[error("option {name} must be a non-negative number, got {value}")]
    InvalidOption { name: &'static str, value: f32 },
    #[error(transparent)]
    Compute(#[from] ComputeError),
}
