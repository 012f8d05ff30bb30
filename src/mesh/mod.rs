//! Triangle meshes: the indexed form every reader and writer speaks, and the half-edge form the
//! tracker mutates (split, collapse, flip) while keeping persistent vertex ids.

mod error;
mod indexed;

pub use error::MeshError;
pub use indexed::{Attribute, IndexedMesh};
