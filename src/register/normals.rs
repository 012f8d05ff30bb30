//! Vertex normals of the mesh being deformed, recomputed whenever correspondences are: the rays of
//! paper §4.2 leave the deformed surface, not the rest one.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::model::CHUNK;

/// The triangles around each vertex, and the triangles themselves, for gathering normals in
/// parallel.
#[derive(Debug, Clone)]
pub struct VertexFaces {
    around: crate::geometry::VertexFaces,
    triangles: Vec<[u32; 3]>,
}

impl VertexFaces {
    pub fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Self {
        Self {
            around: crate::geometry::VertexFaces::new(vertex_count, triangles),
            triangles: triangles.to_vec(),
        }
    }

    /// The mesh's triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Unit vertex normals with Max's weights (as `IndexedMesh::vertex_normals` with
    /// `NormalWeighting::Max`), each vertex summing its triangles in index order.
    pub fn normals(&self, positions: &[DVec3]) -> Vec<Vec3> {
        let all: Vec<u32> = (0..positions.len() as u32).collect();
        self.normals_of(positions, &all)
    }

    /// The normals of `vertices` only.
    pub fn normals_of(&self, positions: &[DVec3], vertices: &[u32]) -> Vec<Vec3> {
        vertices
            .par_iter()
            .with_min_len(CHUNK)
            .map(|&v| {
                let v = v as usize;
                let faces = self.around.around(v as u32);
                let mut n = DVec3::ZERO;
                for &t in faces {
                    let tri = self.triangles[t as usize];
                    let k = tri.iter().position(|&u| u as usize == v).unwrap_or(0);
                    let p = positions[v];
                    let e1 = positions[tri[(k + 1) % 3] as usize] - p;
                    let e2 = positions[tri[(k + 2) % 3] as usize] - p;
                    let d = e1.length_squared() * e2.length_squared();
                    if d > 0.0 {
                        n += e1.cross(e2) / d;
                    }
                }
                n.normalize_or_zero().as_vec3()
            })
            .collect()
    }
}
