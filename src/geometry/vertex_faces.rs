//! The triangles around each vertex, for gathering per-vertex quantities in parallel.

use crate::grid::row_starts;

/// The triangles around each vertex, in triangle order (compressed rows), built by a counting
/// sort so the rows are the same whatever the thread count.
#[derive(Debug, Clone)]
pub struct VertexFaces {
    start: Vec<u32>,
    faces: Vec<u32>,
}

impl VertexFaces {
    /// Indices must be below `vertices`.
    pub fn new(vertices: usize, triangles: &[[u32; 3]]) -> Self {
        let mut corners = vec![0u32; vertices];
        for &v in triangles.iter().flatten() {
            corners[v as usize] += 1;
        }
        let start = row_starts(corners);
        let mut next = start.clone();
        let mut faces = vec![0u32; start[vertices] as usize];
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                faces[next[v as usize] as usize] = t as u32;
                next[v as usize] += 1;
            }
        }
        Self { start, faces }
    }

    pub fn vertices(&self) -> usize {
        self.start.len() - 1
    }

    /// The triangles having vertex `v` as a corner, ascending.
    pub fn around(&self, v: u32) -> &[u32] {
        &self.faces[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }
}
