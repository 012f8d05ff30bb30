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
    /// `ê` for every adjacency entry (same layout as the adjacency's neighbour lists).
    directions: Vec<Vec<DVec3>>,
    options: FineOptions,
}

/// How a conjugate-gradient solve ended.
struct Solve {
    iterations: usize,
    residual: f64,
    converged: bool,
}

impl<'a> System<'a> {
    fn new(surface: &'a Surface, start: &'a [DVec3], options: &FineOptions) -> Self {
        let directions = (0..start.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| {
                surface
                    .adjacency
                    .neighbours(v)
                    .iter()
                    .map(|&u| (start[v] - start[u as usize]).normalize_or_zero())
                    .collect()
            })
            .collect();
        Self {
            surface,
            start,
            directions,
            options: *options,
        }
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
    fn apply(&self, fit: &[DMat3], d: &[DVec3], out: &mut [DVec3]) {
        out.par_iter_mut()
            .enumerate()
            .with_min_len(CHUNK)
            .for_each(|(v, o)| {
                let mut y = fit[v] * d[v];
                for (&u, &e) in self
                    .surface
                    .adjacency
                    .neighbours(v)
                    .iter()
                    .zip(&self.directions[v])
                {
                    let diff = d[v] - d[u as usize];
                    y += self.options.disp_weight * diff
                        + self.options.edge_weight * e * e.dot(diff);
                }
                *o = y;
            });
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
                .zip(&self.directions[v])
                .filter(|&(&u, _)| u as usize > v)
                .map(|(&u, &e)| {
                    let diff = d[v] - d[u as usize];
                    o.disp_weight * diff.length_squared() + o.edge_weight * e.dot(diff).powi(2)
                })
                .sum();
            fit + reg
        })
    }

    /// Preconditioned conjugate gradients on `A d = b`, from the `d` given.
    fn solve(&self, fit: &[DMat3], b: &[DVec3], d: &mut [DVec3], options: &FineOptions) -> Solve {
        let n = d.len();
        let preconditioner: Vec<DMat3> = (0..n)
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| {
                let block = self.directions[v]
                    .iter()
                    .fold(fit[v], |acc, &e| acc + self.edge_block(e));
                if block.determinant().abs() > 1e-300 {
                    block.inverse()
                } else {
                    DMat3::IDENTITY
                }
            })
            .collect();
        let dot = |a: &[DVec3], c: &[DVec3]| ordered_sum(a.len(), |v| a[v].dot(c[v]));
        let mut ad = vec![DVec3::ZERO; n];
        self.apply(fit, d, &mut ad);
        let mut r: Vec<DVec3> = b.iter().zip(&ad).map(|(b, a)| *b - *a).collect();
        let b_norm = dot(b, b).sqrt();
        if b_norm == 0.0 {
            d.iter_mut().for_each(|v| *v = DVec3::ZERO);
            return Solve {
                iterations: 0,
                residual: 0.0,
                converged: true,
            };
        }
        let mut z: Vec<DVec3> = preconditioner
            .iter()
            .zip(&r)
            .map(|(m, r)| *m * *r)
            .collect();
        let mut p = z.clone();
        let mut rz = dot(&r, &z);
        let mut residual = dot(&r, &r).sqrt() / b_norm;
        let mut iterations = 0;
        while residual > options.tolerance && iterations < options.max_cg_iterations {
            self.apply(fit, &p, &mut ad);
            let pap = dot(&p, &ad);
            if pap <= 0.0 || !pap.is_finite() {
                break;
            }
            let alpha = rz / pap;
            d.par_iter_mut().zip(&p).for_each(|(d, p)| *d += alpha * *p);
            r.par_iter_mut()
                .zip(&ad)
                .for_each(|(r, a)| *r -= alpha * *a);
            z.par_iter_mut()
                .zip(&preconditioner)
                .zip(&r)
                .for_each(|((z, m), r)| *z = *m * *r);
            let rz_next = dot(&r, &z);
            let beta = rz_next / rz;
            rz = rz_next;
            p.par_iter_mut()
                .zip(&z)
                .for_each(|(p, z)| *p = *z + beta * *p);
            residual = dot(&r, &r).sqrt() / b_norm;
            iterations += 1;
        }
        Solve {
            iterations,
            residual,
            converged: residual <= options.tolerance,
        }
    }
}
