//! Θ, the voxelized implicit surface a mesh's topology is constrained to (paper §4.3): a value at
//! every corner of the topology grid, negative inside, whose zero set is extracted with the grid's
//! marching-cubes rule.
//!
//! Θ is defined at every corner of the unbounded grid. A sampled box is outside beyond its border; a
//! narrow band around a mesh takes the mesh's inside/outside classification (its sweep windings)
//! beyond the band, so `Φ(M)` and `Φ(T)` need memory for the band only.

use glam::Vec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::TopologyError;
use super::keys::{Cell, Corner, GridEdge, cell_corner, corner_cells};
use crate::grid::{GridFrame, T_MIN, Windings};

/// A voxelized implicit surface on a grid: `value(corner) < 0` inside.
#[derive(Debug, Clone)]
pub struct Field {
    frame: GridFrame,
    values: Values,
}

#[derive(Debug, Clone)]
enum Values {
    /// Samples of the corners `lo ..= lo + dims - 1`, x fastest.
    Box {
        lo: [i32; 3],
        dims: [usize; 3],
        values: Vec<f32>,
    },
    /// Values near a surface; beyond them the windings' inside/outside at distance `far`.
    /// `balanced`: every line's winding returns to 0, as it does for a closed mesh, so the three
    /// sweeps agree on every corner.
    Band {
        near: FxHashMap<Corner, f32>,
        windings: Windings,
        far: f32,
        balanced: bool,
    },
}

/// Largest number of corners a sampled box may have.
const MAX_BOX_CORNERS: usize = 1 << 30;

impl Field {
    /// Θ sampled from `f` (world position to value) at every corner from `lo` to `hi` inclusive;
    /// corners outside that box are outside.
    pub fn from_fn<F>(frame: GridFrame, lo: [i32; 3], hi: [i32; 3], f: F) -> Result<Self, TopologyError>
    where
        F: Fn(Vec3) -> f32 + Sync,
    {
        let dims: [usize; 3] = std::array::from_fn(|a| (hi[a] - lo[a] + 1).max(0) as usize);
        let count = dims
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .filter(|&n| n <= MAX_BOX_CORNERS)
            .ok_or(TopologyError::FieldTooLarge { dims })?;
        let mut values = vec![0.0f32; count];
        let plane = dims[0] * dims[1];
        if plane > 0 {
            values
                .par_chunks_mut(plane)
                .enumerate()
                .for_each(|(k, slice)| {
                    for (n, value) in slice.iter_mut().enumerate() {
                        let c = [
                            lo[0] + (n % dims[0]) as i32,
                            lo[1] + (n / dims[0]) as i32,
                            lo[2] + k as i32,
                        ];
                        *value = f(frame.corner_position(c));
                    }
                });
        }
        Ok(Self {
            frame,
            values: Values::Box { lo, dims, values },
        })
    }

    /// Θ from values stored near a surface and, elsewhere, the inside/outside classification of
    /// `windings` (inside where the winding along x is at least 1), with magnitude `far`. The
    /// stored values must have the windings' sign (a zero counts by its sign bit, so `-0.0` is
    /// inside).
    pub(crate) fn from_band(
        frame: GridFrame,
        near: FxHashMap<Corner, f32>,
        windings: Windings,
        far: f32,
    ) -> Self {
        let near = near
            .into_iter()
            .map(|(c, v)| {
                let v = match v {
                    0.0 if v.is_sign_negative() => -f32::MIN_POSITIVE,
                    0.0 => f32::MIN_POSITIVE,
                    v => v,
                };
                (c, v)
            })
            .collect();
        let balanced = windings.unbalanced_lines().is_empty();
        Self {
            frame,
            values: Values::Band {
                near,
                windings,
                far: far.abs(),
                balanced,
            },
        }
    }

    pub fn frame(&self) -> &GridFrame {
        &self.frame
    }

    /// Θ at a grid corner.
    pub fn value(&self, corner: Corner) -> f32 {
        match &self.values {
            Values::Box { lo, dims, values } => {
                let mut index = 0usize;
                for a in (0..3).rev() {
                    let x = i64::from(corner[a]) - i64::from(lo[a]);
                    if x < 0 || x >= dims[a] as i64 {
                        return self.frame.spacing();
                    }
                    index = index * dims[a] + x as usize;
                }
                values[index]
            }
            Values::Band {
                near,
                windings,
                far,
                ..
            } => match near.get(&corner) {
                Some(&v) => v,
                None if windings.winding(0, corner) >= 1 => -far,
                None => *far,
            },
        }
    }

