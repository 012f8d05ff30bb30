//! Welding of duplicate vertices: many exporters write one vertex per face corner, which leaves the
//! surface disconnected at every edge. Vertices closer than a tolerance are merged into the earliest
//! of them, so the result depends only on the input order (deterministic).
//!
//! Vertices are bucketed by grid cell through one sort of `(cell hash, index)` keys rather than a
//! hash map: a frame's vertices touch the map in random order, and the sort is several times
//! faster than the cache misses it replaces.

use glam::{DVec3, Vec3};

/// Cells are this many tolerances wide, so the tolerance ball around a point almost always lies in
/// its own cell and neighbouring cells are rarely searched.
const CELL_PER_TOLERANCE: f64 = 256.0;

/// Cells are at least this fraction of the largest coordinate wide, which keeps cell indices far from
/// `i64` saturation whatever the tolerance.
const MIN_CELL_PER_EXTENT: f64 = 1.0 / (1u64 << 40) as f64;

/// For every vertex, the index of the vertex it merges into (itself when it is kept).
///
/// A vertex merges into the earliest kept vertex within `tolerance` (Euclidean distance,
/// inclusive), so exact duplicates always merge, even with a zero tolerance.
pub(crate) fn weld_targets(positions: &[Vec3], tolerance: f32) -> Vec<u32> {
    let tolerance = if tolerance.is_finite() && tolerance > 0.0 {
        f64::from(tolerance)
    } else {
        0.0
    };
    let extent = positions
        .iter()
        .map(|p| f64::from(p.abs().max_element()))
        .fold(0.0, f64::max);
    let cell = (tolerance * CELL_PER_TOLERANCE)
        .max(extent * MIN_CELL_PER_EXTENT)
        .max(f64::MIN_POSITIVE);
    let cell_of = |p: DVec3| (p / cell).to_array().map(floor);

    // `(hash of the vertex's cell) << 32 | index`, sorted: each cell's vertices form a run in index
    // order. Two cells with one hash share a run, which only costs extra distance checks.
    let mut sorted: Vec<u64> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| (u64::from(cell_hash(cell_of(p.as_dvec3()))) << 32) | i as u64)
        .collect();
    sorted.sort_unstable();
    let mut position_of = vec![0u32; positions.len()];
    let mut run_start = vec![0u32; positions.len()];
    for (k, &entry) in sorted.iter().enumerate() {
        position_of[entry as u32 as usize] = k as u32;
        run_start[k] = if k > 0 && sorted[k - 1] >> 32 == entry >> 32 {
            run_start[k - 1]
        } else {
            k as u32
        };
    }

    let tolerance_sq = tolerance * tolerance;
    let mut target: Vec<u32> = (0..positions.len() as u32).collect();
    for i in 0..positions.len() {
        let p = positions[i].as_dvec3();
        let within = |j: u32| positions[j as usize].as_dvec3().distance_squared(p) <= tolerance_sq;
        let k = position_of[i] as usize;
        // Earlier vertices of the own cell precede `i` in its run, in index order.
        let mut best = sorted[run_start[k] as usize..k]
            .iter()
            .map(|&entry| entry as u32)
            .find(|&j| target[j as usize] == j && within(j))
            .unwrap_or(u32::MAX);
        let own = cell_of(p);
        let lo = cell_of(p - DVec3::splat(tolerance));
        let hi = cell_of(p + DVec3::splat(tolerance));
        if lo != own || hi != own {
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        if [x, y, z] == own {
                            continue;
                        }
                        let hash = u64::from(cell_hash([x, y, z]));
                        let start = sorted.partition_point(|&entry| entry >> 32 < hash);
                        let limit = best.min(i as u32);
                        if let Some(j) = sorted[start..]
                            .iter()
                            .take_while(|&&entry| entry >> 32 == hash)
                            .map(|&entry| entry as u32)
                            .take_while(|&j| j < limit)
                            .find(|&j| target[j as usize] == j && within(j))
                        {
                            best = j;
                        }
                    }
                }
            }
        }
        if best != u32::MAX {
            target[i] = best;
        }
    }
    target
}

