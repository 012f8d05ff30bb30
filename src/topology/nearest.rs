//! The nearest surviving vertex of a point: the data source of vertices a topology change creates
//! or deletes with no patch boundary to average (a droplet appearing or vanishing whole, §4.4).

use glam::{IVec3, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use crate::grid::{CellBox, by_slot};

/// A uniform grid of buckets over the vertices that exist both before and after a topology
/// change.
pub(crate) struct Survivors {
    cell: f32,
    /// The points, sorted by bucket: each bucket's are a run of them. A query that searches
    /// beyond [`RINGS`] rings compares them all.
    points: Vec<(u32, Vec3)>,
    index: Index,
    /// The first and last bucket along each axis holding a point.
    bounds: (IVec3, IVec3),
}

/// Where each bucket's run of points lies. A query looks up dozens of buckets (a ring of `r`
/// holds about 24·r² of them), each a hash lookup in a sparse index; over a box of buckets few
/// enough to list, each is an array read instead (on the dam break's splash frames, queries of
/// the graft's seeds and of the transfer spent most of their time in those lookups).
enum Index {
    /// Where each bucket's run starts, for every bucket of the bounds' box (x fastest), and one
    /// past the last.
    Dense { cells: CellBox, starts: Vec<u32> },
    /// Each bucket holding points, and its run.
    Sparse(FxHashMap<IVec3, (u32, u32)>),
}

/// Boxes of at most this many buckets per point, plus [`DENSE_FLOOR`], are indexed densely: the
/// dam break's main body (17k vertices) spans about 180k buckets of one grid spacing.
const DENSE_PER_POINT: usize = 16;
const DENSE_FLOOR: usize = 4096;

/// Rings of buckets a query searches before it compares every point instead. Ring `r` holds
/// about 24·r² buckets, so a survivor many cells away (the vertices of a whole component
/// replaced at once, on a fluid frame of tens of thousands of vertices) cost hundreds of
/// thousands of bucket lookups per query; beyond this many rings one pass over the points is
/// cheaper, and gives the same answer.
const RINGS: i32 = 6;

impl Survivors {
    /// `points` are `(vertex, position)`; `cell` is the bucket size (the grid spacing Δ).
    pub(crate) fn new(points: impl IntoIterator<Item = (u32, Vec3)>, cell: f32) -> Self {
        let cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            1.0
        };
        let key = |p: Vec3| (p / cell).floor().as_ivec3();
        let mut points: Vec<(u32, Vec3)> =
            points.into_iter().filter(|(_, p)| p.is_finite()).collect();
        let bounds = points.iter().fold((IVec3::MAX, IVec3::MIN), |b, &(_, p)| {
            (b.0.min(key(p)), b.1.max(key(p)))
        });
        let most = DENSE_PER_POINT * points.len() + DENSE_FLOOR;
        let index = if let Some(cells) = CellBox::spanning(bounds.0, bounds.1, most) {
            let (sorted, starts) = by_slot(&points, cells.volume(), |&(_, p)| {
                cells.index(key(p)).unwrap_or_default()
            });
            points = sorted;
            Index::Dense { cells, starts }
        } else {
            let order = |p: Vec3| {
                let k = key(p);
                (k.z, k.y, k.x)
            };
            points.sort_by_key(|&(v, p)| (order(p), v));
            let mut runs: FxHashMap<IVec3, (u32, u32)> = FxHashMap::default();
            for (i, &(_, p)) in points.iter().enumerate() {
                runs.entry(key(p)).or_insert((i as u32, i as u32)).1 = i as u32 + 1;
            }
            Index::Sparse(runs)
        };
        Self {
            cell,
            points,
            index,
            bounds,
        }
    }

    /// Hands `visit` the points of every bucket at Chebyshev distance exactly `ring` from
    /// `centre`: along x, the whole row where y or z lies on the shell's side, only its two ends
    /// elsewhere. With the dense index a row's buckets are consecutive, and so are their points:
    /// one run a row.
    fn shell(&self, centre: IVec3, ring: i32, mut visit: impl FnMut(&[(u32, Vec3)])) {
        for z in -ring..=ring {
            for y in -ring..=ring {
                // Ring 0 is a single bucket, and on its side.
                let on_side = y.abs() == ring || z.abs() == ring;
                let at = |x: i32| centre + IVec3::new(x, y, z);
                match &self.index {
                    Index::Dense { cells, starts } if on_side => {
                        visit(self.dense_row((at(-ring), at(ring)), cells, starts));
                    }
                    _ => {
                        let step = if on_side { 1 } else { 2 * ring as usize };
                        for x in (-ring..=ring).step_by(step) {
                            visit(self.bucket(at(x)));
                        }
                    }
                }
            }
        }
    }

    /// The points of the buckets from `first` to `last` (one row along x) of the dense index.
    fn dense_row(
        &self,
        (first, last): (IVec3, IVec3),
        cells: &CellBox,
        starts: &[u32],
    ) -> &[(u32, Vec3)] {
        let first = IVec3::new(first.x.max(cells.low().x), first.y, first.z);
        let last = IVec3::new(last.x.min(cells.high().x), last.y, last.z);
        match (cells.index(first), cells.index(last)) {
            (Some(a), Some(b)) if first.x <= last.x => {
                &self.points[starts[a] as usize..starts[b + 1] as usize]
            }
            _ => &[],
        }
    }

    /// The points in bucket `key`.
    fn bucket(&self, key: IVec3) -> &[(u32, Vec3)] {
        let run = match &self.index {
            Index::Dense { cells, starts } => match cells.index(key) {
                Some(slot) => (starts[slot], starts[slot + 1]),
                None => return &[],
            },
            Index::Sparse(runs) => match runs.get(&key) {
                Some(&run) => run,
                None => return &[],
            },
        };
        &self.points[run.0 as usize..run.1 as usize]
    }

    /// The survivor nearest to `p` (ties to the lower vertex index, so the answer is
    /// deterministic); `None` when there is none.
    pub(crate) fn nearest(&self, p: Vec3) -> Option<u32> {
        self.nearest_within(p, f32::INFINITY)
    }

    /// [`Survivors::nearest`] among the points within `within` of `p`, or one a little farther:
    /// rings of buckets wholly beyond `within` are not searched, so a query with nothing near
    /// costs a few rings rather than a pass over every point.
    pub(crate) fn nearest_within(&self, p: Vec3, within: f32) -> Option<u32> {
        if self.points.is_empty() || !p.is_finite() {
            return None;
        }
        let centre = (p / self.cell).floor().as_ivec3();
        let reach = (centre - self.bounds.0)
            .abs()
            .max((self.bounds.1 - centre).abs())
            .max_element();
        let mut best: Option<(f32, u32)> = None;
        let closer = |best: &mut Option<(f32, u32)>, (v, q): (u32, Vec3)| {
            let d = (q - p).length_squared();
            if best.is_none_or(|(bd, bv)| d < bd || (d == bd && v < bv)) {
                *best = Some((d, v));
            }
        };
        for ring in 0..=reach {
            // Every point of ring r + 1 or beyond is at least r cells away; more exactly, it lies
            // outside the cube of the rings searched, whose nearest face is usually farther.
            if let Some((d, _)) = best
                && (d.sqrt() <= ring.saturating_sub(1) as f32 * self.cell
                    || d.sqrt() < self.beyond(p, centre, ring - 1))
            {
                break;
            }
            if ring > 0 && self.beyond(p, centre, ring - 1) > within {
                break;
            }
            if ring > RINGS {
                for &point in &self.points {
                    closer(&mut best, point);
                }
                break;
            }
            self.shell(centre, ring, |points| {
                for &point in points {
                    closer(&mut best, point);
                }
            });
        }
        best.map(|(_, v)| v)
    }

    /// A distance that every point outside the cube of buckets within `searched` rings of
    /// `centre` (the bucket of `p`) exceeds: the distance from `p` to the cube's nearest face,
    /// less a margin for the rounding of `p` and of the points' buckets.
    fn beyond(&self, p: Vec3, centre: IVec3, searched: i32) -> f32 {
        let low = (centre - searched).as_vec3() * self.cell;
        let high = (centre + searched + 1).as_vec3() * self.cell;
        let face = (p - low).min(high - p).min_element();
        let scale = centre.abs().max_element() as f32 + searched as f32 + 2.0;
        face - 4.0 * f32::EPSILON * scale * self.cell
    }

    /// [`Survivors::nearest`] of each of `points`, in order, queried in parallel.
    pub(crate) fn nearest_each(
        &self,
        points: impl IndexedParallelIterator<Item = Vec3>,
    ) -> Vec<Option<u32>> {
        points.map(|p| self.nearest(p)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nearest of `points` to `p` by comparing every one, ties to the lower vertex index.
    fn brute_nearest(points: &[(u32, Vec3)], p: Vec3) -> Option<u32> {
        points
            .iter()
            .min_by(|a, b| {
                (a.1 - p)
                    .length_squared()
                    .total_cmp(&(b.1 - p).length_squared())
                    .then(a.0.cmp(&b.0))
            })
            .map(|&(v, _)| v)
    }

    #[test]
    fn a_bounded_search_stops_rings_short_of_a_far_point() {
        let points = [
            (0, Vec3::new(5.0, 0.0, 0.0)),
            (1, Vec3::new(-7.0, 0.5, 0.0)),
        ];
        let near = Survivors::new(points, 1.0);
        let p = Vec3::new(0.2, 0.3, 0.1);
        assert_eq!(near.nearest(p), Some(0));
        assert_eq!(near.nearest_within(p, 1.0), None);
        assert_eq!(near.nearest_within(p, 6.0), Some(0));
    }

    #[test]
    fn finds_the_brute_force_nearest() {
        let points: Vec<(u32, Vec3)> = (0..200u32)
            .map(|i| {
                let t = i as f32;
                (
                    i,
                    Vec3::new((t * 1.7).sin() * 9.0, (t * 0.3).cos() * 4.0, t * 0.05),
                )
            })
            .collect();
        // Buckets of 0.7 find most answers within a few rings; of 0.05, beyond the rings searched.
        for cell in [0.7, 0.05] {
            let survivors = Survivors::new(points.clone(), cell);
            for k in 0..100 {
                let k = k as f32;
                let p = Vec3::new((k * 0.9).cos() * 12.0, k * 0.1 - 5.0, (k * 2.1).sin() * 3.0);
                let brute = brute_nearest(&points, p);
                assert_eq!(survivors.nearest(p), brute, "query {p}, buckets of {cell}");
            }
        }
        assert_eq!(Survivors::new([], 1.0).nearest(Vec3::ZERO), None);
    }

    /// Two clusters a hundred thousand buckets apart are too wide a box to list: their buckets
    /// are indexed sparsely, one cluster alone densely, and both answer as comparing every point.
    #[test]
    fn sparse_and_dense_indices_give_the_brute_force_nearest() {
        let cluster = |origin: Vec3, first: u32| -> Vec<(u32, Vec3)> {
            (0..300u32)
                .map(|i| {
                    let t = i as f32;
                    let q = Vec3::new((t * 1.3).sin(), (t * 0.7).cos(), (t * 0.11).sin()) * 4.0;
                    (first + i, origin + q)
                })
                .collect()
        };
        let near = cluster(Vec3::ZERO, 0);
        let mut both = near.clone();
        both.extend(cluster(Vec3::new(1.0e5, -2.0e5, 5.0e4), 1000));
        let dense = Survivors::new(near.clone(), 0.5);
        let sparse = Survivors::new(both.clone(), 0.5);
        assert!(matches!(dense.index, Index::Dense { .. }));
        assert!(matches!(sparse.index, Index::Sparse(_)));
        for k in 0..200 {
            let k = k as f32;
            let p = Vec3::new(
                (k * 0.37).cos() * 6.0,
                (k * 0.21).sin() * 5.0,
                k * 0.04 - 4.0,
            );
            assert_eq!(dense.nearest(p), brute_nearest(&near, p), "query {p}");
            assert_eq!(sparse.nearest(p), brute_nearest(&both, p), "query {p}");
            assert_eq!(
                sparse.nearest_within(p, 1.0),
                dense.nearest_within(p, 1.0),
                "query {p}"
            );
        }
    }

    /// Points on a lattice that shares the buckets' planes, and queries on bucket faces and at
    /// points equidistant from several of them (ties), far from the origin too: the search may
    /// stop at the searched cube's nearest face only where no point beyond it could be as near.
    #[test]
    fn ties_and_bucket_faces_give_the_brute_force_nearest() {
        for (origin, cell) in [(Vec3::ZERO, 1.0), (Vec3::new(1000.0, -500.0, 250.0), 0.5)] {
            let mut points = Vec::new();
            for i in 0..6u32 {
                for j in 0..6u32 {
                    for k in 0..6u32 {
                        let q = Vec3::new(i as f32, j as f32, k as f32) * 0.75 * cell;
                        points.push((
                            ((i * 7 + j * 3 + k * 5) % 216) * 1000 + i * 36 + j * 6 + k,
                            origin + q,
                        ));
                    }
                }
            }
            let survivors = Survivors::new(points.clone(), cell);
            for a in 0..12 {
                for b in 0..12 {
                    let p = origin
                        + Vec3::new(a as f32 * 0.375, b as f32 * 0.5, (a + b) as f32 * 0.125)
                            * cell;
                    let brute = brute_nearest(&points, p);
                    assert_eq!(survivors.nearest(p), brute, "query {p}, buckets of {cell}");
                }
            }
        }
    }
}
