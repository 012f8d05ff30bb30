//! The corners that may lie within a narrow band of the surface, found without a dense array.
//!
//! Every point of the surface lies in a cell of its footprint, so a corner within `r` cells of the
//! surface lies within `r` of a footprint cell: its per-axis gaps to that cell's box (whole
//! numbers of cells) have squares summing to at most `r²`. That Euclidean test leaves about a
//! quarter fewer candidates than dilating by `floor(r)` cells in every direction, whose diagonal
//! reach is `√3 r`, and every candidate costs the distance search. The footprint is kept as runs
//! of cells along x and spread axis by axis on the runs, each run carrying the squared gap it has
//! used so far, so the work and memory follow the band's volume, never the bounding box's.

use rayon::prelude::*;

use super::sparse::row_starts;

/// Rows along x: `(z, y)` keys in increasing order, each with its runs in `runs[starts[r]..]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct RowSet<R> {
    pub keys: Vec<[i32; 2]>,
    pub starts: Vec<u32>,
    pub runs: Vec<R>,
}

/// Rows of corners along x, with disjoint, increasing, inclusive runs `[first, last]` of x indices.
pub(crate) type Rows = RowSet<[i32; 2]>;

impl<R: Clone> RowSet<R> {
    /// Runs of row `r`.
    pub fn of(&self, r: usize) -> &[R] {
        &self.runs[self.starts[r] as usize..self.starts[r + 1] as usize]
    }

    fn from_lists(keys: Vec<[i32; 2]>, lists: Vec<Vec<R>>) -> Self {
        let starts = row_starts(lists.iter().map(|l| l.len() as u32));
        Self {
            keys,
            starts,
            runs: lists.into_iter().flatten().collect(),
        }
    }
}

/// Cells `first..=last` of one row that lie `gap` (squared, summed over the axes spread so far)
/// from the target row. Ordered by gap first, so runs that may merge are adjacent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Spread {
    gap: u32,
    first: i32,
    last: i32,
}

/// Corners within Euclidean distance `radius` (in cells) of the cells `cells` (sorted by
/// `(z, y, x)`): those whose gaps to some cell's box along the three axes have squares summing to
/// at most `radius²`.
pub(crate) fn dilated_corners(cells: &[[i32; 3]], radius: f32) -> Rows {
    let limit = (f64::from(radius) * f64::from(radius)).floor() as u32;
    let reach = root(limit) as i32;
    let mut keys: Vec<[i32; 2]> = Vec::new();
    let mut lists: Vec<Vec<Spread>> = Vec::new();
    for c in cells {
        let key = [c[2], c[1]];
        let run = Spread {
            gap: 0,
            first: c[0],
            last: c[0],
        };
        if keys.last() != Some(&key) {
            keys.push(key);
            lists.push(vec![run]);
        } else if let Some(list) = lists.last_mut() {
            push_spread(list, run);
        }
    }
    let rows = RowSet::from_lists(keys, lists);
    let rows = spread_inner(&rows, reach, limit);
    let rows = transpose(&spread_inner(&transpose(&rows), reach, limit));
    corners_along_x(&rows, limit)
}

/// The largest `k` with `k² ≤ n`.
fn root(n: u32) -> u32 {
    let mut k = f64::from(n).sqrt() as u32;
    while k * k > n {
        k -= 1;
    }
    while (k + 1) * (k + 1) <= n {
        k += 1;
    }
    k
}

/// Gap between corner index `corner` and the cell `cell`, which spans `cell..=cell + 1`.
fn gap(corner: i32, cell: i32) -> u32 {
    if corner < cell {
        (cell - corner) as u32
    } else if corner > cell + 1 {
        (corner - cell - 1) as u32
    } else {
        0
    }
}

/// Appends `run` to runs sorted by `(gap, first)`, merging it with the last when they share a gap
/// and touch.
fn push_spread(list: &mut Vec<Spread>, run: Spread) {
    match list.last_mut() {
        Some(last) if last.gap == run.gap && run.first <= last.last + 1 => {
            last.last = last.last.max(run.last);
        }
        _ => list.push(run),
    }
}

/// Row keys of one group of rows, in order.
type RowKeys = Vec<[i32; 2]>;

/// The runs of each row of one group of rows.
type RowRuns = Vec<Vec<Spread>>;

/// Each row `(a, b)` spreads to the rows `(a, b - reach ..= b + 1 + reach)`, each run adding the
/// square of its gap along the inner axis and kept while the sum is at most `limit`.
fn spread_inner(rows: &RowSet<Spread>, reach: i32, limit: u32) -> RowSet<Spread> {
    // Rows sharing the outer key form a group; groups are independent.
    let mut groups: Vec<(usize, usize)> = Vec::new();
    for (r, key) in rows.keys.iter().enumerate() {
        match groups.last_mut() {
            Some(g) if rows.keys[g.0][0] == key[0] => g.1 = r + 1,
            _ => groups.push((r, r + 1)),
        }
    }
    let per_group: Vec<(RowKeys, RowRuns)> = groups
        .par_iter()
        .map(|&(first, end)| {
            let outer = rows.keys[first][0];
            let inner: Vec<i32> = rows.keys[first..end].iter().map(|k| k[1]).collect();
            let mut targets: Vec<i32> = inner
                .iter()
                .flat_map(|&b| b - reach..=b + 1 + reach)
                .collect();
            targets.sort_unstable();
            targets.dedup();
            let mut keys = Vec::with_capacity(targets.len());
            let mut lists = Vec::with_capacity(targets.len());
            let mut gathered: Vec<Spread> = Vec::new();
            for b in targets {
                let lo = inner.partition_point(|&x| x < b - 1 - reach);
                let hi = inner.partition_point(|&x| x <= b + reach);
                gathered.clear();
                for r in first + lo..first + hi {
                    let g = gap(b, rows.keys[r][1]);
                    gathered.extend(rows.of(r).iter().filter_map(|s| {
                        let gap = s.gap + g * g;
                        (gap <= limit).then_some(Spread { gap, ..*s })
                    }));
                }
                if gathered.is_empty() {
                    continue;
                }
                gathered.sort_unstable();
                let mut list = Vec::new();
                for &run in &gathered {
                    push_spread(&mut list, run);
                }
                keys.push([outer, b]);
                lists.push(list);
            }
            (keys, lists)
        })
        .collect();
    let mut keys = Vec::new();
    let mut lists = Vec::new();
    for (k, l) in per_group {
        keys.extend(k);
        lists.extend(l);
    }
    RowSet::from_lists(keys, lists)
}

