//! Θ, the voxelized implicit surface a mesh's topology is constrained to (paper §4.3): a value at
//! every corner of the topology grid, negative inside, whose zero set is extracted with the grid's
//! marching-cubes rule.
//!
//! Θ is defined at every corner of the unbounded grid. A sampled box is outside beyond its border; a
//! narrow band around a mesh takes the mesh's inside/outside classification (its sweep windings)
//! beyond the band, so `Φ(M)` and `Φ(T)` need memory for the band only. Either way Θ also keeps,
//! line by line, where its sign flips: the classification compares those flips with the mesh's
//! crossings one grid line at a time, without a lookup per corner.

use glam::Vec3;
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

use super::TopologyError;
use super::keys::{Cell, Corner, GridEdge, cell_corner, step};
use crate::grid::{GridCrossing, GridFrame, GridLine, T_MIN, Windings, sample_box};

/// A voxelized implicit surface on a grid: `value(corner) < 0` inside.
#[derive(Debug, Clone)]
pub struct Field {
    frame: GridFrame,
    values: Values,
    signs: SignLines,
    /// The grid edges that the mesh Θ was sampled from crosses more than once: sheets, strands
    /// and gaps thinner than a cell, which Θ's values cannot hold.
    sheets: FxHashSet<GridEdge>,
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
    Band {
        near: FxHashMap<Corner, f32>,
        windings: Windings,
        far: f32,
    },
}

/// Where Θ's sign flips along the grid lines that have a flip: on line `lines[l]`, the corners
/// `flips[starts[l]..starts[l + 1]]` (increasing) are each the first corner past a flip; every line
/// starts outside.
#[derive(Debug, Clone, Default)]
pub(crate) struct SignLines {
    lines: Vec<GridLine>,
    starts: Vec<u32>,
    flips: Vec<i32>,
}

impl SignLines {
    /// From every grid edge whose ends differ in sign, in any order.
    fn from_edges(mut edges: Vec<GridEdge>) -> Self {
        let key = |e: &GridEdge| (GridLine::through(e.axis(), e.corner), e.corner[e.axis()]);
        edges.par_sort_unstable_by_key(key);
        edges.dedup();
        let mut out = SignLines::default();
        for e in &edges {
            let (line, along) = key(e);
            if out.lines.last() != Some(&line) {
                out.lines.push(line);
                out.starts.push(out.flips.len() as u32);
            }
            out.flips.push(along + 1);
        }
        out.starts.push(out.flips.len() as u32);
        out
    }

    /// From windings whose lines all return to 0: the sign flips where a run crosses 1.
    fn from_windings(windings: &Windings) -> Self {
        let per_line: Vec<(GridLine, Vec<i32>)> = (0..windings.index().len())
            .into_par_iter()
            .with_min_len(64)
            .map(|l| {
                let mut before = 0;
                let mut flips = Vec::new();
                for run in windings.of_line(l) {
                    if (before >= 1) != (run.winding >= 1) {
                        flips.push(run.start);
                    }
                    before = run.winding;
                }
                (windings.index().lines()[l], flips)
            })
            .collect();
        let mut out = SignLines::default();
        for (line, flips) in per_line {
            if flips.is_empty() {
                continue;
            }
            out.lines.push(line);
            out.starts.push(out.flips.len() as u32);
            out.flips.extend(flips);
        }
        out.starts.push(out.flips.len() as u32);
        out
    }

    pub fn lines(&self) -> &[GridLine] {
        &self.lines
    }

    /// Flips of line number `l`.
    pub fn of_line(&self, l: usize) -> &[i32] {
        &self.flips[self.starts[l] as usize..self.starts[l + 1] as usize]
    }

    /// Every grid edge whose ends differ in sign.
    pub fn edges(&self) -> impl Iterator<Item = GridEdge> + '_ {
        (0..self.lines.len()).flat_map(move |l| {
            let line = self.lines[l];
            self.of_line(l)
                .iter()
                .map(move |&f| GridEdge::new(line.corner(f - 1), line.axis))
        })
    }
}

/// Largest number of corners a sampled box may have.
const MAX_BOX_CORNERS: usize = 1 << 30;

