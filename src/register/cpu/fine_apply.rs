//! CPU twin of `kernels/fine_apply.wgsl`.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::kernels::shared::CgState;
use crate::register::fine_solve::FineSystem;
use crate::register::model::CHUNK;

/// CPU twin of `kernels/fine_apply.wgsl`: one closure call per vertex `v` writes `(A x)_v` and
/// `x_v·(A x)_v`; nothing once the solve has ended.
pub(in crate::register) fn fine_apply(
    system: &FineSystem,
    state: &CgState,
    fit: &[DMat3],
    moved: &[DVec3],
    x: &[DVec3],
    out: &mut [DVec3],
    terms: &mut [[f64; 2]],
) {
    if state.done != 0 {
        return;
    }
    let params = &system.params;
    let cover = &system.cover;
    out.par_iter_mut()
        .zip(terms)
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(v, (out, terms))| {
            let xv = x[v];
            let mut y = fit[v] * xv;
            for (&u, &e) in system.neighbours(v).iter().zip(system.directions(v)) {
                let diff = xv - x[u as usize];
                y += diff * params.disp_weight + (e * params.edge_weight) * e.dot(diff);
            }
            for &entry in cover.entries(v) {
                let pair = (entry >> 2) as usize;
                let w = cover.weights[pair][(entry & 3) as usize];
                y += moved[pair] * w;
            }
            *out = y;
            *terms = [xv.dot(y), 0.0];
        });
}
