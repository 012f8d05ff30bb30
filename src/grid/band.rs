//! The corners that may lie within a narrow band of the surface, found without a dense array.
//!
//! Every point of the surface lies in a cell of its footprint, so a corner within `r` cells of the
//! surface lies within the footprint dilated by `floor(r)` cells in each direction (Chebyshev). The
//! footprint is kept as runs of cells along x, and the dilation is done axis by axis on the runs,
//! so the work and memory follow the band's volume, never the bounding box's.

use rayon::prelude::*;

/// Rows of corners along x: `(z, y)` keys in increasing order, each with disjoint, increasing,
/// inclusive runs `[first, last]` of x indices.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Rows {
    pub keys: Vec<[i32; 2]>,
    pub starts: Vec<u32>,
    pub runs: Vec<[i32; 2]>,
}

impl Rows {
    /// Runs of row `r`.
    pub fn of(&self, r: usize) -> &[[i32; 2]] {
        &self.runs[self.starts[r] as usize..self.starts[r + 1] as usize]
    }

    fn from_lists(keys: Vec<[i32; 2]>, lists: Vec<Vec<[i32; 2]>>) -> Self {
        let mut starts = Vec::with_capacity(keys.len() + 1);
        let mut n = 0u32;
        starts.push(0);
        for l in &lists {
            n += l.len() as u32;
            starts.push(n);
        }
        Self {
            keys,
            starts,
            runs: lists.into_iter().flatten().collect(),
        }
    }
}

/// Corners within Chebyshev distance `reach` of the cells `cells` (sorted by `(z, y, x)`), that is
/// the corners of every cell dilated by `reach`.
pub(crate) fn dilated_corners(cells: &[[i32; 3]], reach: i32) -> Rows {
    // Cells → runs of corners along x, one row per (z, y) of cells.
    let mut keys: Vec<[i32; 2]> = Vec::new();
    let mut lists: Vec<Vec<[i32; 2]>> = Vec::new();
    for c in cells {
        let key = [c[2], c[1]];
        let run = [c[0] - reach, c[0] + 1 + reach];
        if keys.last() != Some(&key) {
            keys.push(key);
            lists.push(vec![run]);
        } else if let Some(list) = lists.last_mut() {
            push_run(list, run);
        }
    }
    let rows = Rows::from_lists(keys, lists);
    let rows = dilate_inner(&rows, reach);
    transpose(&dilate_inner(&transpose(&rows), reach))
}

/// Appends `run` to increasing disjoint runs, merging it with the last when they touch.
fn push_run(list: &mut Vec<[i32; 2]>, run: [i32; 2]) {
    match list.last_mut() {
        Some(last) if run[0] <= last[1] + 1 => last[1] = last[1].max(run[1]),
        _ => list.push(run),
    }
}

/// Row keys of one group of rows, in order.
type RowKeys = Vec<[i32; 2]>;

/// The runs of each row of one group of rows.
type RowRuns = Vec<Vec<[i32; 2]>>;

/// Each row `(a, b)` of cells spreads to the corner rows `(a, b - reach ..= b + 1 + reach)`.
fn dilate_inner(rows: &Rows, reach: i32) -> Rows {
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
            let mut gathered: Vec<[i32; 2]> = Vec::new();
            for b in targets {
                let lo = inner.partition_point(|&x| x < b - 1 - reach);
                let hi = inner.partition_point(|&x| x <= b + reach);
                gathered.clear();
                for r in first + lo..first + hi {
                    gathered.extend_from_slice(rows.of(r));
                }
                gathered.sort_unstable();
                let mut list = Vec::new();
                for &run in &gathered {
                    push_run(&mut list, run);
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
    Rows::from_lists(keys, lists)
}

/// The same rows keyed `(y, z)` instead of `(z, y)`, sorted.
fn transpose(rows: &Rows) -> Rows {
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
    Rows::from_lists(keys, lists)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    fn brute(cells: &[[i32; 3]], reach: i32) -> BTreeSet<[i32; 3]> {
        let mut out = BTreeSet::new();
        for c in cells {
            for k in c[2] - reach..=c[2] + 1 + reach {
                for j in c[1] - reach..=c[1] + 1 + reach {
                    for i in c[0] - reach..=c[0] + 1 + reach {
                        out.insert([k, j, i]);
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
        for reach in [0, 1, 3] {
            let rows = dilated_corners(&cells, reach);
            let mut got = BTreeSet::new();
            for (r, key) in rows.keys.iter().enumerate() {
                for run in rows.of(r) {
                    assert!(run[0] <= run[1]);
                    for i in run[0]..=run[1] {
                        assert!(got.insert([key[0], key[1], i]), "corner listed twice");
                    }
                }
            }
            assert_eq!(got, brute(&cells, reach), "reach {reach}");
            assert!(rows.keys.windows(2).all(|w| w[0] < w[1]));
        }
    }
}
