//! Regular scalar grids and their isosurfaces.
//!
//! [`marching_cubes`] extracts the closed, 2-manifold isosurface of a [`ScalarGrid`]; [`cube`] and
//! [`cases`] expose its cell numbering, its per-face rule and its case table, which the topology
//! stage reuses so its fills agree face by face with every marching-cubes surface (paper §4.3).

pub mod cases;
pub mod cube;
mod inside_bits;
mod marching_cubes;
mod scalar_grid;

pub use marching_cubes::{T_MIN, marching_cubes};
pub(crate) use scalar_grid::sample_box;
pub use scalar_grid::{GridError, MAX_CORNERS, ScalarGrid};

mod band;
mod cell_box;
pub mod cpu;
mod distance;
mod gpu;
mod lattice;
mod overlap;
mod predicates;
mod raster_error;
mod rasterize;
mod sparse;
mod sweep;
mod triangle_tree;

pub use crate::kernels::shared::{
    BandChunk, BandTile, CELL_UNITS, DistanceParams, FRACTION_BITS, GridCrossing, LatticePoint,
    MAX_CELL_INDEX, MAX_TRIANGLE_SPAN, Nearest, TreeNode, TreeTriangle, TriangleBox, WindingRun,
};
pub(crate) use cell_box::CellBox;
pub use distance::{NarrowBand, signed_distance};
pub use gpu::{GpuRasterize, GpuSweep};
pub use lattice::{GridFrame, LatticeMesh, cell_key, key_cell};
pub use overlap::{
    EdgeFace, TriangleCells, cells_around, edge_faces, footprint, mesh_edges, triangle_cells,
};
pub use predicates::cross_axes;
pub(crate) use predicates::{last_above, segment_sign};
pub use raster_error::RasterError;
pub use rasterize::rasterize;
pub use sparse::{Crossings, GridLine, LineIndex};
pub(crate) use sparse::{by_slot, row_starts};
pub use sweep::{CornerWindings, Windings, sweep};
pub use triangle_tree::TriangleTree;
