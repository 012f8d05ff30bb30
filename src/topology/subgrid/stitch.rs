//! The least-cost way to stitch two loops together (optimal contour stitching), for the graft's
//! strips ([`super::graft`], step 3).
//!
//! A strip between loops of `n` and `m` edges is a monotone path through an `(n + 1) × (m + 1)`
//! table from its first corner to its last: each step advances along one loop, adding the
//! triangle spanned by that loop's edge and the other loop's current vertex. Filling the whole
//! table costs `n · m` triangle evaluations, and on fluid frames the loops of a graft's rim run to
//! hundreds of vertices. Most of the table cannot lie on the least-cost path, though: every step
//! costs at least nothing, so a cell whose least cost already exceeds that of some whole path is
//! off it. So the table is filled twice, only where that can matter: first near its diagonal (the
//! least-cost path that stays within [`BAND`] columns of it), then wherever cells come within
//! that path's cost, about a third of the table on the dam break's grafts. Every cell of the
//! second pass holds what the whole table holds there, so the path is the one the whole table
//! gives, ties included. Where the strip must fold, though, that bound is mostly folds that
//! every path pays, and the second pass reaches nearly every cell: large tables
//! ([`PARALLEL_CELLS`]) have all their step costs computed first, on every core, and the passes
//! read them.

use rayon::prelude::*;

/// Columns either side of the table's diagonal that the first, bounding pass fills.
const BAND: usize = 32;

/// Tables of at least this many cells have every step's cost computed first, on all cores. The
/// second fill reaches nearly every cell where the strip must fold (the bound of the band's path
/// is then mostly folds, which any path pays): on the dam break's main body, rim loops of 750–980
/// vertices, 65–125 ms each on one core.
const PARALLEL_CELLS: usize = 1 << 16;

/// The steps of the least-cost path from corner `(0, 0)` to `(n, m)`, in order: `true` advances
/// `i` at cost `down(i, j)`, `false` advances `j` at cost `across(i, j)`. Costs must not be
/// negative. Where both ways into a cell cost the same, the path comes down into it.
pub(super) fn least_cost_steps(
    n: usize,
    m: usize,
    down: impl Fn(usize, usize) -> f32 + Sync,
    across: impl Fn(usize, usize) -> f32 + Sync,
) -> Vec<bool> {
    if (n + 1) * (m + 1) < PARALLEL_CELLS {
        return bounded_steps(n, m, down, across);
    }
    // Each cost is the same number however it is computed, so the path is too.
    let (down_costs, across_costs) =
        rayon::join(|| costs(n, m + 1, &down), || costs(n + 1, m, &across));
    bounded_steps(
        n,
        m,
        |i, j| down_costs[i * (m + 1) + j],
        |i, j| across_costs[i * m + j],
    )
}

/// `cost(i, j)` for every cell of a `rows × columns` table, row-major, computed in parallel.
fn costs(rows: usize, columns: usize, cost: &(impl Fn(usize, usize) -> f32 + Sync)) -> Vec<f32> {
    (0..rows * columns)
        .into_par_iter()
        .with_min_len(4096)
        .map(|k| cost(k / columns, k % columns))
        .collect()
}

/// [`least_cost_steps`], each cost computed where the fills ask for it.
fn bounded_steps(
    n: usize,
    m: usize,
    down: impl Fn(usize, usize) -> f32,
    across: impl Fn(usize, usize) -> f32,
) -> Vec<bool> {
    // The least-cost path near the diagonal bounds the least-cost one: its cost is summed step by
    // step as the whole table sums it, and adding a cost that is at least zero never lowers a
    // sum, rounding included, so no cell of the least-cost path costs more.
    let band = (n > 0 && m <= BAND * n).then_some(BAND);
    let (_, banded) = fill((n, m), (&down, &across), f32::INFINITY, band);
    let (from_down, _) = fill((n, m), (&down, &across), banded, None);
    walk_back((n, m), &from_down)
}

/// The steps of the path that ends at corner `(n, m)` and enters each cell as `from_down` says,
/// in order from `(0, 0)`.
fn walk_back((n, m): (usize, usize), from_down: &[bool]) -> Vec<bool> {
    let (mut i, mut j) = (n, m);
    let mut steps = Vec::with_capacity(n + m);
    while i > 0 || j > 0 {
        let step = from_down[i * (m + 1) + j];
        if step {
            i -= 1;
        } else {
            j -= 1;
        }
        steps.push(step);
    }
    steps.reverse();
    steps
}

