//! CPU twin of `kernels/fine_reduce.wgsl`.

use rayon::prelude::*;

use crate::kernels::shared::REDUCE_CHUNK;

/// CPU twin of `kernels/fine_reduce.wgsl`: one closure call per chunk `c` of `REDUCE_CHUNK`
/// vertices sums each of their two terms in vertex order.
pub(in crate::register) fn fine_reduce(terms: &[[f64; 2]], partials: &mut [[f64; 2]]) {
    partials
        .par_iter_mut()
        .zip(terms.par_chunks(REDUCE_CHUNK as usize))
        .for_each(|(partial, chunk)| {
            let mut first = 0.0;
            let mut second = 0.0;
            for term in chunk {
                first += term[0];
                second += term[1];
            }
            *partial = [first, second];
        });
}
