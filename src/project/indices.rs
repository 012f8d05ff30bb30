//! Triangle indices checked against the positions they index, before either backend reads them.

use rayon::prelude::*;

use crate::compute::ComputeError;

/// The first triangle (in order, whatever the thread count) with an index past `count`.
pub(super) fn check_indices(count: usize, triangles: &[[u32; 3]]) -> Result<(), ComputeError> {
    let bad = triangles
        .par_iter()
        .enumerate()
        .find_first(|(_, tri)| tri.iter().any(|&v| v as usize >= count));
    match bad {
        None => Ok(()),
        Some((triangle, tri)) => Err(ComputeError::IndexOutOfRange {
            triangle,
            vertex: tri
                .iter()
                .copied()
                .find(|&v| v as usize >= count)
                .unwrap_or(tri[0]),
            count,
        }),
    }
}