/// The table's cells that cost at most `bound` (and, given a half-width `band`, lie within that
/// many columns of its diagonal), row by row: from the first such cell of the row above, and on
/// past its last one only while cells stay within the bound. A cell beyond the bound counts as
/// unreachable; a cell within it has its cheaper way in within it too, so it is filled exactly as
/// the whole table fills it. Returns, per cell, whether its least-cost way in comes down, and the
/// cost of the whole path (infinite where no path stays within the bound).
fn fill(
    (n, m): (usize, usize),
    (down, across): (&impl Fn(usize, usize) -> f32, &impl Fn(usize, usize) -> f32),
    bound: f32,
    band: Option<usize>,
) -> (Vec<bool>, f32) {
    let width = m + 1;
    let mut from_down = vec![false; (n + 1) * width];
    let mut above = vec![f32::INFINITY; width];
    let mut row = vec![f32::INFINITY; width];
    // The first and last cell of the row above within the bound.
    let mut live = (0, 0);
    for i in 0..=n {
        let (first, last) = band.map_or((0, m), |w| {
            let diagonal = i * m / n;
            (diagonal.saturating_sub(w), (diagonal + w).min(m))
        });
        let start = live.0.max(first);
        let mut within: Option<(usize, usize)> = None;
        for j in start..=last {
            let here = i * width + j;
            let mut best = if i == 0 && j == 0 { 0.0 } else { f32::INFINITY };
            if i > 0 && j <= live.1 && above[j] <= bound {
                let c = above[j] + down(i - 1, j);
                if c < best {
                    best = c;
                    from_down[here] = true;
                }
            }
            if j > start && row[j - 1] <= bound {
                let c = row[j - 1] + across(i, j - 1);
                if c < best {
                    best = c;
                    from_down[here] = false;
                }
            }
            if best <= bound {
                row[j] = best;
                within = Some((within.map_or(j, |(first, _)| first), j));
            } else {
                row[j] = f32::INFINITY;
                if i == 0 || j > live.1 {
                    break;
                }
            }
        }
        let Some(cells) = within else {
            return (from_down, f32::INFINITY);
        };
        live = cells;
        std::mem::swap(&mut above, &mut row);
    }
    let cost = if live.1 == m { above[m] } else { f32::INFINITY };
    (from_down, cost)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The path of the whole table, filled without bounds: the reference.
    fn whole_table(
        n: usize,
        m: usize,
        down: impl Fn(usize, usize) -> f32,
        across: impl Fn(usize, usize) -> f32,
    ) -> Vec<bool> {
        let (from_down, _) = fill((n, m), (&down, &across), f32::INFINITY, None);
        walk_back((n, m), &from_down)
    }

    /// A deterministic pseudo-random cost in `levels` (many ties, zero steps, fold-sized jumps).
    fn cost(seed: u64, i: usize, j: usize, levels: &[f32]) -> f32 {
        let mut x = seed ^ ((i as u64) << 32) ^ (j as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        x ^= x >> 33;
        x = x.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
        x ^= x >> 33;
        levels[(x % levels.len() as u64) as usize]
    }

    /// On tables of many shapes (square, long and thin either way, one row) and costs with ties,
    /// zeros and large jumps, the bounded fill takes the whole table's path, step for step.
    #[test]
    fn the_bounded_fill_takes_the_whole_tables_path() {
        let levels = [0.0, 0.25, 0.25, 0.5, 1.0, 100.0, 100.25];
        let shapes = [
            (1, 1),
            (1, 40),
            (40, 1),
            (3, 200),
            (70, 70),
            (150, 90),
            (90, 150),
            (400, 380),
        ];
        for (s, &(n, m)) in shapes.iter().enumerate() {
            for seed in 0..6u64 {
                let down = |i: usize, j: usize| cost(seed * 31 + s as u64, i, j, &levels);
                let across = |i: usize, j: usize| cost(seed * 37 + s as u64 + 7, i, j, &levels);
                let steps = least_cost_steps(n, m, down, across);
                assert_eq!(steps.iter().filter(|&&d| d).count(), n);
                assert_eq!(steps.len(), n + m);
                assert_eq!(
                    steps,
                    whole_table(n, m, down, across),
                    "{n}×{m}, seed {seed}"
                );
            }
        }
    }

    /// Where the cheap steps lie far off the diagonal, the bound of the diagonal's path still
    /// admits the path that leaves it.
    #[test]
    fn a_path_far_from_the_diagonal_is_found() {
        let (n, m) = (300, 300);
        // Cheap only along the first row and the last column: the least-cost path runs across
        // first, then down, as far from the diagonal as a path can be.
        let down = |_: usize, j: usize| if j == m { 0.0 } else { 1.0 };
        let across = |i: usize, _: usize| if i == 0 { 0.0 } else { 1.0 };
        let steps = least_cost_steps(n, m, down, across);
        let expected: Vec<bool> = (0..m).map(|_| false).chain((0..n).map(|_| true)).collect();
        assert_eq!(steps, expected);
    }
}
