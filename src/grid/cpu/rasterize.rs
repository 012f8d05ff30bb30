//! CPU twin of `kernels/rasterize.wgsl`.

use rayon::prelude::*;

use crate::grid::lattice::{LatticeMesh, cell_range};
use crate::grid::predicates::{LocalTriangle, cross_axes, line_crossing};
use crate::kernels::shared::GridCrossing;

/// CPU twin of `kernels/rasterize.wgsl`: the kernel runs one invocation per candidate line, this
/// runs the candidates of one triangle in the kernel's order (axis, then row `v`, then `u`).
pub fn rasterize_cpu(mesh: &LatticeMesh) -> Vec<GridCrossing> {
    (0..mesh.triangles().len())
        .into_par_iter()
        .with_min_len(256)
        .flat_map_iter(|t| {
            let corners = mesh.corners(t);
            let (lo, hi) = cell_range(&corners);
            let local = LocalTriangle::new(&corners);
            (0..3).flat_map(move |axis| {
                let (u, v) = cross_axes(axis);
                (lo[v] + 1..=hi[v]).flat_map(move |line_v| {
                    (lo[u] + 1..=hi[u]).filter_map(move |line_u| {
                        line_crossing(&local, hi[axis], t as u32, axis, line_u, line_v)
                    })
                })
            })
        })
        .collect()
}
