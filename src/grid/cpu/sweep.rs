//! CPU twin of `kernels/sweep.wgsl`.

use rayon::prelude::*;

use crate::grid::sparse::Crossings;
use crate::kernels::shared::WindingRun;

/// CPU twin of `kernels/sweep.wgsl`: one closure call per kernel invocation (one line), writing one
/// slot per crossing.
pub fn sweep_cpu(crossings: &Crossings) -> Vec<WindingRun> {
    (0..crossings.index().len())
        .into_par_iter()
        .with_min_len(64)
        .flat_map_iter(|l| {
            let line = crossings.of_line(l);
            let mut winding = 0;
            line.iter().enumerate().map(move |(k, c)| {
                winding += c.sign();
                let last_on_edge = line.get(k + 1).is_none_or(|next| next.along() != c.along());
                WindingRun {
                    start: if last_on_edge {
                        c.along() + 1
                    } else {
                        WindingRun::CONTINUES
                    },
                    winding,
                }
            })
        })
        .collect()
}
