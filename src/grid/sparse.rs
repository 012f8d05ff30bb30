//! Sparse storage keyed by grid line: memory follows the surface area, never the box volume.
//!
//! Only lines that carry at least one crossing are stored, sorted, each owning a contiguous range of
//! a per-line array (crossings, winding runs). A line without crossings is empty space and needs no
//! entry: its corners are all outside. A 1000³ box holding a thin sheet stores the sheet's lines,
//! not 10⁹ corners.

use std::cmp::Ordering;
use std::ops::Range;

use rayon::prelude::*;

use super::predicates::cross_axes;
use crate::kernels::shared::GridCrossing;

/// Where each row of a concatenation of rows with `counts` items starts, and where the last one
/// ends: the prefix sums of `counts` from 0 (compressed rows).
pub(crate) fn row_starts(counts: impl IntoIterator<Item = u32>) -> Vec<u32> {
    let mut n = 0u32;
    std::iter::once(0)
        .chain(counts.into_iter().map(|c| {
            n += c;
            n
        }))
        .collect()
}

/// `items` placed by slot (`slot(item) < slots` for each), each slot's in their order in `items`,
/// and where each slot's run starts ([`row_starts`] of the slots' counts): a counting sort, for
/// keys that number few slots per item.
pub(crate) fn by_slot<T: Copy>(
    items: &[T],
    slots: usize,
    slot: impl Fn(&T) -> usize,
) -> (Vec<T>, Vec<u32>) {
    let mut counts = vec![0u32; slots];
    for item in items {
        counts[slot(item)] += 1;
    }
    let starts = row_starts(counts);
    let mut next = starts.clone();
    let mut placed = items.to_vec();
    for item in items {
        let at = &mut next[slot(item)];
        placed[*at as usize] = *item;
        *at += 1;
    }
    (placed, starts)
}

/// The corners that differ only along `axis`: the line through cells `at` of the two other axes,
/// in [`cross_axes`] order (`(y, z)` for x lines, `(z, x)` for y lines, `(x, y)` for z lines).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GridLine {
    pub axis: usize,
    pub at: [i32; 2],
}

impl GridLine {
    /// The line along `axis` through `corner`.
    pub fn through(axis: usize, corner: [i32; 3]) -> Self {
        let (u, v) = cross_axes(axis);
        Self {
            axis,
            at: [corner[u], corner[v]],
        }
    }

    /// The corner of this line at index `along` on its own axis.
    pub fn corner(&self, along: i32) -> [i32; 3] {
        let (u, v) = cross_axes(self.axis);
        let mut c = [0; 3];
        c[self.axis] = along;
        c[u] = self.at[0];
        c[v] = self.at[1];
        c
    }
}

impl Ord for GridLine {
    /// By axis, then the second cross coordinate, then the first (for x lines: z, then y).
    fn cmp(&self, other: &Self) -> Ordering {
        (self.axis, self.at[1], self.at[0]).cmp(&(other.axis, other.at[1], other.at[0]))
    }
}

impl PartialOrd for GridLine {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Sorted lines, line `l` owning `starts[l]..starts[l + 1]` of a per-line array.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LineIndex {
    lines: Vec<GridLine>,
    starts: Vec<u32>,
}

impl LineIndex {
    /// Groups `keys` (already sorted) into lines.
    pub(crate) fn from_sorted(keys: impl Iterator<Item = GridLine>) -> Self {
        let mut lines: Vec<GridLine> = Vec::new();
        let mut starts = Vec::new();
        let mut n = 0u32;
        for key in keys {
            if lines.last() != Some(&key) {
                lines.push(key);
                starts.push(n);
            }
            n += 1;
        }
        starts.push(n);
        Self { lines, starts }
    }

    /// The same lines with new ranges: `counts[l]` items for line `l`.
    pub(crate) fn with_counts(&self, counts: impl Iterator<Item = u32>) -> Self {
        let starts = row_starts(counts);
        Self {
            lines: self.lines.clone(),
            starts,
        }
    }

    pub fn lines(&self) -> &[GridLine] {
        &self.lines
    }

    pub fn len(&self) -> usize {
        self.lines.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// First item of each line, then the total: `len() + 1` entries.
    pub fn starts(&self) -> &[u32] {
        &self.starts
    }

    /// Items of line number `l`.
    pub fn range(&self, l: usize) -> Range<usize> {
        self.starts[l] as usize..self.starts[l + 1] as usize
    }

    /// Position of `line` among the stored lines.
    pub fn find(&self, line: &GridLine) -> Option<usize> {
        self.lines.binary_search(line).ok()
    }
}

/// Every crossing of a mesh with the grid edges, grouped by grid line and sorted along it (by edge,
/// then by `t`, then by triangle), the output of rasterization.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Crossings {
    index: LineIndex,
    crossings: Vec<GridCrossing>,
}

impl Crossings {
    /// Sorts crossings into line order; the order is total, so the result does not depend on the
    /// order of `crossings` (which on the GPU depends on scheduling).
    pub(crate) fn from_unsorted(mut crossings: Vec<GridCrossing>) -> Self {
        crossings.par_sort_unstable_by(|a, b| {
            let (la, lb) = (line_of(a), line_of(b));
            la.cmp(&lb)
                .then(a.along().cmp(&b.along()))
                .then(a.t.total_cmp(&b.t))
                .then(a.triangle.cmp(&b.triangle))
        });
        let index = LineIndex::from_sorted(crossings.iter().map(line_of));
        Self { index, crossings }
    }

    pub fn index(&self) -> &LineIndex {
        &self.index
    }

    /// All crossings, line by line.
    pub fn all(&self) -> &[GridCrossing] {
        &self.crossings
    }

    pub fn len(&self) -> usize {
        self.crossings.len()
    }

    pub fn is_empty(&self) -> bool {
        self.crossings.is_empty()
    }

    /// Crossings of line number `l` (see [`LineIndex::lines`]), in order along it.
    pub fn of_line(&self, l: usize) -> &[GridCrossing] {
        &self.crossings[self.index.range(l)]
    }

    /// Crossings on `line`, in order along it; empty when the line misses the surface.
    pub fn on_line(&self, line: &GridLine) -> &[GridCrossing] {
        self.index.find(line).map_or(&[], |l| self.of_line(l))
    }

    /// Crossings on the grid edge from `corner` to `corner + unit(axis)`, in order of `t`.
    pub fn on_edge(&self, axis: usize, corner: [i32; 3]) -> &[GridCrossing] {
        let on_line = self.on_line(&GridLine::through(axis, corner));
        let along = corner[axis];
        let lo = on_line.partition_point(|c| c.along() < along);
        let hi = on_line.partition_point(|c| c.along() <= along);
        &on_line[lo..hi]
    }
}

/// The line a crossing lies on.
pub(crate) fn line_of(c: &GridCrossing) -> GridLine {
    GridLine::through(c.axis(), c.corner)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_placed_by_slot_keep_their_order_within_a_slot() {
        let items = [(2, 'a'), (0, 'b'), (2, 'c'), (3, 'd'), (0, 'e')];
        let (placed, starts) = by_slot(&items, 4, |&(s, _)| s);
        assert_eq!(placed, [(0, 'b'), (0, 'e'), (2, 'a'), (2, 'c'), (3, 'd')]);
        assert_eq!(starts, [0, 2, 2, 4, 5]);
        assert_eq!(
            by_slot(&[] as &[(usize, char)], 3, |&(s, _)| s).1,
            [0, 0, 0, 0]
        );
    }
}
