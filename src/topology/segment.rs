//! Exact predicates on a mesh edge against the grid's planes, under the rasterizer's symbolic
//! perturbation (the mesh translated by `(ε, ε², ε³)`, see the grid module's predicates).
//!
//! The cut (thesis §3.4.6) must place every point where a mesh edge pierces a cell face in the same
//! configuration the rasterizer used for its grid-edge crossings, or the loop of cut points around the
//! complex region does not close. Because the perturbation is one geometric translation, exact
//! evaluation here agrees with the rasterizer's exact evaluation there: "the edge pierces this face",
//! "this crossing comes first along the edge" and "the triangle crosses this grid edge" describe one
//! configuration. Coordinates are lattice units in `i128`, so no product can overflow.

use std::cmp::Ordering;

use super::keys::Cell;
use crate::grid::{CELL_UNITS, LatticePoint, last_above, segment_sign};

/// Lattice coordinate of plane `plane`.
fn plane_units(plane: i32) -> i128 {
    i128::from(plane) * i128::from(CELL_UNITS)
}

/// Whether a mesh vertex lies above plane `plane` of `axis`: on the plane counts as above, since
/// the perturbation moves it by `+ε^(axis+1)` (the rasterizer's `floor`).
pub(crate) fn vertex_above(p: &LatticePoint, axis: usize, plane: i32) -> bool {
    p.cell[axis] >= plane
}

/// A mesh edge from `p` to `q` in lattice units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Segment {
    p: [i128; 3],
    d: [i128; 3],
    lo: [i32; 3],
    hi: [i32; 3],
}

impl Segment {
    pub fn new(p: &LatticePoint, q: &LatticePoint) -> Self {
        let pu: [i128; 3] = std::array::from_fn(|a| i128::from(p.units(a)));
        let qu: [i128; 3] = std::array::from_fn(|a| i128::from(q.units(a)));
        Self {
            p: pu,
            d: std::array::from_fn(|a| qu[a] - pu[a]),
            lo: std::array::from_fn(|a| p.cell[a].min(q.cell[a])),
            hi: std::array::from_fn(|a| p.cell[a].max(q.cell[a])),
        }
    }

    /// Planes of `axis` the edge crosses: its endpoints' cells differ along `axis` and the plane
    /// lies between them.
    pub fn planes(&self, axis: usize) -> std::ops::RangeInclusive<i32> {
        self.lo[axis] + 1..=self.hi[axis]
    }

    pub fn crosses(&self, axis: usize, plane: i32) -> bool {
        self.lo[axis] < plane && plane <= self.hi[axis]
    }

    /// Whether the point where the edge crosses plane `i` of `a` lies above plane `j` of `b`
    /// (`b != a`).
    ///
    /// With `X = P + δ + s (Q − P)` and `s = (I − P_a − δ_a) / d_a`,
    /// `(X_b − J) d_a = (P_b − J) d_a + (I − P_a) d_b + δ_b d_a − δ_a d_b`.
    pub fn above(&self, (a, i): (usize, i32), (b, j): (usize, i32)) -> bool {
        let d = &self.d;
        let n = (self.p[b] - plane_units(j)) * d[a] + (plane_units(i) - self.p[a]) * d[b];
        let d_a = d[a].signum() as i32;
        segment_sign(n.signum() as i32, a, b, d_a, d[b].signum() as i32) * d_a > 0
    }

    /// The cell above the face that the edge pierces on plane `i` of `a` (the face is that cell's
    /// lower `a` face). `i` must be one of [`Segment::planes`]`(a)`.
    pub fn face(&self, a: usize, i: i32) -> Cell {
        let mut cell = [0; 3];
        cell[a] = i;
        for b in (0..3).filter(|&b| b != a) {
            cell[b] = last_above(self.lo[b], self.hi[b], |mid| self.above((a, i), (b, mid)));
        }
        cell
    }

    /// Order along the edge (from `P`) of its crossings with plane `i` of `a` and plane `j` of `b`.
    ///
    /// `s_a − s_b` has the sign of `[(I − P_a − δ_a) d_b − (J − P_b − δ_b) d_a] / (d_a d_b)`.
    pub fn compare(&self, (a, i): (usize, i32), (b, j): (usize, i32)) -> Ordering {
        let d = &self.d;
        if a == b {
            return if d[a] > 0 { i.cmp(&j) } else { j.cmp(&i) };
        }
        let n = (plane_units(i) - self.p[a]) * d[b] - (plane_units(j) - self.p[b]) * d[a];
        let (d_a, d_b) = (d[a].signum() as i32, d[b].signum() as i32);
        (segment_sign(n.signum() as i32, a, b, d_a, d_b) * d_a * d_b).cmp(&0)
    }

    /// Parameter along the edge of its crossing with plane `i` of `a`, in `[0, 1]`.
    pub fn parameter(&self, a: usize, i: i32) -> f64 {
        let t = (plane_units(i) - self.p[a]) as f64 / self.d[a] as f64;
        t.clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HALF: u32 = (CELL_UNITS / 2) as u32;

    fn point(cell: [i32; 3], frac: [u32; 3]) -> LatticePoint {
        LatticePoint { cell, frac }
    }

    #[test]
    fn faces_order_and_parameters_follow_the_geometry() {
        let seg = Segment::new(&point([0, 0, 0], [HALF; 3]), &point([2, 1, 0], [HALF; 3]));
        // x = 1 at s = 0.25, y = 1 at s = 0.5, x = 2 at s = 0.75.
        let crossings = [
            ((0usize, 1), [1, 0, 0], 0.25),
            ((1, 1), [1, 1, 0], 0.5),
            ((0, 2), [2, 1, 0], 0.75),
        ];
        for (k, &((axis, plane), face, s)) in crossings.iter().enumerate() {
            assert_eq!(seg.face(axis, plane), face);
            assert!((seg.parameter(axis, plane) - s).abs() < 1e-12);
            for &(later, _, _) in &crossings[k + 1..] {
                assert_eq!(seg.compare((axis, plane), later), Ordering::Less);
                assert_eq!(seg.compare(later, (axis, plane)), Ordering::Greater);
            }
        }
    }

    #[test]
    fn an_edge_through_a_grid_line_is_decided_the_same_both_ways() {
        // (0.5, 0.5) to (1.5, 1.5) meets the z line x = y = 1; shifted by (ε, ε²) it reaches x = 1
        // first and passes below y = 1 there.
        let p = point([0, 0, 0], [HALF; 3]);
        let q = point([1, 1, 0], [HALF; 3]);
        for seg in [Segment::new(&p, &q), Segment::new(&q, &p)] {
            assert_eq!(seg.face(0, 1), [1, 0, 0]);
            assert_eq!(seg.face(1, 1), [1, 1, 0]);
            assert!(!seg.above((0, 1), (1, 1)));
            assert!(seg.above((1, 1), (0, 1)));
        }
        assert_eq!(Segment::new(&p, &q).compare((0, 1), (1, 1)), Ordering::Less);
        assert_eq!(
            Segment::new(&q, &p).compare((0, 1), (1, 1)),
            Ordering::Greater
        );
    }

    #[test]
    fn vertices_on_planes_count_as_above() {
        let p = point([2, 0, 0], [0, 5, 5]);
        assert!(vertex_above(&p, 0, 2));
        assert!(!vertex_above(&p, 0, 3));
    }
}
