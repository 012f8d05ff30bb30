use thiserror::Error;

use super::Abandoned;
use crate::grid::RasterError;
use crate::mesh::MeshError;
use crate::project::ProjectError;

/// Why `constrain_topology` or the construction of Θ failed.
///
/// Input problems (a mesh that is not closed and manifold, a coordinate the grid cannot address) are
/// kept apart from [`TopologyError::Unresolved`], which would mean the method itself failed: every
/// attempt, the last of which replaces the whole surface by Θ's isosurface, produced a mesh that is
/// not closed, manifold and non-degenerate.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TopologyError {
    #[error(transparent)]
    Raster(#[from] RasterError),
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error(transparent)]
    Project(#[from] ProjectError),
    #[error("a sampled field of {dims:?} corners is too large")]
    FieldTooLarge { dims: [usize; 3] },
    #[error(
        "no valid surface after {} attempts: {}",
        abandoned.len() + 1,
        abandoned.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ")
    )]
    Unresolved { abandoned: Vec<Abandoned> },
}
