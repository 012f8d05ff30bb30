//! The fine stage (paper §4.2): per-vertex displacements `d` that bring the detail the coarse graph
//! cannot express onto the target,
//!
//! `E = Σ_v α_plane (n_v·(p_v + d_v − c_v))² + α_point |p_v + d_v − c_v|²
//!    + α_disp Σ_(i,j) |d_i − d_j|² + α_edge Σ_(i,j) (ê_ij·(d_i − d_j))²`,
//!
//! over the mesh edges `(i, j)`, with `ê_ij` the unit edge direction before the stage (so the last
//! term is the linearized change of edge length) and correspondences farther than σ pruned.
//!
//! The paper's correspondences run from the source to the target only, so a target feature no
//! source normal ray reaches — a dimple deepening faster than the mesh follows, a thin spike —
//! pulls on nothing, and the mesh lags behind it frame after frame (paper §4.2: "we do not
//! guarantee that every target surface region will have a corresponding source point"). A cover
//! term closes that gap: every target sample (triangle centroid) farther than `cover_min_distance`
//! from the source as the stage starts but within σ, whose normal agrees within the pruning angle,
//! pulls the source's nearest point, a barycentric blend of three vertices, along the target's
//! normal only (`E_plane`'s weight): a point term would also drag the surface sideways towards
//! wherever the samples sit, which is drift; and samples the source already lies close to are left
//! to `E_fit`, since there the term can only add the target's triangulation noise, which also
//! accumulates as drift. It is scaled by `cover_weight` × source vertices / target samples so that
//! both directions weigh alike at any resolution. At the defaults (weight 3, samples from 0.25 L)
//! the `morph` scene's narrowing dimple is followed within 0.69 Δ where the one-sided fit lags
//! 1.39 Δ behind, and the `rigid` scene's drift after 32 frames moves from 0.045% to 0.085% of its
//! diagonal (`surftrack synth`, `track`, `eval` at their defaults).
//!
//! `E` is quadratic; its minimizer solves `A d = b`, found by conjugate gradients preconditioned
//! with `A`'s 3×3 diagonal blocks, warm-started from the previous round's displacements.

use std::time::Instant;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::RegisterError;
use super::correspond::{Correspond, CoverPairs, targets};
use super::energy::FitTarget;
use super::model::{CHUNK, ordered_sum};
use super::options::FineOptions;
use super::report::{FineReport, FineRound};
use super::surface::Surface;
use crate::mesh::IndexedMesh;

/// Moves `start` (solver coordinates) onto the target; returns the new positions.
pub fn fine(
    correspond: &dyn Correspond,
    surface: &Surface,
    start: &[DVec3],
    options: &FineOptions,
) -> Result<(Vec<DVec3>, FineReport), RegisterError> {
    let system = System::new(surface, start, options);
    let mut d = vec![DVec3::ZERO; start.len()];
    let mut report = FineReport {
        rounds: Vec::new(),
        converged: true,
    };
    // The cover pairs are found once, at the start: a pair is a source triangle with barycentric
    // weights and a target point, so its residual follows the displacements of every round;
    // finding them again would cost a tree over the source and a query per target sample.
    let t = Instant::now();
    let cover = if options.cover_weight > 0.0 {
        let world = IndexedMesh::new(
            start.iter().map(|&p| surface.units.to_world(p)).collect(),
            surface.faces.triangles().to_vec(),
        );
        let pairs = correspond.cover(
            &world,
            options.cover_min_distance as f32,
            options.sigma as f32,
        )?;
        Cover::new(&pairs, surface, start, options)
    } else {
        Cover::default()
    };
    let mut cover_time = t.elapsed();
    for _ in 0..options.rounds {
        let t = Instant::now();
        let positions: Vec<DVec3> = start.iter().zip(&d).map(|(p, d)| *p + *d).collect();
        let normals = surface.faces.normals(&positions);
        let found = targets(
            correspond,
            &surface.units,
            &positions,
            &normals,
            options.sigma,
        )?;
        let correspondence = t.elapsed() + std::mem::take(&mut cover_time);
        let t = Instant::now();
        let fit = system.fit_matrices(&found);
        let mut b = system.rhs(&found, &fit);
        cover.add_rhs(&mut b);
        let energy_before = system.energy(&d, &found) + cover.energy(&d);
        let solve = system.solve(&fit, &cover, &b, &mut d, options);
        let energy = system.energy(&d, &found) + cover.energy(&d);
        let kept = found.iter().filter(|c| c.is_some()).count();
        report.converged &= solve.converged;
        report.rounds.push(FineRound {
            kept,
            pruned: found.len() - kept,
            cover: cover.len(),
            energy_before,
            energy,
            cg_iterations: solve.iterations,
            residual: solve.residual,
            converged: solve.converged,
            correspondence,
            solve: t.elapsed(),
        });
    }
    let positions = start.iter().zip(&d).map(|(p, d)| *p + *d).collect();
    Ok((positions, report))
}

