//! Correspondence projection (paper §4.2): where each point of the tracked mesh lands on the
//! target frame.
//!
//! The coarse and fine registration stages pair every source vertex with a target point found by
//! casting its normal ray both ways and keeping the nearest hit, pruned when the normals differ by
//! more than 60° or the hit is too far ([`project`]); evaluation and the fine stage also need the
//! nearest surface point with a sign ([`closest_points`]).
//!
//! Both queries traverse one [`Bvh`] per target frame: built on the CPU with binned SAH over the
//! triangles' boxes ([`triangle_bounds`]) and flattened into a node array that the CPU twins
//! (`src/project/cpu/`) and the WGSL kernels (`kernels/project.wgsl`,
//! `kernels/closest_point.wgsl`) read alike. Each query is a stack traversal, nearest child first
//! (`cpu/traversal.rs`, `kernels/shared/bvh.wgsl`), with the watertight ray–triangle test of Woop,
//! Benthin & Wald (2013), so rays aimed exactly at shared edges and vertices never slip through.
//! The CPU path runs one query per rayon task, so its results do not depend on the thread count;
//! the GPU path keeps the BVH on the device between queries against the same frame.
//!
//! Every stage here has the shape of `crate::kernels`: a dispatcher (`query.rs`,
//! `triangle_bounds.rs`), CPU twins in `cpu/`, GPU hosts in `gpu/`.

mod build;
mod bvh;
mod cast;
mod cells;
pub mod cpu;
mod directions;
mod error;
mod gpu;
mod indices;
mod options;
mod order;
mod query;
mod shading;
mod slab;
mod triangle_bounds;
mod watertight;

pub use crate::kernels::shared::{
    BvhChild, BvhNode, BvhTriangle, Correspondence, NormalTriple, PseudoNormals, QueryParams,
    Status,
};
pub use bvh::Bvh;
pub use cells::Cells;
pub use error::ProjectError;
pub use gpu::{GpuBvh, GpuQueries, GpuTriangleBounds};
pub use options::ProjectOptions;
pub use query::{closest_points, project};
pub use triangle_bounds::triangle_bounds;
