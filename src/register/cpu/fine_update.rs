//! CPU twin of `kernels/fine_update.wgsl`.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use super::fine_start::Iterates;
use crate::kernels::shared::CgState;
use crate::register::model::CHUNK;

/// CPU twin of `kernels/fine_update.wgsl`: one closure call per vertex `v` steps `d` along `p`
/// and `r` along `A p` by `α`, preconditions `r` into `z` and writes the terms `rᵀz`, `|r|²`;
/// nothing once the solve has ended.
pub(in crate::register) fn fine_update(
    state: &CgState,
    ad: &[DVec3],
    preconditioner: &[DMat3],
    iterates: Iterates,
    terms: &mut [[f64; 2]],
) {
    if state.done != 0 {
        return;
    }
    let Iterates { d, r, z, p } = iterates;
    let p: &[DVec3] = p;
    let alpha = state.alpha;
    d.par_iter_mut()
        .zip(r)
        .zip(z)
        .zip(terms)
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(v, (((d, r), z), terms))| {
            let dv = *d + p[v] * alpha;
            let rv = *r - ad[v] * alpha;
            let zv = preconditioner[v] * rv;
            *d = dv;
            *r = rv;
            *z = zv;
            *terms = [rv.dot(zv), rv.dot(rv)];
        });
}
