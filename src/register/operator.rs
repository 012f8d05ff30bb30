//! The Gauss-Newton matrix `H = JᵀJ` (weighted, plus damping `λ I`) applied to a vector without
//! being assembled: `J v` per vertex, then `Jᵀ` gathered node by node. Conjugate gradients use it
//! to solve the exact Gauss-Newton system while factoring only a sparser bound of it.

use glam::DVec3;
use rayon::prelude::*;

use super::energy::{CoarseWeights, add_fit_transpose, add_smooth, rigid_jacobian, smooth_linear};
use super::model::{CHUNK, Model, NODE_DOFS};

/// `H` at unknowns `x` with per-vertex fit matrices `fit`.
pub struct GaussNewton<'a> {
    pub model: &'a Model,
    pub x: &'a [f64],
    pub fit: &'a [[[f64; 3]; 3]],
    pub weights: CoarseWeights,
    pub damping: f64,
}

impl GaussNewton<'_> {
    /// `out = (H + λ I) v`.
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        let model = self.model;
        let pulls: Vec<DVec3> = (0..model.vertex_count())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|p| {
                let m = &self.fit[p];
                let d = model.deform_vertex(v, p) - model.base[p];
                DVec3::from_array(m.map(|row| row[0] * d.x + row[1] * d.y + row[2] * d.z))
            })
            .collect();
        let w = &self.weights;
        out.par_chunks_mut(NODE_DOFS)
            .enumerate()
            .for_each(|(i, o)| {
                let vi = &v[NODE_DOFS * i..][..NODE_DOFS];
                for (o, &x) in o.iter_mut().zip(vi) {
                    *o = self.damping * x;
                }
                add_fit_transpose(model, &pulls, i, o);
                let jac = rigid_jacobian(&self.x[NODE_DOFS * i..][..NODE_DOFS]);
                for row in &jac {
                    let jv: f64 = row.iter().zip(vi).map(|(a, b)| a * b).sum();
                    for (o, &a) in o.iter_mut().zip(row) {
                        *o += w.reg * a * jv;
                    }
                }
                add_smooth(model, w.reg * w.smooth, i, o, |a, b| {
                    smooth_linear(model, v, a, b)
                });
            });
    }
}
