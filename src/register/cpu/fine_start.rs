//! CPU twin of `kernels/fine_start.wgsl`.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::kernels::shared::CgState;
use crate::register::model::CHUNK;

/// The vectors a conjugate-gradient solve of the fine stage updates.
pub(in crate::register) struct Iterates<'a> {
    pub d: &'a mut [DVec3],
    pub r: &'a mut [DVec3],
    pub z: &'a mut [DVec3],
    pub p: &'a mut [DVec3],
}

/// CPU twin of `kernels/fine_start.wgsl`: one closure call per vertex `v` writes `r = b − A d`,
/// `z = P r`, `p = z` and the terms `rᵀz`, `|r|²`; where `b = 0`, `d = 0` and nothing else.
pub(in crate::register) fn fine_start(
    state: &CgState,
    b: &[DVec3],
    preconditioner: &[DMat3],
    ad: &[DVec3],
    iterates: Iterates,
    terms: &mut [[f64; 2]],
) {
    let Iterates { d, r, z, p } = iterates;
    if state.b_norm == 0.0 {
        d.par_iter_mut().for_each(|d| *d = DVec3::ZERO);
        return;
    }
    r.par_iter_mut()
        .zip(z)
        .zip(p)
        .zip(terms)
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(v, (((r, z), p), terms))| {
            let rv = b[v] - ad[v];
            let zv = preconditioner[v] * rv;
            *r = rv;
            *z = zv;
            *p = zv;
            *terms = [rv.dot(zv), rv.dot(rv)];
        });
}
