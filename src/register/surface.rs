//! The source mesh as the two stages see it: positions in solver coordinates and the connectivity
//! both need (vertex adjacency for geodesics and regularization, vertex faces for normals).

use glam::{DVec3, Vec3};

use super::adjacency::VertexAdjacency;
use super::model::Units;
use super::normals::VertexFaces;

#[derive(Debug, Clone)]
pub struct Surface {
    pub units: Units,
    /// Positions in solver coordinates.
    pub rest: Vec<DVec3>,
    pub adjacency: VertexAdjacency,
    pub faces: VertexFaces,
}

impl Surface {
    /// `unit` is the mesh's mean edge length (positive).
    pub fn new(positions: &[Vec3], triangles: &[[u32; 3]], unit: f32) -> Self {
        let units = Units::new(positions, unit);
        Self {
            units,
            rest: positions.iter().map(|&p| units.to_local(p)).collect(),
            adjacency: VertexAdjacency::new(positions.len(), triangles),
            faces: VertexFaces::new(positions.len(), triangles),
        }
    }
}
