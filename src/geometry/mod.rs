//! Spatial queries and measures that several stages share, each defined once: the box around
//! points, the point of a triangle nearest to a point, the triangles around each vertex, the
//! components of a mesh, the minimum-angle buckets.

mod bounds;
mod components;
mod histogram;
pub mod point_triangle;
mod vertex_faces;

pub use bounds::bounds;
pub use components::Components;
pub use histogram::{ANGLE_BUCKETS, bucket};
pub use point_triangle::{Region, point_triangle_distance, region};
pub use vertex_faces::VertexFaces;
