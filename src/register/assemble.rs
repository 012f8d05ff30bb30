//! Numeric assembly of the Gauss-Newton matrix `H = JᵀJ` (weighted) into the fixed [`Pattern`].
//!
//! Each column of blocks is filled by one rayon task and every block sums its contributions in the
//! pattern's order, so `H` is bit-identical whatever the thread count. A vertex's fit term adds
//! `(u_i u_jᵀ) ⊗ M_v` to block (i, j), with `u = w φ` from the skinning and `M_v` its 3×3 fit
//! matrix; `E_smooth` adds its constant `S ⊗ I₃`; `E_rigid` adds `J_rᵀ J_r` to the diagonal blocks.

use rayon::prelude::*;

use super::energy::{CoarseWeights, rigid_jacobian};
use super::model::{Model, NODE_DOFS};
use super::pattern::Pattern;

type Block = [[f64; NODE_DOFS]; NODE_DOFS];

/// Fills `values` (the pattern's upper triangle) with `H` at unknowns `x`; `fit` holds each vertex's
/// fit matrix (zero for a vertex without a correspondence).
pub fn assemble(
    pattern: &Pattern,
    model: &Model,
    x: &[f64],
    fit: &[[[f64; 3]; 3]],
    w: &CoarseWeights,
    values: &mut [f64],
) {
    let mut rest = values;
    let mut columns = Vec::with_capacity(pattern.node_count());
    for j in 0..pattern.node_count() {
        let len = (pattern.col_ptr[NODE_DOFS * (j + 1)] - pattern.col_ptr[NODE_DOFS * j]) as usize;
        let (head, tail) = rest.split_at_mut(len);
        columns.push(head);
        rest = tail;
    }
    columns
        .into_par_iter()
        .enumerate()
        .for_each(|(j, out)| assemble_column(pattern, model, x, fit, w, j, out));
}

fn assemble_column(
    pattern: &Pattern,
    model: &Model,
    x: &[f64],
    fit: &[[[f64; 3]; 3]],
    w: &CoarseWeights,
    j: usize,
    out: &mut [f64],
) {
    let base = pattern.col_ptr[NODE_DOFS * j] as usize;
    let first = pattern.block_col_ptr[j] as usize;
    let last = pattern.block_col_ptr[j + 1] as usize;
    let ws = w.reg * w.smooth;
    for b in first..last {
        let mut block: Block = [[0.0; NODE_DOFS]; NODE_DOFS];
        for pair in &pattern.fit_pairs[pattern.fit_ptr[b] as usize..pattern.fit_ptr[b + 1] as usize]
        {
            add_fit(
                &mut block,
                &model.skin_u[pair.si as usize],
                &model.skin_u[pair.sj as usize],
                &fit[pair.vertex as usize],
            );
        }
        let s = &pattern.smooth[b];
        for c in 0..4 {
            for d in 0..4 {
                let value = ws * s[4 * c + d];
                for k in 0..3 {
                    block[3 * c + k][3 * d + k] += value;
                }
            }
        }
        let diagonal = b + 1 == last;
        if diagonal {
            let jac = rigid_jacobian(&x[NODE_DOFS * j..][..NODE_DOFS]);
            for row in &jac {
                for p in 0..9 {
                    for q in 0..9 {
                        block[p][q] += w.reg * row[p] * row[q];
                    }
                }
            }
        }
        let rank = b - first;
        let columns = &pattern.col_ptr[NODE_DOFS * j..NODE_DOFS * (j + 1)];
        for (q, &column) in columns.iter().enumerate() {
            let start = column as usize - base + NODE_DOFS * rank;
            let rows = if diagonal { q + 1 } else { NODE_DOFS };
            for (slot, row) in out[start..start + rows].iter_mut().zip(&block) {
                *slot = row[q];
            }
        }
    }
}

/// `H` restricted to the unknowns of `nodes` (ascending, and coupled by the pattern to no other
/// node), as a dense row-major `12n × 12n` matrix: for the small components' exact factors
/// (`small_blocks`).
pub(crate) fn assemble_dense(
    pattern: &Pattern,
    model: &Model,
    x: &[f64],
    fit: &[[[f64; 3]; 3]],
    w: &CoarseWeights,
    nodes: &[u32],
) -> Vec<f64> {
    let m = NODE_DOFS * nodes.len();
    let local = |scalar: u32| {
        let node = scalar / NODE_DOFS as u32;
        nodes
            .binary_search(&node)
            .ok()
            .map(|k| NODE_DOFS * k + scalar as usize % NODE_DOFS)
    };
    let mut dense = vec![0.0; m * m];
    let mut column = Vec::new();
    for &j in nodes {
        let j = j as usize;
        let base = pattern.col_ptr[NODE_DOFS * j] as usize;
        column.clear();
        column.resize(pattern.col_ptr[NODE_DOFS * (j + 1)] as usize - base, 0.0);
        assemble_column(pattern, model, x, fit, w, j, &mut column);
        for c in NODE_DOFS * j..NODE_DOFS * (j + 1) {
            let Some(lc) = local(c as u32) else { continue };
            for at in pattern.col_ptr[c] as usize..pattern.col_ptr[c + 1] as usize {
                if let Some(lr) = local(pattern.row_idx[at]) {
                    dense[lr * m + lc] = column[at - base];
                    dense[lc * m + lr] = column[at - base];
                }
            }
        }
    }
    dense
}

/// `block += (u vᵀ) ⊗ m`.
#[inline]
fn add_fit(block: &mut Block, u: &[f64; 4], v: &[f64; 4], m: &[[f64; 3]; 3]) {
    for c in 0..4 {
        for d in 0..4 {
            let a = u[c] * v[d];
            for k in 0..3 {
                let row = &mut block[3 * c + k];
                row[3 * d] += a * m[k][0];
                row[3 * d + 1] += a * m[k][1];
                row[3 * d + 2] += a * m[k][2];
            }
        }
    }
}

/// Copies `h` into `damped` with `λ` added to the diagonal (the last entry of every column).
pub fn damp(pattern: &Pattern, h: &[f64], lambda: f64, damped: &mut Vec<f64>) {
    damped.clear();
    damped.extend_from_slice(h);
    damp_in_place(pattern, damped, lambda);
}

/// [`damp`] into `h` itself, for a matrix not needed undamped again.
pub fn damp_in_place(pattern: &Pattern, h: &mut [f64], lambda: f64) {
    if lambda > 0.0 {
        for c in 0..pattern.dimension() {
            h[pattern.col_ptr[c + 1] as usize - 1] += lambda;
        }
    }
}
