//! The 256 marching-cubes cases, built once from the per-face rule in [`super::cube`].
//!
//! For each configuration of inside corners: (a) every face joins its crossings with
//! [`face_segments`]; (b) the segments are chained into closed loops (each crossing lies on two
//! faces, entering one and leaving the other, so it has exactly one incoming and one outgoing
//! segment and the loops are disjoint cycles); (c) each loop is triangulated.
//!
//! The triangulation is chosen per loop by dynamic programming over its diagonals, maximizing the
//! worst triangle's shape (then the sum of shapes) with crossings at edge midpoints. It never uses a
//! diagonal between two crossings of one ambiguous face: the cell across that face could pick the
//! same diagonal, and the edge would then have four triangles. Every other edge of the surface is
//! either a face segment (one triangle on each side of the face) or a diagonal private to one cell,
//! so the surface is closed and 2-manifold by construction.

use super::cube::{CORNER_OFFSETS, EDGE_CORNERS, FACE_CORNERS, FACE_EDGES, face_segments};
use std::sync::OnceLock;

/// One corner configuration: bit `c` of the index is set when corner `c` is inside.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CellCase {
    /// Bit `e` set when edge `e` is crossed.
    pub edge_mask: u16,
    /// Closed loops of crossed edges, each following its face segments' direction.
    pub loops: Vec<Vec<u8>>,
    /// Triangles as triples of crossed edges, counter-clockwise seen from outside the surface.
    pub triangles: Vec<[u8; 3]>,
}

/// The case for a corner configuration (bit `c` set when corner `c` is inside).
pub fn cell_case(config: u8) -> &'static CellCase {
    &table()[usize::from(config)]
}

fn table() -> &'static [CellCase; 256] {
    static TABLE: OnceLock<[CellCase; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|config| build_case(config as u8)))
}

fn build_case(config: u8) -> CellCase {
    let inside = |c: usize| config & (1 << c) != 0;
    let mut edge_mask = 0u16;
    for (e, [a, b]) in EDGE_CORNERS.iter().enumerate() {
        if inside(*a) != inside(*b) {
            edge_mask |= 1 << e;
        }
    }
    // next[e]: the crossing that the face segment leaving crossing `e` ends at.
    let mut next = [usize::MAX; 12];
    // Crossings of each pair of edges that lie on a common ambiguous face.
    let mut ambiguous = [0u16; 12];
    for f in 0..6 {
        let signs = FACE_CORNERS[f].map(inside);
        let segments = face_segments(signs);
        for s in segments.as_slice() {
            next[FACE_EDGES[f][s.from]] = FACE_EDGES[f][s.to];
        }
        if segments.as_slice().len() == 2 {
            let face_mask = FACE_EDGES[f].iter().fold(0u16, |m, &e| m | (1 << e));
            for &e in &FACE_EDGES[f] {
                ambiguous[e] |= face_mask;
            }
        }
    }
    let mut loops = Vec::new();
    let mut visited = 0u16;
    for start in 0..12 {
        if edge_mask & (1 << start) == 0 || visited & (1 << start) != 0 {
            continue;
        }
        let mut cycle = Vec::new();
        let mut e = start;
        while visited & (1 << e) == 0 {
            visited |= 1 << e;
            cycle.push(e as u8);
            e = next[e];
        }
        loops.push(cycle);
    }
    let triangles = loops
        .iter()
        .flat_map(|cycle| triangulate(cycle, &ambiguous))
        .collect();
    CellCase {
        edge_mask,
        loops,
        triangles,
    }
}

fn midpoint(e: u8) -> [f64; 3] {
    let [a, b] = EDGE_CORNERS[usize::from(e)];
    std::array::from_fn(|k| (CORNER_OFFSETS[a][k] + CORNER_OFFSETS[b][k]) as f64 * 0.5)
}

