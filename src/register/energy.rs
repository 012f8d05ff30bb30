//! The coarse energy `E_tot = α_fit E_fit + α_reg (E_rigid + 0.1 E_smooth)` (paper §4.2, thesis
//! eq. 3.5–3.8), its residuals and their Jacobians, and its gradient `Jᵀ r`.
//!
//! `E_fit = Σ_v E_plane + 0.1 E_point` over the mesh vertices' correspondences `(c_v, n_v)`:
//! `(n_v · (ṽ − c_v))² + 0.1 |ṽ − c_v|²`; the point-to-plane part lets the surface slide along the
//! target, the point part keeps it from sliding without bound. `E_rigid` is Sumner et al.'s
//! `Rot(A)`: squared dot products of the columns of `A` plus `(|a_c|² − 1)²` (the thesis prints
//! `(1 − |a_c|)²`; the squared norm is the original's and is polynomial). `E_smooth` sums
//! `|A_i (g_j − g_i) + g_i + b_i − (g_j + b_j)|²` over both directions of every graph edge.

use glam::DVec3;
use rayon::prelude::*;

use super::model::{CHUNK, Model, NODE_DOFS, ordered_sum};

/// Where a vertex should go: a point on the target and the target's unit normal there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitTarget {
    pub point: DVec3,
    pub normal: DVec3,
}

/// Term weights of the coarse energy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoarseWeights {
    pub fit: f64,
    pub plane: f64,
    pub point: f64,
    pub reg: f64,
    pub smooth: f64,
}

impl CoarseWeights {
    /// `α_fit (α_plane n nᵀ + α_point I)`: the Hessian of one vertex's fit term with respect to the
    /// vertex position, and the matrix that turns its offset from the target into its gradient.
    pub fn fit_matrix(&self, normal: DVec3) -> [[f64; 3]; 3] {
        let n = normal.to_array();
        let mut m = [[0.0; 3]; 3];
        for (a, row) in m.iter_mut().enumerate() {
            for (b, value) in row.iter_mut().enumerate() {
                let identity = if a == b { self.point } else { 0.0 };
                *value = self.fit * (self.plane * n[a] * n[b] + identity);
            }
        }
        m
    }
}

/// The three energies, unweighted.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyTerms {
    pub fit: f64,
    pub rigid: f64,
    pub smooth: f64,
}

impl EnergyTerms {
    pub fn total(&self, w: &CoarseWeights) -> f64 {
        w.fit * self.fit + w.reg * (self.rigid + w.smooth * self.smooth)
    }
}

/// `α_plane (n · r)² + α_point |r|²` with `r = p − c`.
pub fn fit_energy(target: &FitTarget, p: DVec3, w: &CoarseWeights) -> f64 {
    let r = p - target.point;
    let along = target.normal.dot(r);
    w.plane * along * along + w.point * r.length_squared()
}

/// The columns of `A` stored in a node's unknowns.
fn columns(node: &[f64]) -> [DVec3; 3] {
    [0, 1, 2].map(|c| DVec3::new(node[3 * c], node[3 * c + 1], node[3 * c + 2]))
}

/// Column pairs whose dot product `E_rigid` drives to zero, in residual order.
const PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

/// The six residuals of `E_rigid` for one node: `a_0·a_1, a_0·a_2, a_1·a_2, |a_c|² − 1`.
pub fn rigid_residuals(node: &[f64]) -> [f64; 6] {
    let a = columns(node);
    let mut r = [0.0; 6];
    for (k, &(p, q)) in PAIRS.iter().enumerate() {
        r[k] = a[p].dot(a[q]);
    }
    for c in 0..3 {
        r[3 + c] = a[c].length_squared() - 1.0;
    }
    r
}

/// Jacobian of [`rigid_residuals`] with respect to the nine entries of `A` (unknowns `3c + k`).
pub fn rigid_jacobian(node: &[f64]) -> [[f64; 9]; 6] {
    let a = columns(node);
    let mut j = [[0.0; 9]; 6];
    for (row, &(p, q)) in PAIRS.iter().enumerate() {
        for k in 0..3 {
            j[row][3 * p + k] = a[q][k];
            j[row][3 * q + k] = a[p][k];
        }
    }
    for c in 0..3 {
        for k in 0..3 {
            j[3 + c][3 * c + k] = 2.0 * a[c][k];
        }
    }
    j
}

/// `ψ = (g_j − g_i, 1)`: the smoothness residual of edge i→j is `(ψᵀ ⊗ I₃) x_i − (e₃ᵀ ⊗ I₃) x_j
/// + g_i − g_j`, with `e₃ = (0, 0, 0, 1)`.
pub fn smooth_psi(model: &Model, i: usize, j: usize) -> [f64; 4] {
    let d = model.nodes[j] - model.nodes[i];
    [d.x, d.y, d.z, 1.0]
}

/// Residual of the directed graph edge i→j: `A_i (g_j − g_i) + g_i + b_i − (g_j + b_j)`.
pub fn smooth_residual(model: &Model, x: &[f64], i: usize, j: usize) -> DVec3 {
    smooth_linear(model, x, i, j) + model.nodes[i] - model.nodes[j]
}

