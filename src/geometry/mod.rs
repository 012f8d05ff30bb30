//! Spatial queries that several stages share, each defined once: the point of a triangle nearest
//! to a point, and the triangles around each vertex.

pub mod point_triangle;
mod vertex_faces;

pub use point_triangle::{Region, point_triangle_distance, region};
pub use vertex_faces::VertexFaces;
