use thiserror::Error;

use crate::mesh::MeshError;

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
    Correspondence(String),
    #[error("sparse factorization failed: {0}")]
    Factorization(String),
}
