//! Correspondence projection (paper §4.2): where each point of the tracked mesh lands on the
//! target frame.
//!
//! The coarse and fine registration stages pair every source vertex with a target point found by
//! casting its normal ray both ways and keeping the nearest hit, pruned when the normals differ by
//! more than 60° or the hit is too far ([`project`]); evaluation and the fine stage also need the
//! nearest surface point with a sign ([`closest_points`]).
//!
//! Both queries traverse one [`Bvh`] per target frame: built on the CPU with binned SAH and
//! flattened into a node array that the CPU twins (`src/project/cpu/`) and the WGSL kernels
//! (`kernels/project.wgsl`, `kernels/closest_point.wgsl`) read alike. Each query is a stack
//! traversal, nearest child first, with the watertight ray–triangle test of Woop, Benthin & Wald
//! (2013), so rays aimed exactly at shared edges and vertices never slip through. The CPU path
//! runs one query per rayon task, so its results do not depend on the thread count; the GPU path
//! keeps the BVH on the device between queries against the same frame.

mod adjacency;
mod build;
mod bvh;
mod cast;
mod correspondence;
pub mod cpu;
mod error;
mod gpu;
mod node;
mod options;
mod order;
mod point_triangle;
mod query;
mod shading;
mod slab;
mod triangle;
mod watertight;

pub use bvh::Bvh;
pub use correspondence::{Correspondence, Status};
pub use error::ProjectError;
pub use gpu::{GpuBvh, GpuQueries};
pub use node::{BvhChild, BvhNode};
pub use options::{ProjectOptions, QueryParams};
pub use query::{closest_points, project};
pub use triangle::{BvhTriangle, NormalTriple, PseudoNormals};
