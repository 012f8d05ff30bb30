//! Mirrors of `kernels/shared/bvh.wgsl`: the flattened BVH and the records of one query.

mod correspondence;
mod node;
mod query_params;
mod triangle;

pub use correspondence::{Correspondence, Status};
pub use node::{BvhChild, BvhNode};
pub use query_params::QueryParams;
pub use triangle::{BvhTriangle, NormalTriple, PseudoNormals};