/// The quadratic energy's fixed parts: mesh edges with their directions and the weights.
struct System<'a> {
    surface: &'a Surface,
    start: &'a [DVec3],
    /// `ê` for every adjacency entry, flat: vertex `v`'s are `offsets[v]..offsets[v + 1]`, in the
    /// order of its neighbour list (one allocation, read in sequence by every product).
    directions: Vec<DVec3>,
    offsets: Vec<usize>,
    options: FineOptions,
}

/// The cover term of one round (see the module docs): each pair's three source vertices with
/// their barycentric weights `w`, its matrix `M = s α_plane n nᵀ` and its target
/// point `t` (solver coordinates), contributing `rᵀ M r` with `r = Σ_k w_k (p_k + d_k) − t`; and
/// per vertex the (pair, corner) entries that touch it, in pair order, as compressed rows.
#[derive(Debug, Default)]
struct Cover {
    corners: Vec<[u32; 3]>,
    weights: Vec<[f64; 3]>,
    matrices: Vec<DMat3>,
    /// `t − Σ_k w_k p_k`: the pull at zero displacement.
    gaps: Vec<DVec3>,
    offsets: Vec<usize>,
    entries: Vec<(u32, u8)>,
}

impl Cover {
    fn new(pairs: &CoverPairs, surface: &Surface, start: &[DVec3], options: &FineOptions) -> Self {
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
            cover.corners.push(corners);
            cover.weights.push(w);
            cover
                .matrices
                .push(outer(n) * (options.plane_weight * scale));
            cover.gaps.push(surface.units.to_local(hit.point) - at);
        }
        let mut offsets = vec![0usize; start.len() + 1];
        for corners in &cover.corners {
            for &v in corners {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..start.len() {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets[..start.len()].to_vec();
        let mut entries = vec![(0u32, 0u8); offsets[start.len()]];
        for (p, corners) in cover.corners.iter().enumerate() {
            for (k, &v) in corners.iter().enumerate() {
                entries[fill[v as usize]] = (p as u32, k as u8);
                fill[v as usize] += 1;
            }
        }
        cover.offsets = offsets;
        cover.entries = entries;
        cover
    }

    fn len(&self) -> usize {
        self.corners.len()
    }

    /// `Σ_k w_k x_k` for pair `p`.
    fn blend(&self, p: usize, x: &[DVec3]) -> DVec3 {
        let [a, b, c] = self.corners[p];
        let [wa, wb, wc] = self.weights[p];
        wa * x[a as usize] + wb * x[b as usize] + wc * x[c as usize]
    }

    /// The entries touching vertex `v` (none when the term is empty).
    fn entries(&self, v: usize) -> &[(u32, u8)] {
        match (self.offsets.get(v), self.offsets.get(v + 1)) {
            (Some(&from), Some(&to)) => &self.entries[from..to],
            _ => &[],
        }
    }

    /// Per vertex, `Σ w_v M_p y_p` over the pairs `p` touching it, for one `y` per pair.
    fn gather(&self, y: &[DVec3], out: &mut [DVec3]) {
        out.par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(v, o)| {
                for &(p, k) in self.entries(v) {
                    *o += self.weights[p as usize][k as usize] * y[p as usize];
                }
            });
    }

    /// Adds `b_v += Σ w_v M (t − Σ_k w_k p_k)` over the pairs touching `v`.
    fn add_rhs(&self, b: &mut [DVec3]) {
        if self.corners.is_empty() {
            return;
        }
        let pulls: Vec<DVec3> = (0..self.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|p| self.matrices[p] * self.gaps[p])
            .collect();
        self.gather(&pulls, b);
    }

    /// Adds the term's product `Σ w_v M (Σ_k w_k d_k)` to `out`.
    fn add_product(&self, d: &[DVec3], out: &mut [DVec3]) {
        if self.corners.is_empty() {
            return;
        }
        let moved: Vec<DVec3> = (0..self.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|p| self.matrices[p] * self.blend(p, d))
            .collect();
        self.gather(&moved, out);
    }

    /// The term's 3×3 diagonal block at `v`: `Σ w_v² M`.
    fn diagonal(&self, v: usize) -> DMat3 {
        self.entries(v).iter().fold(DMat3::ZERO, |acc, &(p, k)| {
            let w = self.weights[p as usize][k as usize];
            acc + self.matrices[p as usize] * (w * w)
        })
    }

    /// `Σ rᵀ M r` at displacements `d`.
    fn energy(&self, d: &[DVec3]) -> f64 {
        ordered_sum(self.len(), |p| {
            let r = self.blend(p, d) - self.gaps[p];
            r.dot(self.matrices[p] * r)
        })
    }
}

/// `v vᵀ`.
fn outer(v: DVec3) -> DMat3 {
    DMat3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// How a conjugate-gradient solve ended.
struct Solve {
    iterations: usize,
    residual: f64,
    converged: bool,
}

impl<'a> System<'a> {
    fn new(surface: &'a Surface, start: &'a [DVec3], options: &FineOptions) -> Self {
        let mut offsets = Vec::with_capacity(start.len() + 1);
        offsets.push(0);
        for v in 0..start.len() {
            offsets.push(offsets[v] + surface.adjacency.neighbours(v).len());
        }
        let mut directions = vec![DVec3::ZERO; offsets[start.len()]];
        let mut rest = directions.as_mut_slice();
        let mut per_vertex = Vec::with_capacity(start.len());
        for v in 0..start.len() {
            let (head, tail) = rest.split_at_mut(offsets[v + 1] - offsets[v]);
            per_vertex.push(head);
            rest = tail;
        }
        per_vertex
            .into_par_iter()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(v, out)| {
                for (o, &u) in out.iter_mut().zip(surface.adjacency.neighbours(v)) {
                    *o = (start[v] - start[u as usize]).normalize_or_zero();
                }
            });
        Self {
            surface,
            start,
            directions,
            offsets,
            options: *options,
        }
    }

    fn directions(&self, v: usize) -> &[DVec3] {
        &self.directions[self.offsets[v]..self.offsets[v + 1]]
    }

    /// `α_plane n nᵀ + α_point I` per vertex with a correspondence, zero otherwise.
    fn fit_matrices(&self, found: &[Option<FitTarget>]) -> Vec<DMat3> {
        found
            .iter()
            .map(|c| {
                c.map_or(DMat3::ZERO, |c| {
                    let n = c.normal;
                    outer(n) * self.options.plane_weight
                        + DMat3::IDENTITY * self.options.point_weight
                })
            })
            .collect()
    }

    /// `b_v = M_v (c_v − p_v)`.
    fn rhs(&self, found: &[Option<FitTarget>], fit: &[DMat3]) -> Vec<DVec3> {
        found
            .iter()
            .zip(fit)
            .zip(self.start)
            .map(|((c, m), &p)| c.map_or(DVec3::ZERO, |c| *m * (c.point - p)))
            .collect()
    }

    /// The regularization block of edge direction `e`: `α_disp I + α_edge ê êᵀ`.
    fn edge_block(&self, e: DVec3) -> DMat3 {
        DMat3::IDENTITY * self.options.disp_weight + outer(e) * self.options.edge_weight
    }

    /// `(A d)_v = M_v d_v + Σ_u (α_disp I + α_edge ê êᵀ)(d_v − d_u)`.
    fn apply_vertex(&self, fit: &[DMat3], d: &[DVec3], v: usize) -> DVec3 {
        let mut y = fit[v] * d[v];
        for (&u, &e) in self
            .surface
            .adjacency
            .neighbours(v)
            .iter()
            .zip(self.directions(v))
        {
            let diff = d[v] - d[u as usize];
            y += self.options.disp_weight * diff + self.options.edge_weight * e * e.dot(diff);
        }
        y
    }

    /// `out = A d`; returns `dᵀ A d`.
    fn apply(&self, fit: &[DMat3], cover: &Cover, d: &[DVec3], out: &mut [DVec3]) -> f64 {
        out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
            for (k, o) in o.iter_mut().enumerate() {
                *o = self.apply_vertex(fit, d, c * CHUNK + k);
            }
        });
        cover.add_product(d, out);
        ordered_sum(d.len(), |v| d[v].dot(out[v]))
    }

    /// The energy `E(d)` with correspondences `found`.
    fn energy(&self, d: &[DVec3], found: &[Option<FitTarget>]) -> f64 {
        let o = &self.options;
        ordered_sum(d.len(), |v| {
            let p = self.start[v] + d[v];
            let fit = found[v].map_or(0.0, |c| {
                let r = p - c.point;
                o.plane_weight * c.normal.dot(r).powi(2) + o.point_weight * r.length_squared()
            });
            let reg: f64 = self
                .surface
                .adjacency
                .neighbours(v)
                .iter()
                .zip(self.directions(v))
                .filter(|&(&u, _)| u as usize > v)
                .map(|(&u, &e)| {
                    let diff = d[v] - d[u as usize];
                    o.disp_weight * diff.length_squared() + o.edge_weight * e.dot(diff).powi(2)
                })
                .sum();
            fit + reg
        })
    }

    /// Preconditioned conjugate gradients on `A d = b`, from the `d` given. Each iteration is
    /// three parallel passes over the vertices (the product with its `pᵀAp`; the updates of `d`,
    /// `r` and `z` with `rᵀz` and `rᵀr`; the new direction): the vectors are a few megabytes, so
    /// passes, not arithmetic, are what an iteration costs.
    fn solve(
        &self,
        fit: &[DMat3],
        cover: &Cover,
        b: &[DVec3],
        d: &mut [DVec3],
        options: &FineOptions,
    ) -> Solve {
        let n = d.len();
        let preconditioner: Vec<DMat3> = (0..n)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| {
                let block = self
                    .directions(v)
                    .iter()
                    .fold(fit[v] + cover.diagonal(v), |acc, &e| {
                        acc + self.edge_block(e)
                    });
                if block.determinant().abs() > 1e-300 {
                    block.inverse()
                } else {
                    DMat3::IDENTITY
                }
            })
            .collect();
        let b_norm = ordered_sum(n, |v| b[v].length_squared()).sqrt();
        if b_norm == 0.0 {
            d.iter_mut().for_each(|v| *v = DVec3::ZERO);
            return Solve {
                iterations: 0,
                residual: 0.0,
                converged: true,
            };
        }
        let mut ad = vec![DVec3::ZERO; n];
        self.apply(fit, cover, d, &mut ad);
        let mut r: Vec<DVec3> = b.iter().zip(&ad).map(|(b, a)| *b - *a).collect();
        let mut z: Vec<DVec3> = preconditioner
            .iter()
            .zip(&r)
            .map(|(m, r)| *m * *r)
            .collect();
        let mut p = z.clone();
        let mut rz = ordered_sum(n, |v| r[v].dot(z[v]));
        let mut residual = ordered_sum(n, |v| r[v].length_squared()).sqrt() / b_norm;
        let mut iterations = 0;
        while residual > options.tolerance && iterations < options.max_cg_iterations {
            let pap = self.apply(fit, cover, &p, &mut ad);
            if pap <= 0.0 || !pap.is_finite() {
                break;
            }
            let alpha = rz / pap;
            let partial: Vec<[f64; 2]> = d
                .par_chunks_mut(CHUNK)
                .zip(r.par_chunks_mut(CHUNK))
                .zip(z.par_chunks_mut(CHUNK))
                .enumerate()
                .map(|(c, ((d, r), z))| {
                    let (mut rz, mut rr) = (0.0, 0.0);
                    for (k, ((d, r), z)) in d.iter_mut().zip(r).zip(z).enumerate() {
                        let v = c * CHUNK + k;
                        *d += alpha * p[v];
                        *r -= alpha * ad[v];
                        *z = preconditioner[v] * *r;
                        rz += r.dot(*z);
                        rr += r.length_squared();
                    }
                    [rz, rr]
                })
                .collect();
            let (rz_next, rr) = partial
                .iter()
                .fold((0.0, 0.0), |(a, b), p| (a + p[0], b + p[1]));
            let beta = rz_next / rz;
            rz = rz_next;
            residual = rr.sqrt() / b_norm;
            iterations += 1;
            if residual > options.tolerance {
                p.par_chunks_mut(CHUNK)
                    .zip(z.par_chunks(CHUNK))
                    .for_each(|(p, z)| {
                        p.iter_mut().zip(z).for_each(|(p, z)| *p = *z + beta * *p);
                    });
            }
        }
        Solve {
            iterations,
            residual,
            converged: residual <= options.tolerance,
        }
    }
}