/// The part of [`smooth_residual`] linear in the unknowns: `(ψᵀ ⊗ I₃) x_i − (e₃ᵀ ⊗ I₃) x_j`, which
/// is also its Jacobian applied to `x`.
pub fn smooth_linear(model: &Model, x: &[f64], i: usize, j: usize) -> DVec3 {
    let xi = &x[NODE_DOFS * i..][..NODE_DOFS];
    let xj = &x[NODE_DOFS * j..][..NODE_DOFS];
    let psi = smooth_psi(model, i, j);
    let mut r = -DVec3::new(xj[9], xj[10], xj[11]);
    for (c, &p) in psi.iter().enumerate() {
        r += p * DVec3::new(xi[3 * c], xi[3 * c + 1], xi[3 * c + 2]);
    }
    r
}

/// The three energies at unknowns `x`, whose deformed vertices are `deformed`.
pub fn energy(
    model: &Model,
    x: &[f64],
    deformed: &[DVec3],
    targets: &[Option<FitTarget>],
    w: &CoarseWeights,
) -> EnergyTerms {
    let fit = ordered_sum(deformed.len(), |v| {
        targets[v].map_or(0.0, |t| fit_energy(&t, deformed[v], w))
    });
    let rigid = ordered_sum(model.node_count(), |i| {
        rigid_residuals(&x[NODE_DOFS * i..][..NODE_DOFS])
            .iter()
            .map(|r| r * r)
            .sum()
    });
    let smooth = ordered_sum(model.node_count(), |i| {
        model
            .node_neighbours(i)
            .iter()
            .map(|&j| smooth_residual(model, x, i, j as usize).length_squared())
            .sum()
    });
    EnergyTerms { fit, rigid, smooth }
}

/// `α_fit (α_plane n nᵀ + α_point I) (ṽ − c)` per vertex, zero without a target: the gradient of a
/// vertex's weighted fit term with respect to its position.
pub fn fit_pulls(
    deformed: &[DVec3],
    targets: &[Option<FitTarget>],
    w: &CoarseWeights,
) -> Vec<DVec3> {
    deformed
        .par_iter()
        .zip(targets)
        .with_min_len(CHUNK)
        .map(|(&p, target)| {
            target.map_or(DVec3::ZERO, |t| {
                let m = w.fit_matrix(t.normal);
                let r = (p - t.point).to_array();
                DVec3::from_array(m.map(|row| row[0] * r[0] + row[1] * r[1] + row[2] * r[2]))
            })
        })
        .collect()
}

/// The gradient `Jᵀ r` of `E_tot / 2` (weighted), node by node in parallel; each node sums its own
/// terms in a fixed order, so the result does not depend on the thread count.
pub fn gradient(model: &Model, x: &[f64], pulls: &[DVec3], w: &CoarseWeights) -> Vec<f64> {
    let mut g = vec![0.0; model.unknowns()];
    g.par_chunks_mut(NODE_DOFS)
        .enumerate()
        .for_each(|(i, out)| node_gradient(model, x, pulls, w, i, out));
    g
}

fn node_gradient(
    model: &Model,
    x: &[f64],
    pulls: &[DVec3],
    w: &CoarseWeights,
    i: usize,
    out: &mut [f64],
) {
    add_fit_transpose(model, pulls, i, out);
    let node = &x[NODE_DOFS * i..][..NODE_DOFS];
    let r = rigid_residuals(node);
    let j = rigid_jacobian(node);
    for (row, &res) in j.iter().zip(&r) {
        for (o, &d) in out.iter_mut().zip(row) {
            *o += w.reg * d * res;
        }
    }
    add_smooth(model, w.reg * w.smooth, i, out, |a, b| {
        smooth_residual(model, x, a, b)
    });
}

/// `out += Σ_v (u_s ⊗ pulls_v)` over the skinning entries naming node `i`: the fit part of `Jᵀ`
/// applied to per-vertex 3-vectors.
pub fn add_fit_transpose(model: &Model, pulls: &[DVec3], i: usize, out: &mut [f64]) {
    for &[v, s] in model.node_skin(i) {
        let u = &model.skin_u[s as usize];
        let m = pulls[v as usize];
        for c in 0..4 {
            out[3 * c] += u[c] * m.x;
            out[3 * c + 1] += u[c] * m.y;
            out[3 * c + 2] += u[c] * m.z;
        }
    }
}

/// `out += weight · J_smoothᵀ r` restricted to node `i`, where `residual(a, b)` gives the residual
/// of edge a→b: node `i` is the first node of its outgoing edges (Jacobian `ψᵀ ⊗ I₃`) and the
/// second of its incoming ones (`−e₃ᵀ ⊗ I₃`).
pub fn add_smooth(
    model: &Model,
    weight: f64,
    i: usize,
    out: &mut [f64],
    residual: impl Fn(usize, usize) -> DVec3,
) {
    for &nb in model.node_neighbours(i) {
        let nb = nb as usize;
        let psi = smooth_psi(model, i, nb);
        let out_edge = residual(i, nb);
        for (c, &p) in psi.iter().enumerate() {
            out[3 * c] += weight * p * out_edge.x;
            out[3 * c + 1] += weight * p * out_edge.y;
            out[3 * c + 2] += weight * p * out_edge.z;
        }
        let in_edge = residual(nb, i);
        out[9] -= weight * in_edge.x;
        out[10] -= weight * in_edge.y;
        out[11] -= weight * in_edge.z;
    }
}
