//! Exact predicates under one symbolic perturbation, shared by every rasterization decision.
//!
//! The mesh is treated as translated by `(ε, ε², ε³)` for an infinitesimal `ε > 0` (the scheme of
//! the topology design note §4; TopoFixer reaches the same with index-priority Simulation of
//! Simplicity). After that translation no vertex lies on a grid plane, no mesh edge meets a grid
//! line and no triangle contains a grid corner, so every question "which side" has a strict answer,
//! and all answers describe one geometric configuration. That is why, when a grid line passes
//! exactly through a mesh edge or vertex, exactly one of the triangles around it is counted (no
//! double or missing crossing, the failure of thesis §3.4.3), why the three sweep directions agree
//! at every corner of a closed mesh, and why "a mesh edge pierces a cell face" and "its endpoints lie
//! in different cells" can never disagree (thesis §3.4.6).
//!
//! Each predicate evaluates its exact polynomial on integers (lattice coordinates offset from the
//! triangle's lowest cell, below `2^31`, see [`super::lattice`]): products of two offsets fit in
//! `i64` and a corner's orientation against a triangle's plane in `i128`. When the exact value is
//! zero the coefficients of `ε`, `ε²`, `ε³` decide, in that order. `kernels/shared/exact.wgsl`
//! evaluates the same polynomials with 32-bit limbs, so the GPU reaches identical answers.

use std::cmp::Ordering;

use super::lattice::cell_range;
use crate::kernels::shared::GridCrossing;
use crate::kernels::shared::{CELL_UNITS, FRACTION_BITS, LatticePoint};

/// The two axes of the plane across lines along `axis`, in cyclic order: `(y, z)`, `(z, x)`, `(x, y)`.
/// With this order the 2-D cross product of the projection is the normal's `axis` component.
pub const fn cross_axes(axis: usize) -> (usize, usize) {
    ((axis + 1) % 3, (axis + 2) % 3)
}

/// Number of candidate lines of a triangle with vertex cells `lo..=hi`, per axis.
///
/// A line along `axis` can meet the perturbed triangle only when it lies strictly inside the
/// projected bounding box, shifted by `-δ`: its cells along the two other axes are in
/// `lo + 1 ..= hi`.
pub(crate) fn candidate_counts(lo: [i32; 3], hi: [i32; 3]) -> [u64; 3] {
    std::array::from_fn(|axis| {
        let (u, v) = cross_axes(axis);
        (hi[u] - lo[u]) as u64 * (hi[v] - lo[v]) as u64
    })
}

/// Sign of `x` as -1, 0 or 1.
fn sign<T: Into<i128>>(x: T) -> i32 {
    x.into().signum() as i32
}

/// Sign of the first non-zero value, 0 if all are zero: how a tie is read from the coefficients of
/// `ε`, `ε²`, `ε³` listed in that order.
fn first_sign(values: &[i64]) -> i32 {
    values
        .iter()
        .map(|&v| sign(v))
        .find(|&s| s != 0)
        .unwrap_or(0)
}

/// The sign of a predicate on a segment and the planes of axes `a` and `b` (`a != b`) whose exact
/// value has sign `exact`: when that is 0, the perturbation decides. The tie is
/// `−d_b ε^(a+1) + d_a ε^(b+1)`, read lower power first, where `d_a`, `d_b` are the signs of the
/// segment's extent along each axis. The rasterizer's mesh edges and the topology step's cut
/// share it, so both see one configuration.
pub(crate) fn segment_sign(exact: i32, a: usize, b: usize, d_a: i32, d_b: i32) -> i32 {
    if exact != 0 {
        exact
    } else if a < b {
        if d_b != 0 { -d_b } else { d_a }
    } else if d_a != 0 {
        d_a
    } else {
        -d_b
    }
}