    /// Whether a corner is inside (`value < 0`; zero and NaN are outside, as in marching cubes).
    pub fn inside(&self, corner: Corner) -> bool {
        self.value(corner) < 0.0
    }

    /// Where along a grid edge whose ends differ in sign the zero set crosses it, by linear
    /// interpolation, clamped to `[T_MIN, 1 − T_MIN]` like marching cubes.
    pub(crate) fn crossing(&self, edge: GridEdge) -> f32 {
        let [a, b] = edge.ends().map(|c| self.value(c));
        let t = a / (a - b);
        let t = if t.is_finite() { t } else { 0.5 };
        t.clamp(T_MIN, 1.0 - T_MIN)
    }

    /// The eight corner values of a cell, in cube corner order.
    pub(crate) fn cell_values(&self, cell: Cell) -> [f32; 8] {
        std::array::from_fn(|c| self.value(cell_corner(cell, c)))
    }

    /// Bit `c` set when corner `c` of `cell` is inside.
    pub(crate) fn config(&self, cell: Cell) -> u8 {
        (0..8).fold(0u8, |m, c| m | (u8::from(self.inside(cell_corner(cell, c))) << c))
    }

    /// Every cell whose corners are not all on one side, sorted.
    pub(crate) fn surface_cells(&self) -> Vec<Cell> {
        let mut cells: Vec<Cell> = match &self.values {
            Values::Box { lo, dims, .. } => {
                if dims.contains(&0) {
                    return Vec::new();
                }
                // Cells from one before the box to its last corner: the box's border cells meet the
                // outside beyond it.
                let n: [i32; 3] = std::array::from_fn(|a| dims[a] as i32 + 1);
                (0..n[2])
                    .into_par_iter()
                    .flat_map_iter(|k| {
                        let mut slab = Vec::new();
                        for j in 0..n[1] {
                            for i in 0..n[0] {
                                let cell = [lo[0] - 1 + i, lo[1] - 1 + j, lo[2] - 1 + k];
                                let config = self.config(cell);
                                if config != 0 && config != 255 {
                                    slab.push(cell);
                                }
                            }
                        }
                        slab
                    })
                    .collect()
            }
            Values::Band {
                windings,
                balanced: true,
                ..
            } => {
                // Θ's sign is the windings' (see `from_band`): it flips exactly where a winding run
                // crosses 1, on the grid edge ending at the run's first corner.
                (0..windings.index().len())
                    .into_par_iter()
                    .with_min_len(64)
                    .flat_map_iter(|l| {
                        let line = windings.index().lines()[l];
                        let mut before = 0;
                        let mut cells = Vec::new();
                        for run in windings.of_line(l) {
                            if (before >= 1) != (run.winding >= 1) {
                                let edge = GridEdge::new(line.corner(run.start - 1), line.axis);
                                cells.extend(edge.cells());
                            }
                            before = run.winding;
                        }
                        cells
                    })
                    .collect()
            }
            Values::Band { near, .. } => {
                let mut candidates: Vec<Cell> = near.keys().flat_map(|&c| corner_cells(c)).collect();
                candidates.par_sort_unstable();
                candidates.dedup();
                candidates
            }
        };
        cells.par_sort_unstable();
        cells.dedup();
        cells.retain(|&cell| {
            let config = self.config(cell);
            config != 0 && config != 255
        });
        cells
    }

    /// Θ by trilinear interpolation at grid coordinates `g` inside `cell` (`0 ≤ g − cell ≤ 1`), and
    /// its gradient in grid units.
    pub(crate) fn trilinear(values: &[f32; 8], local: [f64; 3]) -> (f64, [f64; 3]) {
        let mut value = 0.0;
        let mut gradient = [0.0; 3];
        for (c, &v) in values.iter().enumerate() {
            let v = f64::from(v);
            let o = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
            let w: [f64; 3] = std::array::from_fn(|a| if o[a] == 1 { local[a] } else { 1.0 - local[a] });
            let dw: [f64; 3] = std::array::from_fn(|a| if o[a] == 1 { 1.0 } else { -1.0 });
            value += v * w[0] * w[1] * w[2];
            gradient[0] += v * dw[0] * w[1] * w[2];
            gradient[1] += v * w[0] * dw[1] * w[2];
            gradient[2] += v * w[0] * w[1] * dw[2];
        }
        (value, gradient)
    }
}
