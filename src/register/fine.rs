//! The fine stage (paper §4.2): per-vertex displacements `d` that bring the detail the coarse graph
//! cannot express onto the target,
//!
//! `E = Σ_v α_plane (n_v·(p_v + d_v − c_v))² + α_point |p_v + d_v − c_v|²
//!    + α_disp Σ_(i,j) |d_i − d_j|² + α_edge Σ_(i,j) (ê_ij·(d_i − d_j))²`,
//!
//! over the mesh edges `(i, j)`, with `ê_ij` the unit edge direction before the stage (so the last
//! term is the linearized change of edge length) and correspondences farther than σ pruned. `E` is
//! quadratic; its minimizer solves `A d = b`, found by conjugate gradients preconditioned with
//! `A`'s 3×3 diagonal blocks, warm-started from the previous round's displacements.

use std::time::Instant;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::RegisterError;
use super::correspond::{Correspond, targets};
use super::energy::FitTarget;
use super::model::{CHUNK, ordered_sum};
use super::options::FineOptions;
use super::report::{FineReport, FineRound};
use super::surface::Surface;

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
        let correspondence = t.elapsed();
        let t = Instant::now();
        let fit = system.fit_matrices(&found);
        let b = system.rhs(&found, &fit);
        let energy_before = system.energy(&d, &found);
        let solve = system.solve(&fit, &b, &mut d, options);
        let energy = system.energy(&d, &found);
        let kept = found.iter().filter(|c| c.is_some()).count();
        report.converged &= solve.converged;
        report.rounds.push(FineRound {
            kept,
            pruned: found.len() - kept,
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

/// How a conjugate-gradient solve ended.
struct Solve {
    iterations: usize,
    residual: f64,
    converged: bool,
}

/// Runs `chunk(first vertex, chunk of out)` over `out` in chunks of [`CHUNK`] vertices in parallel
/// and sums what the chunks return in chunk order, so the sums do not depend on the thread count
/// (the same grouping as [`ordered_sum`]).
fn chunked<T: Send, const K: usize>(
    out: &mut [T],
    chunk: impl Fn(usize, &mut [T]) -> [f64; K] + Sync,
) -> [f64; K] {
    let partial: Vec<[f64; K]> = out
        .par_chunks_mut(CHUNK)
        .enumerate()
        .map(|(c, o)| chunk(c * CHUNK, o))
        .collect();
    partial.iter().fold([0.0; K], |mut acc, p| {
        acc.iter_mut().zip(p).for_each(|(a, p)| *a += p);
        acc
    })
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
                    DMat3::from_cols(n * n.x, n * n.y, n * n.z) * self.options.plane_weight
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
        DMat3::IDENTITY * self.options.disp_weight
            + DMat3::from_cols(e * e.x, e * e.y, e * e.z) * self.options.edge_weight
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
    fn apply(&self, fit: &[DMat3], d: &[DVec3], out: &mut [DVec3]) -> f64 {
        let [dad] = chunked(out, |first, o| {
            let mut dad = 0.0;
            for (k, o) in o.iter_mut().enumerate() {
                *o = self.apply_vertex(fit, d, first + k);
                dad += d[first + k].dot(*o);
            }
            [dad]
        });
        dad
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
    fn solve(&self, fit: &[DMat3], b: &[DVec3], d: &mut [DVec3], options: &FineOptions) -> Solve {
        let n = d.len();
        let preconditioner: Vec<DMat3> = (0..n)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| {
                let block = self
                    .directions(v)
                    .iter()
                    .fold(fit[v], |acc, &e| acc + self.edge_block(e));
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
        self.apply(fit, d, &mut ad);
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
            let pap = self.apply(fit, &p, &mut ad);
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
