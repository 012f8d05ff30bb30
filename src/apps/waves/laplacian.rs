//! The discrete Laplace–Beltrami operator of a triangle mesh with cotangent weights and a lumped
//! (barycentric) mass matrix, the operator of the paper's wave equation (§5, eq. 1, after Botsch et
//! al. 2010): `Δh ≈ M⁻¹ L h` with `(L h)_i = Σ_j w_ij (h_j − h_i)`, `w_ij = ½ (cot α_ij + cot β_ij)`
//! and `M_ii` a third of the area of the triangles around vertex `i`.
//!
//! Built once per tracked frame, since the surface moves; sums run in f64 and in triangle order,
//! so the operator is deterministic.

use crate::mesh::IndexedMesh;

/// `L` as per-vertex neighbour lists (compressed rows) and the lumped mass `M`.
#[derive(Debug, Clone, PartialEq)]
pub struct Laplacian {
    /// Row `i`'s neighbours are `neighbours[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    neighbours: Vec<u32>,
    weights: Vec<f64>,
    mass: Vec<f64>,
}

impl Laplacian {
    /// The cotangent Laplacian and barycentric mass of `mesh`. A vertex on no triangle (or only on
    /// degenerate ones) has no neighbours and zero mass; [`Self::apply_inverse_mass`] leaves it at 0.
    pub fn of(mesh: &IndexedMesh) -> Self {
        let n = mesh.positions.len();
        let mut entries: Vec<(u32, u32, f64)> = Vec::with_capacity(mesh.triangles.len() * 6);
        let mut mass = vec![0.0f64; n];
        for tri in &mesh.triangles {
            let p = tri.map(|v| mesh.positions[v as usize].as_dvec3());
            let double_area = (p[1] - p[0]).cross(p[2] - p[0]).length();
            if double_area <= 0.0 || !double_area.is_finite() {
                continue;
            }
            for k in 0..3 {
                mass[tri[k] as usize] += double_area / 6.0;
                let (i, j, o) = (tri[(k + 1) % 3], tri[(k + 2) % 3], k);
                let (a, b) = (p[(o + 1) % 3] - p[o], p[(o + 2) % 3] - p[o]);
                let cot = a.dot(b) / double_area;
                entries.push((i, j, 0.5 * cot));
                entries.push((j, i, 0.5 * cot));
            }
        }
        entries.sort_by_key(|x| (x.0, x.1));
        let mut offsets = vec![0usize; n + 1];
        let mut neighbours = Vec::with_capacity(entries.len() / 2);
        let mut weights = Vec::with_capacity(entries.len() / 2);
        for group in entries.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let (i, j) = (group[0].0, group[0].1);
            neighbours.push(j);
            weights.push(group.iter().map(|e| e.2).sum());
            offsets[i as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        Self {
            offsets,
            neighbours,
            weights,
            mass,
        }
    }

    pub fn len(&self) -> usize {
        self.mass.len()
    }

    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// The lumped mass (area) of each vertex.
    pub fn mass(&self) -> &[f64] {
        &self.mass
    }

    /// `(j, w_ij)` for the neighbours `j` of vertex `i`.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.offsets[i]..self.offsets[i + 1];
        self.neighbours[range.clone()]
            .iter()
            .zip(&self.weights[range])
            .map(|(&j, &w)| (j as usize, w))
    }

    /// `out = M⁻¹ L h`: the discrete Laplace–Beltrami of `h` at every vertex.
    pub fn apply_inverse_mass(&self, h: &[f64], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            let m = self.mass[i];
            *o = if m > 0.0 {
                self.row(i).map(|(j, w)| w * (h[j] - h[i])).sum::<f64>() / m
            } else {
                0.0
            };
        }
    }

    /// The Dirichlet energy `½ Σ_edges w_ij (h_i − h_j)² = −½ hᵀ L h`, the potential of the wave
    /// equation per unit c².
    pub fn dirichlet_energy(&self, h: &[f64]) -> f64 {
        (0..self.len())
            .map(|i| {
                self.row(i)
                    .filter(|&(j, _)| j > i)
                    .map(|(j, w)| w * (h[i] - h[j]).powi(2))
                    .sum::<f64>()
            })
            .sum::<f64>()
            * 0.5
    }

    /// An upper bound on the largest eigenvalue of `−M⁻¹ L` (Gershgorin, on each row
    /// `2 Σ_j |w_ij| / m_i`): the square of the highest angular frequency the mesh can carry per
    /// unit wave speed, which sets the stable time step.
    pub fn max_eigenvalue_bound(&self) -> f64 {
        (0..self.len())
            .filter(|&i| self.mass[i] > 0.0)
            .map(|i| 2.0 * self.row(i).map(|(_, w)| w.abs()).sum::<f64>() / self.mass[i])
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn rows_sum_to_zero_and_mass_sums_to_the_area() {
        let mesh = IndexedMesh::icosphere(Vec3::ZERO, 2.0, 3);
        let lap = Laplacian::of(&mesh);
        let mut out = vec![1.0; lap.len()];
        lap.apply_inverse_mass(&vec![3.5; lap.len()], &mut out);
        assert!(out.iter().all(|v| v.abs() < 1e-9), "constant field");
        let area: f64 = lap.mass().iter().sum();
        let sphere = 4.0 * std::f64::consts::PI * 4.0;
        assert!((area - sphere).abs() / sphere < 0.01, "{area} vs {sphere}");
    }

    #[test]
    fn the_laplacian_is_symmetric() {
        let mesh = IndexedMesh::torus(1.0, 0.4, 24, 12);
        let lap = Laplacian::of(&mesh);
        for i in 0..lap.len() {
            for (j, w) in lap.row(i) {
                let back = lap.row(j).find(|&(k, _)| k == i).map(|(_, w)| w);
                assert_eq!(back, Some(w), "w[{i}][{j}]");
            }
        }
    }
}
