//! CPU twin of `kernels/fine_system.wgsl`.

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::kernels::shared::FineTarget;
use crate::register::fine_solve::{FineSystem, outer};
use crate::register::model::CHUNK;

/// CPU twin of `kernels/fine_system.wgsl`: one closure call per vertex `v` writes its fit matrix,
/// right-hand side, preconditioner block and `|b_v|²`.
pub(in crate::register) fn fine_system(
    system: &FineSystem,
    targets: &[FineTarget],
    fit: &mut [DMat3],
    b: &mut [DVec3],
    preconditioner: &mut [DMat3],
    terms: &mut [[f64; 2]],
) {
    let params = &system.params;
    let cover = &system.cover;
    fit.par_iter_mut()
        .zip(b)
        .zip(preconditioner)
        .zip(terms)
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(v, (((fit, b), preconditioner), terms))| {
            let target_v = &targets[v];
            let mut m = DMat3::ZERO;
            let mut rhs = DVec3::ZERO;
            if target_v.found != 0 {
                let n = DVec3::from_array(target_v.normal);
                let c = DVec3::from_array(target_v.point);
                let p = system.start[v];
                m = outer(n) * params.plane_weight + DMat3::IDENTITY * params.point_weight;
                rhs = m * (c - p);
            }
            let mut diagonal = DMat3::ZERO;
            for &entry in cover.entries(v) {
                let pair = (entry >> 2) as usize;
                let w = cover.weights[pair][(entry & 3) as usize];
                rhs += cover.pulls[pair] * w;
                diagonal += cover.matrices[pair] * (w * w);
            }
            let mut block = m + diagonal;
            for &e in system.directions(v) {
                block += DMat3::IDENTITY * params.disp_weight + outer(e) * params.edge_weight;
            }
            let inverse = if block.determinant().abs() > 1e-300 {
                block.inverse()
            } else {
                DMat3::IDENTITY
            };
            *fit = m;
            *b = rhs;
            *preconditioner = inverse;
            *terms = [rhs.dot(rhs), 0.0];
        });
}
