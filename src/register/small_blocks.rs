//! A spray's droplets in the coarse stage (paper §4.2): the Gauss-Newton blocks of the deformation
//! graph's small components, factored exactly at every solve.
//!
//! Conjugate gradients on the exact system are preconditioned by a sparse factor that is kept for
//! several Gauss-Newton iterations (see `coarse`): a large body's part of the matrix changes little
//! from one iteration to the next, so the factor stays a good preconditioner there. A droplet's
//! whole motion is its few nodes', and its part changes by orders between iterations (the rigidity
//! term's Jacobian at the new unknowns, the damping, which falls tenfold after an accepted step and
//! is all that holds a nearly free droplet in place). Where droplets make up much of the graph, a
//! kept factor lets solves run to their cap of 200 iterations (the dam break with 1,000 droplets
//! added: 857 iterations in one registration, against 20 with a fresh factor every iteration).
//! The graph's components are independent blocks of the matrix, so each small one is assembled and
//! factored densely, in double precision, at the current state, and the preconditioner applies
//! that exact inverse on its unknowns and the sparse factor on the rest.
//!
//! Only where small components hold at least [`MIN_SHARE`] of the nodes: on fluid frames with a
//! few dozen droplets beside a body, solves converge in a few iterations on the kept factor, and
//! exact droplet blocks only perturb the steps (the dam break: 87.51% of vertices carried per frame
//! against 87.88%, and 8% slower).

use faer::linalg::solvers::{Llt, Solve};
use faer::{Mat, Side};
use rayon::prelude::*;

use super::assemble::assemble_dense;
use super::energy::CoarseWeights;
use super::model::{Model, NODE_DOFS};
use super::pattern::Pattern;
use crate::geometry::Components;

/// Components of at most this many nodes are small: a factor of at most 96 × 96.
const MAX_NODES: usize = 8;

/// The share of the graph's nodes that small components must hold for their blocks to be factored
/// apart.
const MIN_SHARE: f64 = 0.25;

/// The small components and, after [`SmallBlocks::refresh`], the exact factor of each.
pub struct SmallBlocks {
    /// Node lists, ascending.
    components: Vec<Vec<u32>>,
    /// The Cholesky factor of each component's damped block; `None` where it was not positive
    /// definite in double precision (the sparse factor then stands in for it).
    factors: Vec<Option<Llt<f64>>>,
}

impl SmallBlocks {
    /// The components of at most [`MAX_NODES`] nodes of `pattern`'s block graph, if they hold at
    /// least [`MIN_SHARE`] of its nodes; else none.
    pub fn new(pattern: &Pattern) -> Self {
        let nodes = pattern.node_count();
        let mut joined = Components::new(nodes, &[]);
        for j in 0..nodes {
            let blocks = pattern.block_col_ptr[j] as usize..pattern.block_col_ptr[j + 1] as usize;
            for &i in &pattern.block_rows[blocks] {
                joined.join(i, j as u32);
            }
        }
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); nodes];
        for node in 0..nodes as u32 {
            members[joined.find(node) as usize].push(node);
        }
        let components: Vec<Vec<u32>> = members
            .into_iter()
            .filter(|m| !m.is_empty() && m.len() <= MAX_NODES)
            .collect();
        let small: usize = components.iter().map(Vec::len).sum();
        if (small as f64) < MIN_SHARE * nodes as f64 {
            return Self::none();
        }
        Self {
            components,
            factors: Vec::new(),
        }
    }

    /// No small components apart: the preconditioner is the sparse factor alone.
    pub fn none() -> Self {
        Self {
            components: Vec::new(),
            factors: Vec::new(),
        }
    }

    /// Assembles and factors every small component's block at unknowns `x`, fit matrices `fit`,
    /// weights `w` and damping `lambda`.
    pub fn refresh(
        &mut self,
        pattern: &Pattern,
        model: &Model,
        x: &[f64],
        fit: &[[[f64; 3]; 3]],
        w: &CoarseWeights,
        lambda: f64,
    ) {
        self.factors = self
            .components
            .par_iter()
            .map(|nodes| {
                let m = NODE_DOFS * nodes.len();
                let block = assemble_dense(pattern, model, x, fit, w, nodes);
                Mat::from_fn(m, m, |r, c| {
                    block[r * m + c] + if r == c { lambda } else { 0.0 }
                })
                .llt(Side::Lower)
                .ok()
            })
            .collect();
    }

    /// Replaces `z` on each small component's unknowns by its block's exact solve of `r`.
    pub fn apply(&self, r: &[f64], z: &mut [f64]) {
        for (nodes, factor) in self.components.iter().zip(&self.factors) {
            let Some(factor) = factor else { continue };
            let dof = |k: usize| NODE_DOFS * nodes[k / NODE_DOFS] as usize + k % NODE_DOFS;
            let m = NODE_DOFS * nodes.len();
            let solved = factor.solve(Mat::from_fn(m, 1, |k, _| r[dof(k)]));
            for k in 0..m {
                z[dof(k)] = solved[(k, 0)];
            }
        }
    }
}
