//! Rasterization: every crossing of a triangle with a grid edge (thesis §3.4.2, paper §4.3).
//!
//! Kernel: `kernels/rasterize.wgsl`. Both backends walk the same candidates: for each triangle, each
//! axis, the grid lines through the triangle's cell range (the lines strictly inside its projected
//! bounding box, row by row), and decide each with [`line_crossing`], whose exact predicates make the
//! two backends agree on every crossing, its grid edge and its direction. The crossings are then
//! sorted into lines ([`Crossings`]), which also makes their order independent of GPU scheduling.

use rayon::prelude::*;

use super::RasterError;
use super::crossing::GridCrossing;
use super::lattice::{LatticeMesh, cell_range};
use super::predicates::{LocalTriangle, cross_axes, line_crossing};
use super::rasterize_gpu::GpuRasterize;
use super::sparse::Crossings;
use crate::compute::Backend;

/// Every grid-edge crossing of `mesh`, grouped by grid line.
///
/// Fails only when the GPU backend cannot run the kernel.
pub fn rasterize(backend: &Backend, mesh: &LatticeMesh) -> Result<Crossings, RasterError> {
    let crossings = match backend {
        Backend::Cpu => rasterize_cpu(mesh),
        Backend::Gpu(context) => {
            let job = GpuRasterize::upload(context, mesh)?;
            job.dispatch(context)?;
            job.read(context)?
        }
    };
    Ok(Crossings::from_unsorted(crossings))
}

/// Number of candidate lines of a triangle with vertex cells `lo..=hi`, per axis.
///
/// A line along `axis` can meet the perturbed triangle only when it lies strictly inside the
/// projected bounding box, shifted by `-δ`: its cells along the two other axes are in
/// `lo + 1 ..= hi`.
pub(crate) fn candidate_counts(lo: [i32; 3], hi: [i32; 3]) -> [u64; 3] {
    std::array::from_fn(|axis| {
        let (u, v) = cross_axes(axis);
        (hi[u] - lo[u]) as u64 * (hi[v] - lo[v]) as u64
    })
}

/// CPU twin of `kernels/rasterize.wgsl`: the kernel runs one invocation per candidate line, this
/// runs the candidates of one triangle in the kernel's order (axis, then row `v`, then `u`).
fn rasterize_cpu(mesh: &LatticeMesh) -> Vec<GridCrossing> {
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