impl Field {
    /// Θ sampled from `f` (world position to value) at every corner from `lo` to `hi` inclusive;
    /// corners outside that box are outside.
    pub fn from_fn<F>(
        frame: GridFrame,
        lo: [i32; 3],
        hi: [i32; 3],
        f: F,
    ) -> Result<Self, TopologyError>
    where
        F: Fn(Vec3) -> f32 + Sync,
    {
        let dims: [usize; 3] = std::array::from_fn(|a| (hi[a] - lo[a] + 1).max(0) as usize);
        let count = dims
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .filter(|&n| n <= MAX_BOX_CORNERS)
            .ok_or(TopologyError::FieldTooLarge { dims })?;
        let values = sample_box(dims, count, |corner| {
            f(frame.corner_position(std::array::from_fn(|a| lo[a] + corner[a] as i32)))
        });
        let mut field = Self {
            frame,
            values: Values::Box { lo, dims, values },
            signs: SignLines::default(),
            sheets: FxHashSet::default(),
        };
        if !dims.contains(&0) {
            // Every edge from one corner before the box to one past it: beyond the box is outside.
            let n: [i32; 3] = std::array::from_fn(|a| dims[a] as i32 + 2);
            let flips: Vec<GridEdge> = (0..n[2])
                .into_par_iter()
                .flat_map_iter(|k| {
                    let field = &field;
                    (0..n[1]).flat_map(move |j| {
                        (0..n[0]).flat_map(move |i| {
                            let c = [lo[0] - 1 + i, lo[1] - 1 + j, lo[2] - 1 + k];
                            let here = field.inside(c);
                            (0..3)
                                .filter(move |&a| field.inside(step(c, a, 1)) != here)
                                .map(move |a| GridEdge::new(c, a))
                        })
                    })
                })
                .collect();
            field.signs = SignLines::from_edges(flips);
        }
        Ok(field)
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
        let near: FxHashMap<Corner, f32> = near
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
        let mut field = Self {
            frame,
            values: Values::Band {
                near,
                windings,
                far: far.abs(),
            },
            signs: SignLines::default(),
            sheets: FxHashSet::default(),
        };
        let signs = match &field.values {
            // A closed mesh's three sweeps agree on every corner, so each line's own runs tell
            // where the sign flips along it.
            Values::Band { windings, .. } if balanced => SignLines::from_windings(windings),
            // Otherwise the sign is the x sweep's, and every flip lies next to a stored corner.
            Values::Band { near, .. } => {
                let corners: Vec<Corner> = near.keys().copied().collect();
                let field = &field;
                SignLines::from_edges(
                    corners
                        .par_iter()
                        .flat_map_iter(|&c| {
                            (0..3).flat_map(move |a| {
                                [GridEdge::new(step(c, a, -1), a), GridEdge::new(c, a)]
                                    .into_iter()
                                    .filter(|e| {
                                        let [p, q] = e.ends();
                                        field.inside(p) != field.inside(q)
                                    })
                            })
                        })
                        .collect(),
                )
            }
            Values::Box { .. } => SignLines::default(),
        };
        field.signs = signs;
        field
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
            } => match near.get(&corner) {
                Some(&v) => v,
                None if windings.winding(0, corner) >= 1 => -far,
                None => *far,
            },
        }
    }

    /// Θ that also remembers the grid edges its mesh crosses more than once (see
    /// [`Field::sheet_on`]); `crossings` are that mesh's crossings of the grid.
    pub(crate) fn with_sheets(mut self, crossings: &[GridCrossing]) -> Self {
        let mut counts: FxHashMap<GridEdge, u32> = FxHashMap::default();
        for c in crossings {
            *counts.entry(GridEdge::new(c.corner, c.axis())).or_insert(0) += 1;
        }
        self.sheets = counts
            .into_iter()
            .filter(|&(_, n)| n >= 2)
            .map(|(edge, _)| edge)
            .collect();
        self
    }

    /// Whether the mesh Θ was sampled from crosses `edge` more than once (false where Θ did not
    /// come from a mesh).
    pub(crate) fn sheet_on(&self, edge: &GridEdge) -> bool {
        self.sheets.contains(edge)
    }

    /// Whether a corner is inside (`value < 0`; zero and NaN are outside, as in marching cubes).
    pub fn inside(&self, corner: Corner) -> bool {
        self.value(corner) < 0.0
    }

    /// Where Θ's sign flips, line by line.
    pub(crate) fn signs(&self) -> &SignLines {
        &self.signs
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
        (0..8).fold(0u8, |m, c| {
            m | (u8::from(self.inside(cell_corner(cell, c))) << c)
        })
    }

    /// Every cell whose corners are not all on one side, with its corner configuration, row by row.
    ///
    /// Θ's sign at every corner is the parity of the x line's flips up to it, so the cells of one
    /// row (along x) are read from the flips of the four x lines through their corners: a cell is
    /// mixed where one of them flips inside it or where they are in different states, which is a
    /// walk over those flips, with no lookup per corner.
    pub(crate) fn surface(&self) -> Vec<(Cell, u8)> {
        let x_lines = self.signs.lines.partition_point(|l| l.axis == 0);
        let mut rows: Vec<[i32; 2]> = self.signs.lines[..x_lines]
            .iter()
            .flat_map(|l| {
                let [y, z] = l.at;
                [[z - 1, y - 1], [z - 1, y], [z, y - 1], [z, y]]
            })
            .collect();
        rows.par_sort_unstable();
        rows.dedup();
        rows.par_iter()
            .with_min_len(64)
            .flat_map_iter(|&[z, y]| self.row_cells(y, z))
            .collect()
    }

    /// The mixed cells `(i, y, z)` of one row, in order of `i`.
    fn row_cells(&self, y: i32, z: i32) -> Vec<(Cell, u8)> {
        let flips = |dy: i32, dz: i32| -> &[i32] {
            let line = GridLine {
                axis: 0,
                at: [y + dy, z + dz],
            };
            match self.signs.lines.binary_search(&line) {
                Ok(l) => self.signs.of_line(l),
                Err(_) => &[],
            }
        };
        // Corner offsets (dy, dz) of the four lines, in cube corner order (bit 1 is y, bit 2 z).
        let lines = [flips(0, 0), flips(1, 0), flips(0, 1), flips(1, 1)];
        let inside = |line: &[i32], i: i32| line.partition_point(|&f| f <= i) % 2 == 1;
        let mut events: Vec<i32> = lines.iter().flat_map(|l| l.iter().copied()).collect();
        events.sort_unstable();
        events.dedup();
        let mut candidates: Vec<i32> = events.iter().map(|&e| e - 1).collect();
        for pair in events.windows(2) {
            let states = lines.map(|l| inside(l, pair[0]));
            if states.iter().any(|&s| s != states[0]) {
                candidates.extend(pair[0]..pair[1] - 1);
            }
        }
        candidates.sort_unstable();
        candidates.dedup();
        candidates
            .into_iter()
            .filter_map(|i| {
                let config = (0..8).fold(0u8, |m, c| {
                    let line = lines[c >> 1];
                    m | (u8::from(inside(line, i + (c & 1) as i32)) << c)
                });
                (config != 0 && config != 255).then_some(([i, y, z], config))
            })
            .collect()
    }

    /// Θ by trilinear interpolation at `local` coordinates inside a cell with corner values
    /// `values`, and its gradient in grid units.
    pub(crate) fn trilinear(values: &[f32; 8], local: [f64; 3]) -> (f64, [f64; 3]) {
        let mut value = 0.0;
        let mut gradient = [0.0; 3];
        for (c, &v) in values.iter().enumerate() {
            let v = f64::from(v);
            let o = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
            let w: [f64; 3] =
                std::array::from_fn(|a| if o[a] == 1 { local[a] } else { 1.0 - local[a] });
            let dw: [f64; 3] = std::array::from_fn(|a| if o[a] == 1 { 1.0 } else { -1.0 });
            value += v * w[0] * w[1] * w[2];
            gradient[0] += v * dw[0] * w[1] * w[2];
            gradient[1] += v * w[0] * dw[1] * w[2];
            gradient[2] += v * w[0] * w[1] * dw[2];
        }
        (value, gradient)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(field: &Field, lo: i32, hi: i32) -> Vec<(Cell, u8)> {
        let mut out = Vec::new();
        for z in lo..=hi {
            for y in lo..=hi {
                for x in lo..=hi {
                    let config = field.config([x, y, z]);
                    if config != 0 && config != 255 {
                        out.push(([x, y, z], config));
                    }
                }
            }
        }
        out.sort_unstable();
        out
    }

    #[test]
    fn sign_lines_find_every_mixed_cell() {
        let frame = GridFrame::new(Vec3::new(0.3, -0.2, 0.1), 0.5).unwrap();
        // Two blobs, one of them touching the box border, and a checkerboard patch.
        let field = Field::from_fn(frame, [-6; 3], [6; 3], |p| {
            let blobs = ((p - Vec3::new(1.0, 0.5, 0.0)).length() - 1.3)
                .min((p - Vec3::new(-2.5, -2.0, 1.0)).length() - 1.2);
            let g = (p - frame.origin()) / frame.spacing();
            if g.x > 2.5 && g.y > 2.5 && g.z > 2.5 {
                if (g.x.round() + g.y.round() + g.z.round()) as i32 % 2 == 0 {
                    -1.0
                } else {
                    1.0
                }
            } else {
                blobs
            }
        })
        .unwrap();
        let mut fast = field.surface();
        fast.sort_unstable();
        assert_eq!(fast, brute_force(&field, -9, 9));
        let flips: Vec<GridEdge> = field.signs().edges().collect();
        for e in &flips {
            let [a, b] = e.ends();
            assert_ne!(field.inside(a), field.inside(b));
        }
        let mut count = 0;
        for z in -8..=8 {
            for y in -8..=8 {
                for x in -8..=8 {
                    for a in 0..3 {
                        let c = [x, y, z];
                        count += usize::from(field.inside(c) != field.inside(step(c, a, 1)));
                    }
                }
            }
        }
        assert_eq!(flips.len(), count);
    }

    #[test]
    fn trilinear_matches_corners_and_gradient() {
        let values = [-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0];
        let (v, g) = Field::trilinear(&values, [0.25, 0.7, 0.1]);
        assert!((v - (-0.5)).abs() < 1e-12);
        assert!((g[0] - 2.0).abs() < 1e-12 && g[1].abs() < 1e-12 && g[2].abs() < 1e-12);
    }
}
