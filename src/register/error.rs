use thiserror::Error;

use crate::compute::ComputeError;
use crate::mesh::MeshError;
use crate::project::ProjectError;

/// Why a registration could not run or could not finish.
///
/// Bad input (an invalid mesh, a nonsensical option) is kept apart from numerical failure, which a
/// caller may answer differently (for instance by re-meshing the region and trying again).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RegisterError {
    #[error("registration option {name} must be {expected}, got {value}")]
    Option {
        name: &'static str,
        expected: &'static str,
        value: f64,
    },
    #[error("the {which} mesh has no edges of positive length")]
    NoScale { which: &'static str },
    #[error("the {which} mesh is invalid: {source}")]
    Mesh {
        which: &'static str,
        #[source]
        source: MeshError,
    },
    #[error("correspondence search failed: {0}")]
    Correspondence(#[source] ProjectError),
    #[error("the fine stage's {what} ({count}) are more than its 32-bit indices hold")]
    TooLarge { what: &'static str, count: usize },
    #[error("the fine stage failed on the GPU: {0}")]
    Compute(#[from] ComputeError),
    #[error("sparse factorization failed: {0}")]
    Factorization(#[from] FactorizationError),
}

/// A failure of the coarse stage's sparse Cholesky solver (after faer's `LltError`): which step
/// failed and with what, so a caller can act on it — coarsen the graph, raise the damping, free
/// memory — instead of reading a message.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FactorizationError {
    #[error("{nonzeros} nonzeros exceed the 32-bit index range; use a coarser graph")]
    TooManyNonzeros { nonzeros: usize },
    #[error("out of memory allocating the {what}")]
    OutOfMemory { what: &'static str },
    #[error("fill-reducing ordering of {unknowns} unknowns failed: {reason}")]
    Ordering { unknowns: usize, reason: String },
    #[error("symbolic analysis of {unknowns} unknowns failed: {reason}")]
    Symbolic { unknowns: usize, reason: String },
    #[error(
        "no positive definite system after {retries} damping increases (last: pivot {pivot} not positive at λ = {lambda:e})"
    )]
    NotPositiveDefinite {
        retries: usize,
        pivot: usize,
        lambda: f64,
    },
    #[error("a solve of dimension {dimension} without a matching factorization")]
    NotFactored { dimension: usize },
}
