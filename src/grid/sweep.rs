//! Inside/outside sweeps: along every grid line, the signed crossings summed from `-∞` give the
//! winding number of each corner (thesis §3.4.3, after Wojtan et al.'s sweeps). Corners with winding
//! above 1 or below 0 lie where the surface overlaps or is inverted: `ConstrainTopology(M, Φ(M))`
//! resolves those (paper §4.3).
//!
//! Kernel: `kernels/sweep.wgsl`, its CPU twin `cpu/sweep.rs`, its GPU host `gpu/sweep.rs`. Both
//! backends run one pass per line over its sorted crossings and
//! write, for the last crossing of each grid edge, the run of constant winding that starts at the
//! edge's upper corner. A line is then a handful of runs and a line without crossings is empty
//! space (winding 0), so every corner of the unbounded grid is classified, far ones included, with
//! memory proportional to the number of crossings.
//!
//! The thesis sweeps each line in both directions and clumps nearby crossings to survive numerical
//! error; with exact predicates one direction suffices, the sum returns to 0 at the end of every
//! line of a closed mesh, and the three axes give the same winding at every corner. Those two facts
//! are checked by [`Windings::unbalanced_lines`] and [`CornerWindings::consistent`].

use rayon::prelude::*;

use super::RasterError;
use super::cpu::sweep::sweep_cpu;
use super::gpu::GpuSweep;
use super::sparse::{Crossings, GridLine, LineIndex};
use crate::compute::{Backend, kernel_time};
use crate::kernels::shared::WindingRun;

/// Sweeps every line of `crossings` into winding runs.
///
/// Fails only when the GPU backend cannot run the kernel.
pub fn sweep(backend: &Backend, crossings: &Crossings) -> Result<Windings, RasterError> {
    let slots = kernel_time::timed(|| match backend {
        Backend::Cpu => Ok(sweep_cpu(crossings)),
        Backend::Gpu(context) => GpuSweep::run(context, crossings),
    })?;
    Ok(Windings::from_slots(crossings.index(), &slots))
}

/// The winding number of every grid corner, as runs along the lines that carry crossings.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Windings {
    index: LineIndex,
    runs: Vec<WindingRun>,
}

/// The winding number of one corner as the sweep along each axis sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CornerWindings(pub [i32; 3]);

impl CornerWindings {
    /// Inside the surface: winding at least 1 along x (the three agree on a closed mesh).
    pub fn inside(&self) -> bool {
        self.0[0] >= 1
    }

    /// The three sweeps agree, as they always do for a closed, consistently oriented mesh.
    pub fn consistent(&self) -> bool {
        self.0[0] == self.0[1] && self.0[1] == self.0[2]
    }

    /// A winding above 1 or below 0 along some axis: the surface overlaps itself or is inverted here.
    pub fn self_intersecting(&self) -> bool {
        self.0.iter().any(|&w| !(0..=1).contains(&w))
    }
}

impl Windings {
    /// Keeps the slots that start a run, line by line.
    fn from_slots(crossings: &LineIndex, slots: &[WindingRun]) -> Self {
        let per_line: Vec<Vec<WindingRun>> = (0..crossings.len())
            .into_par_iter()
            .with_min_len(64)
            .map(|l| {
                slots[crossings.range(l)]
                    .iter()
                    .copied()
                    .filter(|r| r.start != WindingRun::CONTINUES)
                    .collect()
            })
            .collect();
        let index = crossings.with_counts(per_line.iter().map(|r| r.len() as u32));
        Self {
            index,
            runs: per_line.into_iter().flatten().collect(),
        }
    }

    pub fn index(&self) -> &LineIndex {
        &self.index
    }

    /// All runs, line by line.
    pub fn runs(&self) -> &[WindingRun] {
        &self.runs
    }

    /// Runs of line number `l`, in order along it; corners before the first run have winding 0.
    pub fn of_line(&self, l: usize) -> &[WindingRun] {
        &self.runs[self.index.range(l)]
    }

    /// Runs of `line`; empty when the line misses the surface.
    pub fn on_line(&self, line: &GridLine) -> &[WindingRun] {
        self.index.find(line).map_or(&[], |l| self.of_line(l))
    }

    /// Winding number of `corner` from the sweep along `axis`.
    pub fn winding(&self, axis: usize, corner: [i32; 3]) -> i32 {
        winding_at(self.on_line(&GridLine::through(axis, corner)), corner[axis])
    }

    /// Winding number of `corner` from all three sweeps.
    pub fn corner(&self, corner: [i32; 3]) -> CornerWindings {
        CornerWindings(std::array::from_fn(|axis| self.winding(axis, corner)))
    }

    /// Lines whose winding does not return to 0 past their last crossing: never, for a closed mesh.
    pub fn unbalanced_lines(&self) -> Vec<GridLine> {
        (0..self.index.len())
            .filter(|&l| self.of_line(l).last().is_some_and(|r| r.winding != 0))
            .map(|l| self.index.lines()[l])
            .collect()
    }

    /// Winding numbers (from the sweep along x) of every corner of the box `lo .. lo + dims`, x
    /// fastest: a dense view for callers that want one over a region of their choosing.
    pub fn fill_box(&self, lo: [i32; 3], dims: [usize; 3]) -> Vec<i32> {
        let mut out = vec![0i32; dims[0] * dims[1] * dims[2]];
        if dims[0] == 0 {
            return out;
        }
        out.par_chunks_mut(dims[0])
            .enumerate()
            .for_each(|(row, values)| {
                let j = lo[1] + (row % dims[1].max(1)) as i32;
                let k = lo[2] + (row / dims[1].max(1)) as i32;
                let runs = self.on_line(&GridLine {
                    axis: 0,
                    at: [j, k],
                });
                if runs.is_empty() {
                    return;
                }
                let mut r = runs.partition_point(|run| run.start <= lo[0]);
                let mut winding = if r == 0 { 0 } else { runs[r - 1].winding };
                for (x, value) in values.iter_mut().enumerate() {
                    let i = lo[0] + x as i32;
                    while r < runs.len() && runs[r].start <= i {
                        winding = runs[r].winding;
                        r += 1;
                    }
                    *value = winding;
                }
            });
        out
    }
}

/// Winding at index `along` of a line with runs `runs`.
fn winding_at(runs: &[WindingRun], along: i32) -> i32 {
    let r = runs.partition_point(|run| run.start <= along);
    if r == 0 { 0 } else { runs[r - 1].winding }
}