/// `x.floor()` as an integer (saturating), without a libm call.
fn floor(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// A fixed (so deterministic), well-mixed 32-bit hash of integer cell coordinates.
fn cell_hash([x, y, z]: [i64; 3]) -> u32 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    h = (h ^ (y as u64)).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    h = (h ^ (z as u64)).wrapping_mul(0x1656_67B1_9E37_79F9);
    (h >> 32) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition, by brute force: each vertex merges into the earliest kept vertex within
    /// the tolerance.
    fn brute_force(positions: &[Vec3], tolerance: f32) -> Vec<u32> {
        let tolerance_sq = f64::from(tolerance).powi(2);
        let mut target: Vec<u32> = Vec::new();
        for (i, p) in positions.iter().enumerate() {
            let found = (0..i).find(|&j| {
                target[j] == j as u32
                    && positions[j].as_dvec3().distance_squared(p.as_dvec3()) <= tolerance_sq
            });
            target.push(found.map_or(i as u32, |j| j as u32));
        }
        target
    }

    /// Clusters of points whose spread is comparable to the tolerance, so that welds happen both
    /// within cells and across cell boundaries.
    fn clusters(seed: u64, count: usize, spread: f32) -> Vec<Vec3> {
        let mut state = seed;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 40) as f32 / (1u64 << 24) as f32) - 0.5
        };
        let centres: Vec<Vec3> = (0..count / 8 + 1)
            .map(|_| Vec3::new(next(), next(), next()) * 10.0)
            .collect();
        (0..count)
            .map(|k| centres[k % centres.len()] + Vec3::new(next(), next(), next()) * spread)
            .collect()
    }

    #[test]
    fn matches_brute_force_across_cell_boundaries() {
        for (seed, tolerance) in [(1, 1e-3), (2, 1e-2), (3, 0.05), (4, 0.3)] {
            // A spread of 2·tolerance mixes welded and separate points in every cluster; 256
            // tolerances per cell put many clusters on cell boundaries.
            let positions = clusters(seed, 2000, 2.0 * tolerance);
            let expected = brute_force(&positions, tolerance);
            assert!(expected.iter().enumerate().any(|(i, &t)| t as usize != i));
            assert!(
                expected
                    .iter()
                    .enumerate()
                    .filter(|&(i, &t)| t as usize == i)
                    .count()
                    > 250
            );
            assert_eq!(weld_targets(&positions, tolerance), expected, "seed {seed}");
        }
    }

    #[test]
    fn zero_tolerance_merges_exact_duplicates_only() {
        let a = Vec3::new(1.0, -2.0, 3.0);
        let b = Vec3::new(1.0, -2.0, f32::from_bits(3.0f32.to_bits() + 1));
        let positions = [a, b, a, Vec3::ZERO, -Vec3::ZERO, b];
        assert_eq!(weld_targets(&positions, 0.0), [0, 1, 0, 3, 3, 1]);
        assert_eq!(weld_targets(&positions, f32::NAN), [0, 1, 0, 3, 3, 1]);
    }

    #[test]
    fn a_chain_welds_to_the_earliest_kept_vertex_only() {
        // 1 is within the tolerance of 0 and 2, but 2 is not within it of 0: 2 stays.
        let positions = [Vec3::ZERO, Vec3::X * 0.9, Vec3::X * 1.8];
        assert_eq!(weld_targets(&positions, 1.0), [0, 0, 2]);
    }

    #[test]
    fn floor_agrees_with_the_standard_library() {
        for x in [-2.5, -2.0, -1e-300, -0.0, 0.0, 0.5, 1.0, 3.9, -1e30, 1e30] {
            assert_eq!(floor(x), x.floor() as i64, "{x}");
        }
    }
}
