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
