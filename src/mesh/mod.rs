//! Triangle meshes: the indexed form every reader and writer speaks, and the half-edge form the
//! tracker mutates (split, collapse, flip) while keeping persistent vertex ids.

mod check;
mod continuing;
mod error;
mod halfedge;
mod indexed;
mod mutate;
mod mutation;
mod normals;
mod primitives;
mod quality;
mod replace;
mod topology;
mod validate;

pub use error::{MeshError, ReplacementError};
pub use halfedge::{FaceId, HalfEdgeId, Mesh, Outgoing, VertexId};
pub use indexed::{Attribute, IndexedMesh};
pub use mutation::Mutation;
pub use normals::NormalWeighting;
pub use quality::{QualityStats, aspect_ratio, min_angle_degrees};
pub use replace::Replacement;
pub use topology::{ComponentTopology, Topology};
pub(crate) use validate::degenerate_triangle;