/// Shape of a triangle: 4√3·area / Σ edge², 1 for equilateral, 0 for degenerate.
fn shape(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let sub = |p: [f64; 3], q: [f64; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
    let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    let (u, v, w) = (sub(b, a), sub(c, b), sub(a, c));
    let cross = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let area = 0.5 * dot(cross, cross).sqrt();
    4.0 * 3f64.sqrt() * area / (dot(u, u) + dot(v, v) + dot(w, w))
}

/// Best triangulation of one loop (see the module docs), triangles following the loop's direction.
fn triangulate(cycle: &[u8], ambiguous: &[u16; 12]) -> Vec<[u8; 3]> {
    let n = cycle.len();
    let p: Vec<[f64; 3]> = cycle.iter().map(|&e| midpoint(e)).collect();
    let allowed = |i: usize, j: usize| {
        j == i + 1
            || (i == 0 && j == n - 1)
            || ambiguous[usize::from(cycle[i])] & (1 << cycle[j]) == 0
    };
    // best[i][j]: (worst shape, shape sum, split vertex) of the sub-polygon i..=j.
    let mut best = vec![vec![None::<(f64, f64, usize)>; n]; n];
    for i in 0..n.saturating_sub(1) {
        best[i][i + 1] = Some((f64::INFINITY, 0.0, i));
    }
    for len in 2..n {
        for i in 0..n - len {
            let j = i + len;
            if !allowed(i, j) {
                continue;
            }
            for k in i + 1..j {
                let (Some(left), Some(right)) = (best[i][k], best[k][j]) else {
                    continue;
                };
                let q = shape(p[i], p[k], p[j]);
                let candidate = (q.min(left.0).min(right.0), q + left.1 + right.1, k);
                let better = match best[i][j] {
                    None => true,
                    Some(current) => (candidate.0, candidate.1) > (current.0, current.1),
                };
                if better {
                    best[i][j] = Some(candidate);
                }
            }
        }
    }
    let mut triangles = Vec::with_capacity(n.saturating_sub(2));
    let mut stack = vec![(0, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let Some((_, _, k)) = best[i][j] else {
            continue;
        };
        triangles.push([cycle[i], cycle[k], cycle[j]]);
        stack.push((i, k));
        stack.push((k, j));
    }
    triangles
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn complementary_trivial_cases_are_empty() {
        assert!(cell_case(0).triangles.is_empty());
        assert!(cell_case(255).triangles.is_empty());
    }

    #[test]
    fn every_loop_is_fully_triangulated_as_a_disk() {
        for config in 0..=255u8 {
            let case = cell_case(config);
            let crossed = case.edge_mask.count_ones() as usize;
            let in_loops: usize = case.loops.iter().map(Vec::len).sum();
            assert_eq!(
                in_loops, crossed,
                "config {config}: every crossing in one loop"
            );
            let expected: usize = case.loops.iter().map(|l| l.len() - 2).sum();
            assert_eq!(case.triangles.len(), expected, "config {config}");
            // Within a cell the triangles of a loop form a disk whose boundary is the loop: each
            // loop side is used once (in the loop's direction), each diagonal twice (once each way).
            let mut directed: HashMap<(u8, u8), usize> = HashMap::new();
            for t in &case.triangles {
                for k in 0..3 {
                    *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
                }
            }
            for cycle in &case.loops {
                for i in 0..cycle.len() {
                    let (a, b) = (cycle[i], cycle[(i + 1) % cycle.len()]);
                    assert_eq!(
                        directed.get(&(a, b)),
                        Some(&1),
                        "config {config} side {a}->{b}"
                    );
                    assert_eq!(directed.get(&(b, a)), None, "config {config} side {b}->{a}");
                }
            }
            for (&(a, b), &count) in &directed {
                assert_eq!(
                    count, 1,
                    "config {config}: edge {a}->{b} used {count} times"
                );
            }
        }
    }

    #[test]
    fn triangles_face_from_inside_corners_toward_outside_corners() {
        for config in 1..255u8 {
            let inside = |c: usize| config & (1 << c) != 0;
            for t in &cell_case(config).triangles {
                let [a, b, c] = t.map(|e| glam::DVec3::from_array(midpoint(e)));
                let normal = (b - a).cross(c - a).to_array();
                // Each crossed edge points from its inside corner to its outside corner; the surface
                // must face along the sum of those directions at its three vertices.
                let mut outward = [0.0f64; 3];
                for &e in t {
                    let [lo, hi] = EDGE_CORNERS[usize::from(e)];
                    let sign = if inside(lo) { 1.0 } else { -1.0 };
                    outward[usize::from(e) / 4] += sign;
                    assert_ne!(inside(lo), inside(hi));
                }
                let dot: f64 = (0..3).map(|k| normal[k] * outward[k]).sum();
                assert!(dot > 0.0, "config {config:08b} triangle {t:?} faces inward");
            }
        }
    }

    #[test]
    fn no_diagonal_joins_two_crossings_of_an_ambiguous_face() {
        for config in 0..=255u8 {
            let inside = |c: usize| config & (1 << c) != 0;
            let case = cell_case(config);
            for f in 0..6 {
                if face_segments(FACE_CORNERS[f].map(inside)).as_slice().len() != 2 {
                    continue;
                }
                let on_face = |e: u8| FACE_EDGES[f].contains(&usize::from(e));
                for t in &case.triangles {
                    for k in 0..3 {
                        let (a, b) = (t[k], t[(k + 1) % 3]);
                        if on_face(a) && on_face(b) {
                            let is_side = case.loops.iter().any(|l| {
                                (0..l.len()).any(|i| {
                                    let (x, y) = (l[i], l[(i + 1) % l.len()]);
                                    (x, y) == (a, b) || (x, y) == (b, a)
                                })
                            });
                            assert!(is_side, "config {config:08b}: diagonal {a}-{b} on face {f}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn complement_has_the_same_crossings() {
        for config in 0..=255u8 {
            assert_eq!(cell_case(config).edge_mask, cell_case(!config).edge_mask);
        }
    }
}
