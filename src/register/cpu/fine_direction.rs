//! CPU twin of `kernels/fine_direction.wgsl`.

use glam::DVec3;
use rayon::prelude::*;

use crate::kernels::shared::CgState;
use crate::register::model::CHUNK;

/// CPU twin of `kernels/fine_direction.wgsl`: one closure call per vertex `v` writes
/// `p = z + β p`; nothing once the solve has ended.
pub(in crate::register) fn fine_direction(state: &CgState, z: &[DVec3], p: &mut [DVec3]) {
    if state.done != 0 {
        return;
    }
    let beta = state.beta;
    p.par_iter_mut()
        .zip(z)
        .with_min_len(CHUNK)
        .for_each(|(p, z)| *p = *z + *p * beta);
}
