//! The nearest surviving vertex of a point: the data source of vertices a topology change creates
//! or deletes with no patch boundary to average (a droplet appearing or vanishing whole, §4.4).

use glam::{IVec3, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// A uniform hash grid over the vertices that exist both before and after a topology change.
pub(crate) struct Survivors {
    cell: f32,
    buckets: FxHashMap<IVec3, Vec<(u32, Vec3)>>,
    bounds: (IVec3, IVec3),
    /// Every point, for a query whose nearest survivor lies beyond [`RINGS`] rings.
    all: Vec<(u32, Vec3)>,
}

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
        let mut buckets: FxHashMap<IVec3, Vec<(u32, Vec3)>> = FxHashMap::default();
        let mut bounds = (IVec3::MAX, IVec3::MIN);
        let all: Vec<(u32, Vec3)> = points.into_iter().filter(|(_, p)| p.is_finite()).collect();
        for &(v, p) in &all {
            let key = (p / cell).floor().as_ivec3();
            bounds = (bounds.0.min(key), bounds.1.max(key));
            buckets.entry(key).or_default().push((v, p));
        }
        Self {
            cell,
            buckets,
            bounds,
            all,
        }
    }

    /// The survivor nearest to `p` (ties to the lower vertex index, so the answer is
    /// deterministic); `None` when there is none.
    pub(crate) fn nearest(&self, p: Vec3) -> Option<u32> {
        if self.buckets.is_empty() || !p.is_finite() {
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
            // Every point of ring r + 1 or beyond is at least r cells away.
            if let Some((d, _)) = best
                && d.sqrt() <= ring.saturating_sub(1) as f32 * self.cell
            {
                break;
            }
            if ring > RINGS {
                for &point in &self.all {
                    closer(&mut best, point);
                }
                break;
            }
            for key in shell(centre, ring) {
                for &point in self.buckets.get(&key).into_iter().flatten() {
                    closer(&mut best, point);
                }
            }
        }
        best.map(|(_, v)| v)
    }

    /// [`Survivors::nearest`] of each of `points`, in order, queried in parallel.
    pub(crate) fn nearest_each(
        &self,
        points: impl IndexedParallelIterator<Item = Vec3>,
    ) -> Vec<Option<u32>> {
        points.map(|p| self.nearest(p)).collect()
    }
}

/// The keys at Chebyshev distance exactly `ring` from `centre`: whole columns of `z` where `x` or
/// `y` lies on the shell's side, only its two ends elsewhere (no allocation: a query visits
/// dozens of columns).
fn shell(centre: IVec3, ring: i32) -> impl Iterator<Item = IVec3> {
    (-ring..=ring).flat_map(move |x| {
        (-ring..=ring).flat_map(move |y| {
            // Ring 0 is a single key, and on its side.
            let on_side = x.abs() == ring || y.abs() == ring;
            let step = if on_side { 1 } else { 2 * ring as usize };
            (-ring..=ring)
                .step_by(step)
                .map(move |z| centre + IVec3::new(x, y, z))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
                let brute = points
                    .iter()
                    .min_by(|a, b| {
                        (a.1 - p)
                            .length_squared()
                            .total_cmp(&(b.1 - p).length_squared())
                            .then(a.0.cmp(&b.0))
                    })
                    .map(|&(v, _)| v);
                assert_eq!(survivors.nearest(p), brute, "query {p}, buckets of {cell}");
            }
        }
        assert_eq!(Survivors::new([], 1.0).nearest(Vec3::ZERO), None);
    }
}