/// Each run of cells, with the squared gap it has used across y and z, widened to the corners
/// whose gap along x keeps the sum within `limit`; the runs of each row merged.
fn corners_along_x(rows: &RowSet<Spread>, limit: u32) -> Rows {
    let lists: Vec<Vec<[i32; 2]>> = (0..rows.keys.len())
        .into_par_iter()
        .with_min_len(64)
        .map(|r| {
            let mut widened: Vec<[i32; 2]> = rows
                .of(r)
                .iter()
                .map(|s| {
                    let reach = root(limit - s.gap) as i32;
                    [s.first - reach, s.last + 1 + reach]
                })
                .collect();
            widened.sort_unstable();
            let mut list: Vec<[i32; 2]> = Vec::with_capacity(widened.len());
            for run in widened {
                match list.last_mut() {
                    Some(last) if run[0] <= last[1] + 1 => last[1] = last[1].max(run[1]),
                    _ => list.push(run),
                }
            }
            list
        })
        .collect();
    RowSet::from_lists(rows.keys.clone(), lists)
}

/// The same rows keyed `(y, z)` instead of `(z, y)`, sorted.
fn transpose<R: Clone + Send + Sync>(rows: &RowSet<R>) -> RowSet<R> {
    let mut order: Vec<u32> = (0..rows.keys.len() as u32).collect();
    order.par_sort_unstable_by_key(|&r| {
        let k = rows.keys[r as usize];
        (k[1], k[0])
    });
    let keys = order
        .iter()
        .map(|&r| {
            let k = rows.keys[r as usize];
            [k[1], k[0]]
        })
        .collect();
    let lists = order
        .iter()
        .map(|&r| rows.of(r as usize).to_vec())
        .collect();
    RowSet::from_lists(keys, lists)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// Corners `(z, y, x)` within `radius` of some cell, by the definition.
    fn brute(cells: &[[i32; 3]], radius: f32) -> BTreeSet<[i32; 3]> {
        let reach = radius.floor() as i32;
        let mut out = BTreeSet::new();
        for c in cells {
            for k in c[2] - reach..=c[2] + 1 + reach {
                for j in c[1] - reach..=c[1] + 1 + reach {
                    for i in c[0] - reach..=c[0] + 1 + reach {
                        let d: [u32; 3] = [gap(i, c[0]), gap(j, c[1]), gap(k, c[2])];
                        let sum: u32 = d.iter().map(|g| g * g).sum();
                        if f64::from(sum) <= f64::from(radius) * f64::from(radius) {
                            out.insert([k, j, i]);
                        }
                    }
                }
            }
        }
        out
    }

    #[test]
    fn dilation_matches_brute_force() {
        let mut cells: Vec<[i32; 3]> = Vec::new();
        let mut x = 12345u64;
        for _ in 0..300 {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = |s: u32| ((x >> s) % 23) as i32 - 11;
            cells.push([r(10), r(20), r(30)]);
        }
        cells.sort_unstable_by_key(|c| [c[2], c[1], c[0]]);
        cells.dedup();
        for radius in [0.0, 0.5, 1.0, 1.5, 2.9, 3.0, 4.2] {
            let rows = dilated_corners(&cells, radius);
            let mut got = BTreeSet::new();
            for (r, key) in rows.keys.iter().enumerate() {
                for run in rows.of(r) {
                    assert!(run[0] <= run[1]);
                    for i in run[0]..=run[1] {
                        assert!(got.insert([key[0], key[1], i]), "corner listed twice");
                    }
                }
            }
            assert_eq!(got, brute(&cells, radius), "radius {radius}");
            assert!(rows.keys.windows(2).all(|w| w[0] < w[1]));
            assert!(
                (0..rows.keys.len()).all(|r| rows.of(r).windows(2).all(|w| w[0][1] + 1 < w[1][0]))
            );
        }
    }

    #[test]
    fn diagonal_reach_is_the_radius() {
        // The cell spans corners 0..=1 on each axis; the gaps below are to that box.
        let rows = dilated_corners(&[[0, 0, 0]], 3.0);
        let has = |c: [i32; 3]| {
            rows.keys
                .iter()
                .position(|&k| k == [c[2], c[1]])
                .is_some_and(|r| {
                    rows.of(r)
                        .iter()
                        .any(|run| run[0] <= c[0] && c[0] <= run[1])
                })
        };
        assert!(has([4, 1, 1]), "3 cells along x from the box");
        assert!(has([3, 3, 1]), "gaps 2, 2, 0: √8 ≤ 3");
        assert!(!has([3, 3, 3]), "gaps 2, 2, 2: √12 > 3");
        assert!(!has([4, 3, 0]), "gaps 3, 2, 0: √13 > 3");
    }
}
