//! Triangulating a convex polygon without new vertices and without zero-area triangles.
//!
//! The pieces of a cut triangle are convex, but points inserted along a triangle side (where the
//! neighbouring triangle was split) make runs of collinear vertices; a triangle with its three
//! corners on one such run would have zero area. Each vertex carries a mask of the lines it lies on,
//! and the best triangulation (largest worst shape, then largest total, as the case table of
//! [`crate::grid::cases`] does) is chosen among those where no triangle has all three corners on one
//! line.

use glam::DVec3;

/// Shape of a triangle: `4√3 · area / Σ edge²`, 1 for equilateral, 0 for degenerate.
pub(crate) fn shape(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let area = 0.5 * (b - a).cross(c - a).length();
    let sum = (b - a).length_squared() + (c - b).length_squared() + (a - c).length_squared();
    if sum > 0.0 {
        4.0 * 3f64.sqrt() * area / sum
    } else {
        0.0
    }
}

/// Triangles (as indices into the polygon, in its orientation) of the best triangulation of the
/// polygon with vertices at `positions`, where `lines[i]` has bit `k` set when vertex `i` lies on
/// line `k`; `None` when every triangulation puts three vertices of one line in one triangle.
pub(crate) fn triangulate(positions: &[DVec3], lines: &[u8]) -> Option<Vec<[usize; 3]>> {
    let n = positions.len();
    if n < 3 {
        return None;
    }
    let allowed = |i: usize, k: usize, j: usize| lines[i] & lines[k] & lines[j] == 0;
    // best[i][j]: (worst shape, shape sum, split vertex) of the sub-polygon i..=j.
    let mut best = vec![vec![None::<(f64, f64, usize)>; n]; n];
    for i in 0..n - 1 {
        best[i][i + 1] = Some((f64::INFINITY, 0.0, i));
    }
    for len in 2..n {
        for i in 0..n - len {
            let j = i + len;
            let mut choice: Option<(f64, f64, usize)> = None;
            for k in i + 1..j {
                let (Some(left), Some(right)) = (best[i][k], best[k][j]) else {
                    continue;
                };
                if !allowed(i, k, j) {
                    continue;
                }
                let q = shape(positions[i], positions[k], positions[j]);
                let candidate = (q.min(left.0).min(right.0), q + left.1 + right.1, k);
                if choice.is_none_or(|c| (candidate.0, candidate.1) > (c.0, c.1)) {
                    choice = Some(candidate);
                }
            }
            best[i][j] = choice;
        }
    }
    best[0][n - 1]?;
    let mut triangles = Vec::with_capacity(n - 2);
    let mut stack = vec![(0usize, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (_, _, k) = best[i][j]?;
        triangles.push([i, k, j]);
        stack.push((i, k));
        stack.push((k, j));
    }
    Some(triangles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collinear_runs_are_never_one_triangle() {
        // A triangle with two extra points on side 0 (bit 0) and one on side 1 (bit 1).
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(3.0, 0.0, 0.0),
            DVec3::new(1.5, 1.5, 0.0),
            DVec3::new(0.0, 3.0, 0.0),
        ];
        let lines = [0b101, 0b001, 0b001, 0b011, 0b010, 0b110];
        let tris = triangulate(&p, &lines).unwrap();
        assert_eq!(tris.len(), 4);
        let mut area = 0.0;
        for t in &tris {
            assert_eq!(lines[t[0]] & lines[t[1]] & lines[t[2]], 0);
            let [a, b, c] = t.map(|i| p[i]);
            let z = (b - a).cross(c - a).z;
            assert!(z > 0.0, "orientation kept");
            area += 0.5 * z;
        }
        assert!((area - 4.5).abs() < 1e-12);
    }

    #[test]
    fn three_points_on_one_line_have_no_triangulation() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0];
        assert_eq!(triangulate(&p, &[1, 1, 1]), None);
    }
}