/// The largest `x` in `lo..=hi` for which `above(x)` holds, `lo` when none past it does, for an
/// `above` that holds up to some index and fails beyond it: the cell where a segment or a grid
/// line leaves the range `lo..=hi`, found by bisection.
pub(crate) fn last_above(mut lo: i32, mut hi: i32, above: impl Fn(i32) -> bool) -> i32 {
    while lo < hi {
        let mid = lo + (hi - lo + 1) / 2;
        if above(mid) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

/// A triangle with its corners as lattice offsets from its lowest cell (`base`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct LocalTriangle {
    pub base: [i32; 3],
    pub p: [[i32; 3]; 3],
}

impl LocalTriangle {
    /// Offsets of the corners from their lowest cell; [`super::LatticeMesh`] guarantees the span
    /// bound that makes every offset fit in 31 bits.
    pub fn new(corners: &[LatticePoint; 3]) -> Self {
        let (base, _) = cell_range(corners);
        Self {
            base,
            p: corners.map(|c| local_point(&c, base)),
        }
    }

    /// Local coordinate of the grid plane with index `cell` along `axis`.
    pub fn plane(&self, axis: usize, cell: i32) -> i32 {
        (cell - self.base[axis]) << FRACTION_BITS
    }

    /// The normal `(B - A) × (C - A)`, exact.
    pub fn normal(&self) -> [i64; 3] {
        std::array::from_fn(|axis| {
            let (u, v) = cross_axes(axis);
            cross2(self.p[0], self.p[1], self.p[2], u, v)
        })
    }
}

/// Offsets of a lattice point from cell `base`, in lattice units.
fn local_point(c: &LatticePoint, base: [i32; 3]) -> [i32; 3] {
    std::array::from_fn(|a| ((c.cell[a] - base[a]) << FRACTION_BITS) + c.frac[a] as i32)
}

/// `(b - a) × (c - a)` in the plane of axes `(u, v)`; doubled signed area of the projection.
fn cross2(a: [i32; 3], b: [i32; 3], c: [i32; 3], u: usize, v: usize) -> i64 {
    let (bu, bv) = (i64::from(b[u] - a[u]), i64::from(b[v] - a[v]));
    let (cu, cv) = (i64::from(c[u] - a[u]), i64::from(c[v] - a[v]));
    bu * cv - bv * cu
}

/// Which side of the directed projected edge `p → q` the grid line through `(xu, xv)` passes,
/// perturbed: `+1` left, `-1` right, `0` only when the projected edge is a point.
///
/// Translating the mesh by `δ` moves the line by `-δ` relative to it, which adds
/// `(q_v - p_v) δ_u - (q_u - p_u) δ_v` to the edge function; `δ_u` is the larger of the two when
/// `u < v` (it carries the lower power of `ε`).
fn edge_sign(p: [i32; 3], q: [i32; 3], u: usize, v: usize, xu: i32, xv: i32) -> i32 {
    let du = i64::from(q[u] - p[u]);
    let dv = i64::from(q[v] - p[v]);
    let e = du * i64::from(xv - p[v]) - dv * i64::from(xu - p[u]);
    if e != 0 {
        return sign(e);
    }
    if u < v {
        first_sign(&[dv, -du])
    } else {
        first_sign(&[-du, dv])
    }
}

/// Side of the corner `q` against the perturbed plane of the triangle: the sign of
/// `n · (A + δ - q)`, whose tie is `n · δ`, the first non-zero of `n_x`, `n_y`, `n_z`.
fn plane_side(n: [i64; 3], a: [i32; 3], q: [i32; 3]) -> (i128, i32) {
    let s: i128 = (0..3)
        .map(|k| i128::from(n[k]) * i128::from(a[k] - q[k]))
        .sum();
    let side = if s != 0 { sign(s) } else { first_sign(&n) };
    (s, side)
}

/// The crossing of triangle `triangle` (corners `tri`) with the grid line along `axis` through
/// cells `(line_u, line_v)` of the two other axes ([`cross_axes`] order), if they cross.
///
/// The line meets the perturbed triangle when it lies strictly on the inner side of all three
/// projected edges; a triangle whose projection has zero area is never met. The grid edge holding
/// the crossing is found by bisection over the triangle's cell range with [`plane_side`]: the
/// crossing lies past corner `i` when the corner is on the side of the plane that the normal's
/// `axis` component points away from. This is the body of the rasterize kernel
/// (`kernels/rasterize.wgsl`), run once per candidate line.
pub(crate) fn line_crossing(
    tri: &LocalTriangle,
    hi_along: i32,
    triangle: u32,
    axis: usize,
    line_u: i32,
    line_v: i32,
) -> Option<GridCrossing> {
    let (u, v) = cross_axes(axis);
    let [a, b, c] = tri.p;
    let d = cross2(a, b, c, u, v);
    if d == 0 {
        return None;
    }
    let (xu, xv) = (tri.plane(u, line_u), tri.plane(v, line_v));
    let want = sign(d);
    if edge_sign(a, b, u, v, xu, xv) != want
        || edge_sign(b, c, u, v, xu, xv) != want
        || edge_sign(c, a, u, v, xu, xv) != want
    {
        return None;
    }
    let n = tri.normal();
    let corner_at = |i: i32| {
        let mut q = [0; 3];
        q[axis] = tri.plane(axis, i);
        q[u] = xu;
        q[v] = xv;
        q
    };
    let past = |i: i32| plane_side(n, a, corner_at(i)).1 == want;
    let lo = last_above(tri.base[axis], hi_along, past);
    let (s, _) = plane_side(n, a, corner_at(lo));
    let t = crossing_fraction(s as f32, d as f32);
    let mut corner = [0; 3];
    corner[axis] = lo;
    corner[u] = line_u;
    corner[v] = line_v;
    Some(GridCrossing::new(corner, axis, triangle, t, d < 0))
}

/// Position of the crossing past its corner, in cells: `n·(A - q) / n_axis`, clamped to `[0, 1)`.
pub(crate) fn crossing_fraction(side: f32, normal_along: f32) -> f32 {
    let t = side / normal_along * (1.0 / CELL_UNITS as f32);
    t.clamp(0.0, 1.0 - f32::EPSILON / 2.0)
}

/// A mesh edge with its endpoints as lattice offsets from their lowest cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct LocalSegment {
    pub base: [i32; 3],
    pub p: [i32; 3],
    pub q: [i32; 3],
    pub cell_p: [i32; 3],
    pub cell_q: [i32; 3],
}

