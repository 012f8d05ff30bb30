use thiserror::Error;

use crate::compute::ComputeError;
use crate::kernels::shared::{MAX_CELL_INDEX, MAX_TRIANGLE_SPAN};

/// Why a mesh could not be rasterized, swept or turned into a distance field.
///
/// Bad input (a coordinate, an index, a triangle too large for the exact predicates) is kept apart
/// from a failing GPU so callers can fix the input or fall back to the CPU as fits.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum RasterError {
    #[error("grid spacing must be finite and positive, got {0}")]
    Spacing(f32),
    #[error("grid origin must be finite, got {0:?}")]
    Origin([f32; 3]),
    #[error("the mesh has no edges, so no spacing can be derived from its mean edge length")]
    NoEdges,
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite { vertex: usize },
    #[error(
        "vertex {vertex} lies {cells:e} cells from the grid origin; at most {MAX_CELL_INDEX} cells are addressable"
    )]
    OutOfRange { vertex: usize, cells: f64 },
    #[error("triangle {triangle} references vertex {vertex}, but there are only {count} vertices")]
    IndexOutOfRange {
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    #[error(
        "triangle {triangle} spans {span} cells along axis {axis}; at most {MAX_TRIANGLE_SPAN} are supported (use a coarser grid or a finer mesh)"
    )]
    TriangleTooLarge {
        triangle: usize,
        axis: usize,
        span: i64,
    },
    #[error("narrow band half-width must be finite and positive (in cells), got {0}")]
    Band(f32),
    #[error("{0} items exceed the 32-bit indices the GPU buffers use")]
    TooManyItems(usize),
    #[error(transparent)]
    Compute(#[from] ComputeError),
}
