//! The fine stage's cover term (see `register::fine`): each pair's three source vertices with
//! their barycentric weights `w`, its matrix `M = s α_plane n nᵀ` and its target point `t` (solver
//! coordinates), contributing `rᵀ M r` with `r = Σ_k w_k (p_k + d_k) − t`; and per vertex the
//! (pair, corner) entries that touch it, in pair order, as compressed rows. The pairs are fixed for
//! the whole stage, so this is built, and on the GPU path uploaded, once.

use glam::{DMat3, DVec3};

use super::RegisterError;
use super::correspond::CoverPairs;
use super::fine_solve::outer;
use super::model::ordered_sum;
use super::options::FineOptions;
use super::surface::Surface;

#[derive(Debug, Default)]
pub struct Cover {
    pub corners: Vec<[u32; 3]>,
    pub weights: Vec<[f64; 3]>,
    pub matrices: Vec<DMat3>,
    /// `t − Σ_k w_k p_k`: the pull at zero displacement.
    pub gaps: Vec<DVec3>,
    /// `M (t − Σ_k w_k p_k)`: the pair's part of the right-hand side, before its weight `w`.
    pub pulls: Vec<DVec3>,
    pub offsets: Vec<u32>,
    /// `pair << 2 | corner` per entry.
    pub entries: Vec<u32>,
}

/// How much harder than the configured weight a pair pulls whose target sample lies `gap` (solver
/// units: mean edge lengths) from the source: `(gap / cover_min_distance)^cover_growth`, at least 1.
/// A sample just past the minimum distance is mostly the target's triangulation noise, and pulling
/// it hard moves the surface along with the noise (drift); a sample a cell or more away is a
/// feature the source lacks — a splash sheet or strand no source normal ray reaches (paper §4.2:
/// "we do not guarantee that every target surface region will have a corresponding source
/// point") — and left behind there, the mesh is re-sampled by the topology step (§4.3) in the
/// next frame and the next.
fn growth(gap: f64, options: &FineOptions) -> f64 {
    if options.cover_growth == 0.0 {
        return 1.0;
    }
    (gap / options.cover_min_distance)
        .max(1.0)
        .powf(options.cover_growth)
}

impl Cover {
    /// Fails when the pairs are too many for the 32-bit entry indices the kernels read.
    pub fn new(
        pairs: &CoverPairs,
        surface: &Surface,
        start: &[DVec3],
        options: &FineOptions,
    ) -> Result<Self, RegisterError> {
        if pairs.hits.len() > (u32::MAX >> 2) as usize / 3 {
            return Err(RegisterError::TooLarge {
                what: "cover pairs",
                count: pairs.hits.len(),
            });
        }
        let triangles = surface.faces.triangles();
        let scale = options.cover_weight * start.len() as f64 / pairs.samples.max(1) as f64;
        let mut cover = Cover::default();
        for hit in &pairs.hits {
            let Some(&corners) = triangles.get(hit.triangle as usize) else {
                continue;
            };
            let n = hit.normal.as_dvec3().normalize_or_zero();
            let w = hit.barycentric.as_dvec3().to_array();
            let at = w[0] * start[corners[0] as usize]
                + w[1] * start[corners[1] as usize]
                + w[2] * start[corners[2] as usize];
            let gap = surface.units.to_local(hit.point) - at;
            let matrix = outer(n) * (options.plane_weight * scale * growth(gap.length(), options));
            cover.corners.push(corners);
            cover.weights.push(w);
            cover.matrices.push(matrix);
            cover.gaps.push(gap);
            cover.pulls.push(matrix * gap);
        }
        let mut offsets = vec![0u32; start.len() + 1];
        for corners in &cover.corners {
            for &v in corners {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..start.len() {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets[..start.len()].to_vec();
        let mut entries = vec![0u32; offsets[start.len()] as usize];
        for (p, corners) in cover.corners.iter().enumerate() {
            for (k, &v) in corners.iter().enumerate() {
                entries[fill[v as usize] as usize] = (p as u32) << 2 | k as u32;
                fill[v as usize] += 1;
            }
        }
        cover.offsets = offsets;
        cover.entries = entries;
        Ok(cover)
    }

    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// `Σ_k w_k x_k` for pair `p`.
    fn blend(&self, p: usize, x: &[DVec3]) -> DVec3 {
        let [a, b, c] = self.corners[p];
        let [wa, wb, wc] = self.weights[p];
        wa * x[a as usize] + wb * x[b as usize] + wc * x[c as usize]
    }

    /// The entries touching vertex `v` (none when the term is empty).
    pub fn entries(&self, v: usize) -> &[u32] {
        match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&from), Some(&to)) => &self.entries[from as usize..to as usize],
            _ => &[],
        }
    }

    /// `Σ rᵀ M r` at displacements `d`.
    pub fn energy(&self, d: &[DVec3]) -> f64 {
        ordered_sum(self.len(), |p| {
            let r = self.blend(p, d) - self.gaps[p];
            r.dot(self.matrices[p] * r)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::register::correspond::CoverHit;
    use glam::Vec3;

    /// A pair whose sample lies `gap` mean edge lengths above the centre of a unit triangle.
    fn hit(surface: &Surface, gap: f64) -> CoverHit {
        let centre = surface.rest.iter().sum::<DVec3>() / 3.0;
        CoverHit {
            point: surface.units.to_world(centre + DVec3::Z * gap),
            normal: Vec3::Z,
            triangle: 0,
            barycentric: Vec3::splat(1.0 / 3.0),
        }
    }

    /// The weight each pair's matrix carries along the normal.
    fn weights(growth: f64, gaps: &[f64]) -> Vec<f64> {
        let positions = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let surface = Surface::new(&positions, &[[0, 1, 2]], 2.0);
        let pairs = CoverPairs {
            hits: gaps.iter().map(|&g| hit(&surface, g)).collect(),
            samples: gaps.len(),
        };
        let options = FineOptions {
            cover_growth: growth,
            ..FineOptions::default()
        };
        let cover = Cover::new(&pairs, &surface, &surface.rest, &options).unwrap();
        cover.matrices.iter().map(|m| m.z_axis.z).collect()
    }

    #[test]
    fn a_pair_pulls_harder_the_farther_its_sample_lies() {
        // The minimum distance is 0.25: a sample at 0.5 pulls twice, at 1.0 four times as hard
        // as one at or within it.
        let grown = weights(1.0, &[0.1, 0.25, 0.5, 1.0]);
        let base = grown[0];
        assert!(base > 0.0);
        for (w, factor) in grown.iter().zip([1.0, 1.0, 2.0, 4.0]) {
            assert!((w / base - factor).abs() < 1e-9, "{grown:?}");
        }
        let squared = weights(2.0, &[0.25, 1.0]);
        assert!((squared[1] / squared[0] - 16.0).abs() < 1e-9, "{squared:?}");
        let flat = weights(0.0, &[0.25, 0.5, 1.0]);
        assert!(flat.iter().all(|&w| w == flat[0]), "{flat:?}");
    }

    #[test]
    fn a_growing_weight_needs_a_minimum_distance_to_grow_from() {
        let mut options = crate::register::RegisterOptions::default();
        options.fine.cover_min_distance = 0.0;
        assert!(options.check().is_err());
        options.fine.cover_growth = 0.0;
        assert!(options.check().is_ok());
        options.fine.cover_growth = -1.0;
        options.fine.cover_min_distance = 0.25;
        assert!(options.check().is_err());
    }
}