impl LocalSegment {
    pub fn new(p: &LatticePoint, q: &LatticePoint) -> Self {
        let base = std::array::from_fn(|a| p.cell[a].min(q.cell[a]));
        Self {
            base,
            p: local_point(p, base),
            q: local_point(q, base),
            cell_p: p.cell,
            cell_q: q.cell,
        }
    }

    fn plane(&self, axis: usize, cell: i32) -> i32 {
        (cell - self.base[axis]) << FRACTION_BITS
    }

    /// Whether the point where the segment crosses plane `plane` of `axis` lies past plane
    /// `other_plane` of `other` (both indices of cells).
    ///
    /// The crossing point is `P + δ + s (Q - P)` with `s = (I - P_a - δ_a) / d_a`, so
    /// `(x_o - J) d_a = (P_o - J) d_a + d_o (I - P_a) + δ_o d_a - δ_a d_o`.
    fn past(&self, axis: usize, plane: i32, other: usize, other_plane: i32) -> bool {
        let d: [i64; 3] = std::array::from_fn(|k| i64::from(self.q[k] - self.p[k]));
        let i = i64::from(self.plane(axis, plane));
        let j = i64::from(self.plane(other, other_plane));
        let k = (i64::from(self.p[other]) - j) * d[axis] + d[other] * (i - i64::from(self.p[axis]));
        segment_sign(sign(k), axis, other, sign(d[axis]), sign(d[other])) * sign(d[axis]) > 0
    }

    /// The cell face that the segment pierces on plane `plane` of `axis`: the cell just above the
    /// plane, whose lower `axis` face it is. `plane` must lie strictly between the endpoints' cells
    /// (`min < plane <= max`).
    pub fn face(&self, axis: usize, plane: i32) -> [i32; 3] {
        let mut cell = [0; 3];
        cell[axis] = plane;
        let (u, v) = cross_axes(axis);
        for other in [u, v] {
            let lo = self.cell_p[other].min(self.cell_q[other]);
            let hi = self.cell_p[other].max(self.cell_q[other]);
            cell[other] = last_above(lo, hi, |mid| self.past(axis, plane, other, mid));
        }
        cell
    }

    /// Order along the segment (from `P`) of its crossings with plane `i` of `a` and plane `j` of `b`.
    ///
    /// `s_a - s_b` has the sign of `[(I - P_a - δ_a) d_b - (J - P_b - δ_b) d_a] / (d_a d_b)`.
    pub fn compare(&self, (a, i): (usize, i32), (b, j): (usize, i32)) -> Ordering {
        let d: [i64; 3] = std::array::from_fn(|k| i64::from(self.q[k] - self.p[k]));
        if a == b {
            return if d[a] > 0 { i.cmp(&j) } else { j.cmp(&i) };
        }
        let i = i64::from(self.plane(a, i)) - i64::from(self.p[a]);
        let j = i64::from(self.plane(b, j)) - i64::from(self.p[b]);
        let n = i * d[b] - j * d[a];
        let (d_a, d_b) = (sign(d[a]), sign(d[b]));
        (segment_sign(sign(n), a, b, d_a, d_b) * d_a * d_b).cmp(&0)
    }

