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
pub use scalar_grid::{GridError, MAX_CORNERS, ScalarGrid};

mod band;
mod crossing;
mod distance;
mod distance_cpu;
mod distance_gpu;
mod lattice;
mod overlap;
mod predicates;
mod raster_error;
mod rasterize;
mod rasterize_gpu;
mod sparse;
mod sweep;
mod sweep_gpu;
mod triangle_tree;

pub use crossing::GridCrossing;
pub use distance::{BandChunk, BandTile, NarrowBand, Nearest, signed_distance};
pub use distance_gpu::DistanceParams;
pub use lattice::{
    CELL_UNITS, FRACTION_BITS, GridFrame, LatticeMesh, LatticePoint, MAX_CELL_INDEX,
    MAX_TRIANGLE_SPAN, cell_key, key_cell,
};
pub use overlap::{
    EdgeFace, TriangleCells, cells_around, edge_faces, footprint, mesh_edges, triangle_cells,
};
pub use predicates::cross_axes;
pub use raster_error::RasterError;
pub use rasterize::rasterize;
pub use rasterize_gpu::GpuRasterize;
pub use sparse::{Crossings, GridLine, LineIndex};
pub use sweep::{CornerWindings, WindingRun, Windings, sweep};
pub use sweep_gpu::GpuSweep;
pub use triangle_tree::{TreeNode, TreeTriangle, TriangleBox};
