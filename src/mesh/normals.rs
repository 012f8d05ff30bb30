//! Vertex normals. Projection casts rays along them (paper §4.2), so their quality matters: Max's
//! weights (`004_…`, "Mesh Processing") are exact for vertices on a sphere.

use super::IndexedMesh;
use glam::Vec3;

/// How face normals are combined into a vertex normal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalWeighting {
    /// Unnormalised face normals summed: weight ∝ face area.
    Area,
    /// Unit face normals weighted by the interior angle at the vertex.
    Angle,
    /// Max (1999): face normal × sin(angle) / (|e1|·|e2|), i.e. cross(e1, e2) / (|e1|²·|e2|²).
    Max,
}

impl IndexedMesh {
    /// Unit vertex normals (zero for a vertex with no non-degenerate incident face), accumulated in f64
    /// in triangle order so the result is deterministic.
    pub fn vertex_normals(&self, weighting: NormalWeighting) -> Vec<Vec3> {
        let mut acc = vec![glam::DVec3::ZERO; self.positions.len()];
        for tri in &self.triangles {
            let p = tri.map(|v| self.positions[v as usize].as_dvec3());
            for k in 0..3 {
                let e1 = p[(k + 1) % 3] - p[k];
                let e2 = p[(k + 2) % 3] - p[k];
                let cross = e1.cross(e2);
                let contribution = match weighting {
                    NormalWeighting::Area => cross,
                    NormalWeighting::Angle => {
                        let angle = e1.angle_between(e2);
                        cross.normalize_or_zero() * angle
                    }
                    NormalWeighting::Max => {
                        let d = e1.length_squared() * e2.length_squared();
                        if d > 0.0 {
                            cross / d
                        } else {
                            glam::DVec3::ZERO
                        }
                    }
                };
                acc[tri[k] as usize] += contribution;
            }
        }
        acc.iter()
            .map(|n| n.normalize_or_zero().as_vec3())
            .collect()
    }

    /// Unit face normals (CCW seen from outside points outward).
    pub fn face_normals(&self) -> Vec<Vec3> {
        self.triangles
            .iter()
            .map(|tri| {
                let p = tri.map(|v| self.positions[v as usize]);
                (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
            })
            .collect()
    }

    /// Signed enclosed volume (divergence theorem); positive for an outward-oriented closed surface.
    pub fn signed_volume(&self) -> f64 {
        self.signed_volume_of(0..self.triangles.len() as u32)
    }

    /// [`IndexedMesh::signed_volume`] of the triangles `triangles` alone, summed in their order.
    pub fn signed_volume_of(&self, triangles: impl IntoIterator<Item = u32>) -> f64 {
        triangles
            .into_iter()
            .map(|t| {
                let p = self.triangles[t as usize].map(|v| self.positions[v as usize].as_dvec3());
                p[0].dot(p[1].cross(p[2])) / 6.0
            })
            .sum()
    }
}