    /// Parameter of the crossing with plane `plane` of `axis` along the segment, in `(0, 1)`.
    pub fn parameter(&self, axis: usize, plane: i32) -> f32 {
        let d = f64::from(self.q[axis] - self.p[axis]);
        let s = f64::from(self.plane(axis, plane) - self.p[axis]) / d;
        (s as f32).clamp(f32::EPSILON, 1.0 - f32::EPSILON)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(cell: [i32; 3], frac: [u32; 3]) -> LatticePoint {
        LatticePoint { cell, frac }
    }

    fn unit(c: [i32; 3]) -> LatticePoint {
        point(c, [0; 3])
    }

    const HALF: u32 = (CELL_UNITS / 2) as u32;

    #[test]
    fn line_through_a_shared_edge_hits_exactly_one_of_two_triangles() {
        // Square [0,2]² at height z = 0.5 split along its diagonal; the z line through (1, 1) runs
        // exactly through the diagonal.
        let z = [0, 0, HALF];
        let a = point([0, 0, 0], z);
        let b = point([2, 0, 0], z);
        let c = point([2, 2, 0], z);
        let d = point([0, 2, 0], z);
        let mut hits = 0;
        for (t, tri) in [[a, b, c], [a, c, d]].iter().enumerate() {
            let local = LocalTriangle::new(tri);
            let (_, hi) = cell_range(tri);
            if let Some(x) = line_crossing(&local, hi[2], t as u32, 2, 1, 1) {
                hits += 1;
                assert_eq!(x.corner, [1, 1, 0]);
                assert_eq!(x.t, 0.5);
                assert!(!x.enter(), "normal +z: walking +z exits");
            }
        }
        assert_eq!(hits, 1);
    }

    #[test]
    fn crossing_on_a_corner_belongs_to_the_edge_above() {
        let tri = [unit([0, 0, 1]), unit([3, 0, 1]), unit([0, 3, 1])];
        let local = LocalTriangle::new(&tri);
        let x = line_crossing(&local, 1, 0, 2, 1, 1).unwrap();
        assert_eq!(x.corner, [1, 1, 1]);
        assert_eq!(x.t, 0.0);
    }

    #[test]
    fn segment_faces_and_order_agree() {
        let p = point([0, 0, 0], [HALF; 3]);
        let q = point([2, 1, 0], [HALF; 3]);
        let seg = LocalSegment::new(&p, &q);
        let mut planes = vec![(0usize, 2), (1, 1), (0, 1)];
        planes.sort_by(|&x, &y| seg.compare(x, y));
        // x = 1 at s = 0.25, y = 1 at s = 0.5, x = 2 at s = 0.75.
        assert_eq!(planes, vec![(0, 1), (1, 1), (0, 2)]);
        assert_eq!(seg.face(0, 1), [1, 0, 0]);
        assert_eq!(seg.face(1, 1), [1, 1, 0]);
        assert_eq!(seg.face(0, 2), [2, 1, 0]);
    }

    #[test]
    fn segment_through_a_grid_line_passes_one_side_of_it() {
        // (0.5, 0.5) to (1.5, 1.5) meets the z line x = y = 1. Shifted by (ε, ε²) the segment reaches
        // x = 1 first (at s = 1/2 - ε) and passes below y = 1 there, then crosses y = 1 in cell x = 1.
        let p = point([0, 0, 0], [HALF; 3]);
        let q = point([1, 1, 0], [HALF; 3]);
        let seg = LocalSegment::new(&p, &q);
        assert_eq!(seg.compare((0, 1), (1, 1)), Ordering::Less);
        assert_eq!(seg.compare((1, 1), (0, 1)), Ordering::Greater);
        assert_eq!(seg.face(0, 1), [1, 0, 0]);
        assert_eq!(seg.face(1, 1), [1, 1, 0]);
        // Reversed, the same configuration: y = 1 is crossed at x = 1 + ε, in cell x = 1.
        let back = LocalSegment::new(&q, &p);
        assert_eq!(back.compare((1, 1), (0, 1)), Ordering::Less);
        assert_eq!(back.face(0, 1), [1, 0, 0]);
        assert_eq!(back.face(1, 1), [1, 1, 0]);
    }
}
