//! The sparsity pattern of the Gauss-Newton matrix `JᵀJ`, fixed for as long as the deformation graph
//! is: one dense 12×12 block for every pair of nodes that skin a common vertex or share a graph
//! edge. Only the upper triangle is stored (faer reads it as self-adjoint), as a scalar compressed
//! column matrix whose value positions are known per block, so assembly writes in place.

use rayon::prelude::*;

use super::energy::smooth_psi;
use super::model::{Model, NODE_DOFS};
use super::{FactorizationError, RegisterError};

/// One fit contribution to a block: vertex `v` whose skinning entries `si` (row node) and `sj`
/// (column node) name the block's two nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct FitPair {
    pub row: u32,
    pub vertex: u32,
    pub si: u32,
    pub sj: u32,
}

/// Block structure, per-block contributions and the scalar pattern.
#[derive(Debug, Clone)]
pub struct Pattern {
    nodes: usize,
    /// Blocks of column-node `j` are `block_col_ptr[j]..block_col_ptr[j + 1]`, by increasing row
    /// node; the last is the diagonal block.
    pub block_col_ptr: Vec<u32>,
    pub block_rows: Vec<u32>,
    /// Fit contributions of each block (compressed rows over blocks).
    pub fit_ptr: Vec<u32>,
    pub fit_pairs: Vec<FitPair>,
    /// The constant `E_smooth` Hessian of each block is `smooth[b] ⊗ I₃` (4×4, row-major).
    pub smooth: Vec<[f64; 16]>,
    /// Scalar compressed-column upper triangle of dimension `12 × nodes`.
    pub col_ptr: Vec<u32>,
    pub row_idx: Vec<u32>,
}

/// Which node pairs get a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coupling {
    /// Every pair that skins a common vertex or shares a graph edge: the exact `JᵀJ`.
    Full,
    /// Graph edges only. The fit coupling of any other pair `(a, b)` of a vertex is replaced by
    /// the self terms `(u_a u_aᵀ) ⊗ M` on `a` and `(u_b u_bᵀ) ⊗ M` on `b`; since
    /// `2 pᵀq ≤ |p|² + |q|²`, the result bounds `JᵀJ` from above and stays positive semidefinite,
    /// with the sparsity (and fill) of the graph itself.
    Graph,
}

impl Pattern {
    pub fn new(model: &Model, coupling: Coupling) -> Result<Self, RegisterError> {
        let nodes = model.node_count();
        let columns = collect_by_column(model);
        let rows_of = |j: usize, pairs: &[FitPair]| -> Vec<u32> {
            let mut rows: Vec<u32> = match coupling {
                Coupling::Full => pairs.iter().map(|p| p.row).collect(),
                Coupling::Graph => Vec::new(),
            };
            rows.extend(
                model
                    .node_neighbours(j)
                    .iter()
                    .copied()
                    .filter(|&i| (i as usize) < j),
            );
            rows.push(j as u32);
            rows.sort_unstable();
            rows.dedup();
            rows
        };
        let block_rows_per_column: Vec<Vec<u32>> = columns
            .iter()
            .enumerate()
            .map(|(j, pairs)| rows_of(j, pairs))
            .collect();
        let mut spill: Vec<Vec<FitPair>> = vec![Vec::new(); nodes];
        for (j, pairs) in columns.iter().enumerate() {
            let rows = &block_rows_per_column[j];
            for p in pairs {
                if rows.binary_search(&p.row).is_err() {
                    spill[j].push(FitPair {
                        row: j as u32,
                        vertex: p.vertex,
                        si: p.sj,
                        sj: p.sj,
                    });
                    spill[p.row as usize].push(FitPair {
                        row: p.row,
                        vertex: p.vertex,
                        si: p.si,
                        sj: p.si,
                    });
                }
            }
        }
        let mut block_col_ptr = Vec::with_capacity(nodes + 1);
        block_col_ptr.push(0u32);
        let mut block_rows = Vec::new();
        let mut fit_ptr = vec![0u32];
        let mut fit_pairs = Vec::new();
        for (j, (pairs, rows)) in columns.iter().zip(block_rows_per_column).enumerate() {
            let mut next = 0;
            for &row in &rows {
                while next < pairs.len() && pairs[next].row < row {
                    next += 1;
                }
                while next < pairs.len() && pairs[next].row == row {
                    fit_pairs.push(pairs[next]);
                    next += 1;
                }
                if row as usize == j {
                    spill[j].sort_unstable();
                    fit_pairs.extend_from_slice(&spill[j]);
                }
                fit_ptr.push(fit_pairs.len() as u32);
            }
            block_rows.extend(rows);
            block_col_ptr.push(block_rows.len() as u32);
        }
        let mut pattern = Self {
            nodes,
            block_col_ptr,
            block_rows,
            fit_ptr,
            fit_pairs,
            smooth: Vec::new(),
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
        };
        pattern.smooth = pattern.smooth_blocks(model);
        pattern.expand()?;
        Ok(pattern)
    }

