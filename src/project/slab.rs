//! Line–box test for BVH traversal: the part of a line `o + t·d` inside a node's box, as the
//! distance `|t|` from the origin to the nearest point of that part.

use glam::{Vec3, Vec3A};

use super::BvhNode;

/// Relative widening of every box interval: the slab parameters carry at most 3 roundings each,
/// so widening by 2γ₃ (Ize 2013, "Robust BVH ray traversal") keeps the test conservative and a
/// box is never culled where the exact line enters it. 4ε ≥ 2γ₃.
const WIDEN: f32 = 4.0 * f32::EPSILON;
/// Direction components smaller than this are replaced by it (with their sign) before taking the
/// reciprocal, so no slab parameter is ever NaN (0 · ∞) or infinite (as in Embree).
const MIN_DIRECTION: f32 = 1e-18;
/// What [`Slabs::key`] returns for a box the line misses within the allowed interval.
pub(super) const MISS_KEY: f32 = -1.0;

/// A line's origin and safe reciprocal direction.
#[derive(Debug, Clone, Copy)]
pub(super) struct Slabs {
    origin: Vec3A,
    inv: Vec3A,
}

impl Slabs {
    pub(super) fn new(origin: Vec3, direction: Vec3) -> Self {
        let safe = |d: f32| {
            if d.abs() < MIN_DIRECTION {
                if d < 0.0 {
                    -MIN_DIRECTION
                } else {
                    MIN_DIRECTION
                }
            } else {
                d
            }
        };
        Self {
            origin: origin.into(),
            inv: Vec3A::ONE / Vec3A::new(safe(direction.x), safe(direction.y), safe(direction.z)),
        }
    }

    /// `min |t|` over the line's parameters inside `node`'s box and inside `[lo, hi]`, or
    /// [`MISS_KEY`] when there is none.
    #[inline(always)]
    pub(super) fn key(&self, node: &BvhNode, lo: f32, hi: f32) -> f32 {
        let t0 = (Vec3A::from(node.min) - self.origin) * self.inv;
        let t1 = (Vec3A::from(node.max) - self.origin) * self.inv;
        let enter = t0.min(t1).max_element();
        let exit = t0.max(t1).min_element();
        let enter = (enter - enter.abs() * WIDEN).max(lo);
        let exit = (exit + exit.abs() * WIDEN).min(hi);
        if enter <= exit {
            enter.max(-exit).max(0.0)
        } else {
            MISS_KEY
        }
    }
}
