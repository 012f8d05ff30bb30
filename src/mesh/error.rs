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
    Replacement(#[from] super::ReplacementError),
    #[error("half-edge structure corrupt: {0}")]
    Corrupt(String),
}
