//! Line–box test for BVH traversal: for each of a node's four children, the part of a line
//! `o + t·d` inside the child's box, as the distance `|t|` from the origin to the nearest point
//! of that part.

use glam::{BVec4A, Vec3, Vec4};

use crate::kernels::shared::BvhNode;

/// Relative widening of every box interval: the slab parameters carry at most 3 roundings each,
/// so widening by 2γ₃ (Ize 2013, "Robust BVH ray traversal") keeps the test conservative and a
/// box is never culled where the exact line enters it. 4ε ≥ 2γ₃.
const WIDEN: f32 = 4.0 * f32::EPSILON;
/// Direction components smaller than this are replaced by it (with their sign) before taking the
/// reciprocal, so no slab parameter is ever NaN (0 · ∞) or infinite (as in Embree).
const MIN_DIRECTION: f32 = 1e-18;

/// A line's origin and safe reciprocal direction, each component splatted over four lanes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Slabs {
    origin: [Vec4; 3],
    inv: [Vec4; 3],
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
            origin: origin.to_array().map(Vec4::splat),
            inv: direction.to_array().map(|d| Vec4::splat(1.0 / safe(d))),
        }
    }

    /// Per child: `min |t|` over the line's parameters inside the child's box and inside
    /// `[lo, hi]`, and whether there are any. Unused slots come out as whatever their zero box
    /// gives; callers skip them by `count`.
    #[inline(always)]
    pub(super) fn keys(&self, node: &BvhNode, lo: f32, hi: f32) -> (Vec4, BVec4A) {
        let [ox, oy, oz] = self.origin;
        let [ix, iy, iz] = self.inv;
        let tx0 = (Vec4::from(node.min_x) - ox) * ix;
        let tx1 = (Vec4::from(node.max_x) - ox) * ix;
        let ty0 = (Vec4::from(node.min_y) - oy) * iy;
        let ty1 = (Vec4::from(node.max_y) - oy) * iy;
        let tz0 = (Vec4::from(node.min_z) - oz) * iz;
        let tz1 = (Vec4::from(node.max_z) - oz) * iz;
        let enter = tx0.min(tx1).max(ty0.min(ty1)).max(tz0.min(tz1));
        let exit = tx0.max(tx1).min(ty0.max(ty1)).min(tz0.max(tz1));
        let enter = (enter - enter.abs() * WIDEN).max(Vec4::splat(lo));
        let exit = (exit + exit.abs() * WIDEN).min(Vec4::splat(hi));
        (enter.max(-exit).max(Vec4::ZERO), enter.cmple(exit))
    }
}