    pub fn node_count(&self) -> usize {
        self.nodes
    }

    pub fn dimension(&self) -> usize {
        NODE_DOFS * self.nodes
    }

    /// Index of block (i, j), `i ≤ j`.
    fn block(&self, i: u32, j: usize) -> Option<usize> {
        let range = self.block_col_ptr[j] as usize..self.block_col_ptr[j + 1] as usize;
        self.block_rows[range.clone()]
            .binary_search(&i)
            .ok()
            .map(|k| range.start + k)
    }

    /// `E_smooth`'s Hessian per block. Edge i→j has Jacobian `ψᵀ ⊗ I₃` for node i and `−e₃ᵀ ⊗ I₃`
    /// for node j, so it adds `ψψᵀ` to (i, i), `e₃e₃ᵀ` to (j, j) and `−ψ e₃ᵀ` to (i, j).
    fn smooth_blocks(&self, model: &Model) -> Vec<[f64; 16]> {
        let mut smooth = vec![[0.0; 16]; self.block_rows.len()];
        let mut add = |b: Option<usize>, f: &dyn Fn(usize, usize) -> f64| {
            if let Some(b) = b {
                for r in 0..4 {
                    for c in 0..4 {
                        smooth[b][4 * r + c] += f(r, c);
                    }
                }
            }
        };
        let e3 = |r: usize| if r == 3 { 1.0 } else { 0.0 };
        for &[i, j] in &model.edges {
            let (i, j) = (i as usize, j as usize);
            let out = smooth_psi(model, i, j);
            let back = smooth_psi(model, j, i);
            add(self.block(i as u32, j), &|r, c| {
                -out[r] * e3(c) - e3(r) * back[c]
            });
            add(self.block(i as u32, i), &|r, c| {
                out[r] * out[c] + e3(r) * e3(c)
            });
            add(self.block(j as u32, j), &|r, c| {
                back[r] * back[c] + e3(r) * e3(c)
            });
        }
        smooth
    }

