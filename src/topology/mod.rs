//! `ConstrainTopology(M, Θ)` (paper §4.3, thesis §3.4.4–3.4.7): gives a tracked mesh the topology of
//! a voxelized implicit surface Θ by re-sampling it, only where the two differ deeply, with Θ's
//! isosurface — robustly: the result is always closed, 2-manifold and consistently oriented, with
//! Θ's components and Euler characteristics (see [`constrain_topology`]).
//!
//! The steps (design note `notes/topology.md` §2):
//! 1. rasterize the mesh on Θ's grid with exact, perturbed predicates ([`crate::grid`]);
//! 2. classify the cells where mesh and Θ differ deeply, and grow that region until its boundary is
//!    simple ([`classify`], [`region`]);
//! 3. cut the mesh exactly along the region's boundary ([`clip`], [`cut`]);
//! 4. fill the region with Θ's isosurface, stitched to the cut point for point ([`fill`]);
//! 5. assemble, verify, record events ([`build`], [`record`], [`constrain`]).

mod build;
mod classify;
mod clip;
mod constrain;
mod cut;
mod distance;
mod error;
mod face_arcs;
mod field;
mod fill;
mod isosurface;
mod keys;
mod mesh_grid;
mod options;
mod place;
mod points;
mod record;
mod region;
mod report;
mod segment;
mod triangulate;

pub use constrain::constrain_topology;
pub use distance::PHI_HALF_WIDTH;
pub use error::TopologyError;
pub use field::Field;
pub use options::TopologyOptions;
pub use report::{Resampling, TopologyReport};
