//! Queries are run in Morton (Z-curve) order of their positions: consecutive queries then
//! traverse nearly the same BVH nodes, which stay in cache. The traversal is bound by memory
//! latency, so this doubles the throughput against shuffled input and makes it independent of
//! the caller's vertex order (a tracked mesh's order degrades as it is remeshed). Results are
//! returned in the caller's order; each query is computed independently, so the order changes
//! no result.

use glam::{UVec3, Vec3};
use rayon::prelude::*;

/// Bits per axis of the Morton code: a 64³ grid over the queries' bounding box.
const BITS: u32 = 6;
const CELLS: usize = 1 << (3 * BITS);

/// A permutation of the queries and its inverse.
#[derive(Debug)]
pub(super) struct SpatialOrder {
    /// `order[k]`: the query run k-th.
    order: Vec<u32>,
    /// `rank[i]`: when query `i` runs.
    rank: Vec<u32>,
}

impl SpatialOrder {
    /// Morton order of the points' cells, by a stable counting sort, so queries in one cell keep
    /// the caller's order and the permutation is the same whatever the thread count. Non-finite
    /// points go first.
    pub(super) fn new(points: &[Vec3]) -> Self {
        let (lo, hi) = points
            .par_iter()
            .filter(|p| p.is_finite())
            .fold(
                || (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), &p| (lo.min(p), hi.max(p)),
            )
            .reduce(
                || (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |a, b| (a.0.min(b.0), a.1.max(b.1)),
            );
        let scale = Vec3::splat((1 << BITS) as f32) / (hi - lo).max(Vec3::splat(f32::MIN_POSITIVE));
        let codes: Vec<u32> = points
            .par_iter()
            .map(|&p| {
                if p.is_finite() {
                    let cell = ((p - lo) * scale)
                        .as_uvec3()
                        .min(UVec3::splat((1 << BITS) - 1));
                    morton(cell)
                } else {
                    0
                }
            })
            .collect();
        let mut start = vec![0u32; CELLS + 1];
        for &code in &codes {
            start[code as usize + 1] += 1;
        }
        for c in 0..CELLS {
            start[c + 1] += start[c];
        }
        let mut order = vec![0u32; points.len()];
        let mut rank = vec![0u32; points.len()];
        for (i, &code) in codes.iter().enumerate() {
            let k = start[code as usize];
            start[code as usize] += 1;
            order[k as usize] = i as u32;
            rank[i] = k;
        }
        Self { order, rank }
    }

    /// `values` in run order.
    pub(super) fn permute<T: Copy + Send + Sync>(&self, values: &[T]) -> Vec<T> {
        self.order.par_iter().map(|&i| values[i as usize]).collect()
    }

    /// Results in run order, back in the caller's order.
    pub(super) fn restore<T: Copy + Send + Sync>(&self, results: &[T]) -> Vec<T> {
        self.rank.par_iter().map(|&k| results[k as usize]).collect()
    }
}

/// Interleaves the low [`BITS`] bits of x, y, z.
fn morton(cell: UVec3) -> u32 {
    let spread = |v: u32| (0..BITS).fold(0u32, |m, b| m | ((v >> b) & 1) << (3 * b));
    spread(cell.x) | spread(cell.y) << 1 | spread(cell.z) << 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_round_trips_and_neighbours_stay_close() {
        // Uniform points in the unit cube from an LCG, in random order.
        let mut state = 1u64;
        let mut unit = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let points: Vec<Vec3> = (0..4096)
            .map(|_| Vec3::new(unit(), unit(), unit()))
            .chain([Vec3::NAN, Vec3::INFINITY])
            .collect();
        let order = SpatialOrder::new(&points);
        let ids: Vec<u32> = (0..points.len() as u32).collect();
        let run = order.permute(&ids);
        let mut seen = run.clone();
        seen.sort_unstable();
        assert_eq!(seen, ids, "a permutation");
        assert_eq!(order.restore(&run), ids, "restore undoes permute");
        assert!(
            !points[run[0] as usize].is_finite(),
            "non-finite points go first"
        );
        let path = |ids: &[u32]| -> f32 {
            ids.windows(2)
                .map(|w| points[w[0] as usize].distance(points[w[1] as usize]))
                .filter(|d| d.is_finite())
                .sum()
        };
        let (curve, given) = (path(&run), path(&ids));
        assert!(
            curve < 0.25 * given,
            "the curve shortens the walk: {curve} vs {given}"
        );
    }

    #[test]
    fn morton_interleaves_bits() {
        assert_eq!(morton(UVec3::new(1, 0, 0)), 1);
        assert_eq!(morton(UVec3::new(0, 1, 0)), 2);
        assert_eq!(morton(UVec3::new(0, 0, 1)), 4);
        assert_eq!(morton(UVec3::new(3, 0, 0)), 0b1001);
        assert_eq!(morton(UVec3::splat(63)), (1 << 18) - 1);
    }

    #[test]
    fn empty_and_single_inputs() {
        let order = SpatialOrder::new(&[]);
        assert!(order.permute::<u32>(&[]).is_empty());
        let order = SpatialOrder::new(&[Vec3::ONE]);
        assert_eq!(order.restore(&order.permute(&[7u32])), vec![7]);
    }
}
