//! `ConstrainTopology(M, Θ)` (paper §4.3, thesis §3.4.4–3.4.7): gives a tracked mesh the topology of
//! a voxelized implicit surface Θ by re-sampling it, only where the two differ deeply, with Θ's
//! isosurface — robustly: the result is always closed, 2-manifold and consistently oriented, with
//! Θ's components and Euler characteristics (see [`constrain_topology`]).
//!
//! The steps, one module each (after the design note `notes/topology.md` §2):
//! 1. `mesh_grid`: the mesh on Θ's grid, rasterized with exact, perturbed predicates
//!    ([`crate::grid`]), and `segment`: the same predicates for mesh edges against grid planes;
//! 2. `classify`: the cells where mesh and Θ differ deeply; `region`, `face_arcs`: growth of that
//!    region until the cut can run along its boundary;
//! 3. `clip`, `cut`, `triangulate`: the mesh cut exactly along the region's boundary;
//! 4. `fill`: Θ's isosurface inside the region, stitched to the cut point for point;
//! 5. `place`, `build`: positions and assembly; `constrain`: verification and the ladder of
//!    attempts; `record`: events (paper §4.4);
//!
//! with `field` and `distance` for Θ itself and `isosurface` for the topology it prescribes.

mod build;
mod classify;
mod clip;
mod clusters;
mod constrain;
mod cut;
mod distance;
mod droplets;
mod error;
mod face_arcs;
mod field;
mod fill;
mod isosurface;
mod keys;
mod mesh_grid;
mod mismatch;
mod move_onto;
mod narrow;
mod nearest;
mod options;
mod place;
mod points;
mod record;
mod region;
mod report;
mod segment;
pub mod subgrid;
mod theta_surface;
mod transfer;
mod triangulate;

pub use constrain::{constrain_topology, constrain_topology_on};
pub use distance::PHI_HALF_WIDTH;
pub(crate) use droplets::{cell, droplets};
pub use error::TopologyError;
pub use field::Field;
pub use mesh_grid::MeshRaster;
pub use options::{CONTINUE_WITHIN, Moves, TopologyOptions};
pub use report::{Abandoned, Resampling, TopologyReport};
pub use theta_surface::ThetaSurface;
pub use transfer::Carry;
