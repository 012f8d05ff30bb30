//! CPU twin of `kernels/fine_cover.wgsl`.

use glam::DVec3;
use rayon::prelude::*;

use crate::kernels::shared::CgState;
use crate::register::cover::Cover;
use crate::register::model::CHUNK;

/// CPU twin of `kernels/fine_cover.wgsl`: one closure call per cover pair `p` writes
/// `M_p Σ_k w_k x_k`; nothing once the solve has ended.
pub(in crate::register) fn fine_cover(
    state: &CgState,
    cover: &Cover,
    x: &[DVec3],
    moved: &mut [DVec3],
) {
    if state.done != 0 {
        return;
    }
    moved
        .par_iter_mut()
        .enumerate()
        .with_min_len(CHUNK)
        .for_each(|(p, moved)| {
            let [a, b, c] = cover.corners[p];
            let [wa, wb, wc] = cover.weights[p];
            let blend = x[a as usize] * wa + x[b as usize] * wb + x[c as usize] * wc;
            *moved = cover.matrices[p] * blend;
        });
}
