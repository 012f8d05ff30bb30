use thiserror::Error;

/// Why a mesh is not a closed, consistently oriented 2-manifold with finite, non-degenerate faces.
///
/// Every variant names the first offending element so a user can find it in their file
/// (indices are 0-based into the mesh's vertex and triangle arrays).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MeshError {
    #[error("mesh is empty (no triangles)")]
    Empty,
    #[error(
        "triangle {triangle} references vertex {vertex}, but the mesh has only {count} vertices"
    )]
    IndexOutOfRange {
        triangle: usize,
        vertex: u32,
        count: usize,
    },
    #[error("vertex {vertex} has a non-finite coordinate {position:?}")]
    NonFiniteCoordinate { vertex: usize, position: [f32; 3] },
    #[error("triangle {triangle} is degenerate (zero area or repeated vertex)")]
    DegenerateFace { triangle: usize },
    #[error("open boundary: edge ({a}, {b}) belongs to only one triangle ({triangle})")]
    OpenBoundary { a: u32, b: u32, triangle: usize },
    #[error("non-manifold edge ({a}, {b}) is shared by {count} triangles")]
    NonManifoldEdge { a: u32, b: u32, count: usize },
    #[error("non-manifold vertex {vertex}: its triangles form {fans} separate fans (bow-tie)")]
    NonManifoldVertex { vertex: u32, fans: usize },
    #[error(
        "inconsistent orientation: edge ({a}, {b}) is traversed in the same direction by triangles {t0} and {t1}"
    )]
    InconsistentOrientation {
        a: u32,
        b: u32,
        t0: usize,
        t1: usize,
    },
    #[error("isolated vertex {vertex} belongs to no triangle")]
    IsolatedVertex { vertex: usize },
    #[error("patch replacement: {0}")]
    Replacement(#[from] ReplacementError),
    #[error("half-edge structure corrupt: {0}")]
    Corrupt(String),
}

impl MeshError {
    /// The vertices of the mesh with `triangles` that this error names: the corners of a
    /// degenerate triangle, the ends of an edge, one vertex; none for an error about the whole
    /// mesh. A repair grows the region it re-samples around them.
    pub fn vertices(&self, triangles: &[[u32; 3]]) -> Vec<u32> {
        match *self {
            Self::DegenerateFace { triangle } => {
                triangles.get(triangle).map_or(Vec::new(), |t| t.to_vec())
            }
            Self::OpenBoundary { a, b, .. }
            | Self::NonManifoldEdge { a, b, .. }
            | Self::InconsistentOrientation { a, b, .. } => vec![a, b],
            Self::NonManifoldVertex { vertex, .. } => vec![vertex],
            Self::IsolatedVertex { vertex } | Self::NonFiniteCoordinate { vertex, .. } => {
                vec![vertex as u32]
            }
            _ => Vec::new(),
        }
    }
}

/// Why a replacement's record does not account for its surface.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ReplacementError {
    #[error(
        "vertex {id} appears in the surface but the mesh has no such vertex and nothing creates it"
    )]
    Unrecorded { id: u64 },
    #[error("vertex {id} leaves the mesh but nothing removes it")]
    Vanished { id: u64 },
    #[error("vertex {id} is created twice, or with an id already handed out")]
    Reused { id: u64 },
    #[error("vertex {id} is created but not in the surface")]
    Lost { id: u64 },
    #[error("vertex {id} is removed but was not in the mesh, or is still in the surface")]
    NotRemovable { id: u64 },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_error_names_the_vertices_of_its_element() {
        let triangles = [[0, 1, 2], [2, 1, 3]];
        let degenerate = MeshError::DegenerateFace { triangle: 1 };
        assert_eq!(degenerate.vertices(&triangles), vec![2, 1, 3]);
        let edge = MeshError::NonManifoldEdge {
            a: 4,
            b: 7,
            count: 4,
        };
        assert_eq!(edge.vertices(&triangles), vec![4, 7]);
        let bowtie = MeshError::NonManifoldVertex { vertex: 5, fans: 2 };
        assert_eq!(bowtie.vertices(&triangles), vec![5]);
        assert!(MeshError::Empty.vertices(&triangles).is_empty());
        let missing = MeshError::DegenerateFace { triangle: 9 };
        assert!(missing.vertices(&triangles).is_empty());
    }
}
