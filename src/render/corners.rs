//! A frame as the rasterizer takes it: every triangle's three corners with position, normal and
//! colour, the normal the face's (flat shading) or the vertex's (smooth).

use crate::mesh::{IndexedMesh, NormalWeighting};
use bytemuck::{Pod, Zeroable};

/// One corner, as `render.wgsl`'s `Corner` reads it (three `vec4<f32>`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Corner {
    pub position: [f32; 4],
    pub normal: [f32; 4],
    pub colour: [f32; 4],
}

/// How normals vary over a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shading {
    /// One normal per triangle: facets show.
    Flat,
    /// Vertex normals interpolated: a smooth surface.
    Smooth,
    /// No lighting: every pixel shows its colour exactly.
    Unlit,
}

/// The corners of every triangle of `mesh`, coloured by `colours` (one per vertex).
pub fn corners(mesh: &IndexedMesh, colours: &[[f32; 3]], shading: Shading) -> Vec<Corner> {
    let vertex_normals = match shading {
        Shading::Smooth => mesh.vertex_normals(NormalWeighting::Angle),
        Shading::Flat | Shading::Unlit => Vec::new(),
    };
    let face_normals = match shading {
        Shading::Flat | Shading::Unlit => mesh.face_normals(),
        Shading::Smooth => Vec::new(),
    };
    let mut out = Vec::with_capacity(mesh.triangles.len() * 3);
    for (f, triangle) in mesh.triangles.iter().enumerate() {
        for &v in triangle {
            let v = v as usize;
            let normal = match shading {
                Shading::Smooth => vertex_normals[v],
                Shading::Flat | Shading::Unlit => face_normals[f],
            };
            let [r, g, b] = colours[v];
            out.push(Corner {
                position: mesh.positions[v].extend(1.0).to_array(),
                normal: normal.extend(0.0).to_array(),
                colour: [r, g, b, 1.0],
            });
        }
    }
    out
}