    /// Expands blocks into scalar columns: column `12 j + q` holds, for each block row node `i < j`,
    /// rows `12 i .. 12 i + 12`, then rows `12 j ..= 12 j + q` of the diagonal block. Entry `(p, q)`
    /// of the block of rank `r` in its column is then at `col_ptr[12 j + q] + 12 r + p`.
    fn expand(&mut self) -> Result<(), RegisterError> {
        let n = self.dimension();
        let mut nnz = 0usize;
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        for j in 0..self.nodes {
            let off = (self.block_col_ptr[j + 1] - self.block_col_ptr[j] - 1) as usize;
            for q in 0..NODE_DOFS {
                nnz += NODE_DOFS * off + q + 1;
                col_ptr.push(nnz);
            }
        }
        if nnz > u32::MAX as usize / 2 {
            return Err(FactorizationError::TooManyNonzeros { nonzeros: nnz }.into());
        }
        let mut row_idx = vec![0u32; nnz];
        let block_col_ptr = &self.block_col_ptr;
        let block_rows = &self.block_rows;
        let mut rest = row_idx.as_mut_slice();
        let mut chunks = Vec::with_capacity(self.nodes);
        for j in 0..self.nodes {
            let len = col_ptr[NODE_DOFS * (j + 1)] - col_ptr[NODE_DOFS * j];
            let (head, tail) = rest.split_at_mut(len);
            chunks.push(head);
            rest = tail;
        }
        chunks.into_par_iter().enumerate().for_each(|(j, out)| {
            let rows = &block_rows[block_col_ptr[j] as usize..block_col_ptr[j + 1] as usize];
            let mut at = 0;
            for q in 0..NODE_DOFS {
                for &i in &rows[..rows.len() - 1] {
                    for p in 0..NODE_DOFS {
                        out[at] = (NODE_DOFS * i as usize + p) as u32;
                        at += 1;
                    }
                }
                for p in 0..=q {
                    out[at] = (NODE_DOFS * j + p) as u32;
                    at += 1;
                }
            }
        });
        self.col_ptr = col_ptr.into_iter().map(|c| c as u32).collect();
        self.row_idx = row_idx;
        Ok(())
    }

    /// A fill-reducing order of the scalar unknowns: approximate minimum degree on the node graph,
    /// each node's 12 unknowns kept together (cheaper than ordering the scalar matrix, and the
    /// factor then has dense 12-wide supernodes).
    pub fn ordering(&self) -> Result<(Vec<u32>, Vec<u32>), RegisterError> {
        use faer::sparse::SymbolicSparseColMatRef;
        use faer::sparse::linalg::amd;
        let n = self.nodes;
        let block =
            SymbolicSparseColMatRef::new_checked(n, n, &self.block_col_ptr, None, &self.block_rows);
        let mut fwd = vec![0u32; n];
        let mut inv = vec![0u32; n];
        let mut mem = faer::dyn_stack::MemBuffer::try_new(amd::order_scratch::<u32>(
            n,
            self.block_rows.len(),
        ))
        .map_err(|_| FactorizationError::OutOfMemory {
            what: "graph ordering workspace",
        })?;
        amd::order(
            &mut fwd,
            &mut inv,
            block,
            amd::Control::default(),
            faer::dyn_stack::MemStack::new(&mut mem),
        )
        .map_err(|e| FactorizationError::Ordering {
            unknowns: n,
            reason: format!("{e:?}"),
        })?;
        let expand = |perm: &[u32]| -> Vec<u32> {
            perm.iter()
                .flat_map(|&b| (0..NODE_DOFS as u32).map(move |t| NODE_DOFS as u32 * b + t))
                .collect()
        };
        Ok((expand(&fwd), expand(&inv)))
    }
}

/// Fit pairs grouped by column node, each group sorted by (row node, vertex).
fn collect_by_column(model: &Model) -> Vec<Vec<FitPair>> {
    let nodes = model.node_count();
    let mut counts = vec![0usize; nodes];
    for v in 0..model.vertex_count() {
        let range = model.skin_range(v);
        for a in range.clone() {
            for b in a..range.end {
                let (na, nb) = (model.skin_nodes[a], model.skin_nodes[b]);
                counts[na.max(nb) as usize] += 1;
            }
        }
    }
    let mut columns: Vec<Vec<FitPair>> = counts.iter().map(|&c| Vec::with_capacity(c)).collect();
    for v in 0..model.vertex_count() {
        let range = model.skin_range(v);
        for a in range.clone() {
            for b in a..range.end {
                let (na, nb) = (model.skin_nodes[a], model.skin_nodes[b]);
                let (si, sj) = if na <= nb { (a, b) } else { (b, a) };
                columns[na.max(nb) as usize].push(FitPair {
                    row: na.min(nb),
                    vertex: v as u32,
                    si: si as u32,
                    sj: sj as u32,
                });
            }
        }
    }
    columns.par_iter_mut().for_each(|c| c.sort_unstable());
    columns
}
