//! Numbering of a grid cell's corners, edges and faces, and the one rule that joins a face's edge
//! crossings into segments.
//!
//! Marching cubes and the topology stage (paper §4.3, thesis §3.4.6) both read cells through these
//! tables, so a face shared by two cells is always resolved the same way by both: that agreement is
//! what keeps every extracted surface closed (the "hole" failure of thesis §3.4.5 comes from two cells
//! resolving an ambiguous face differently).
//!
//! * Corner `c` (0..8) sits at offset `(c & 1, (c >> 1) & 1, (c >> 2) & 1)` from the cell's lowest
//!   corner: bit 0 is x, bit 1 is y, bit 2 is z.
//! * Edge `e` (0..12) runs along axis `e / 4` (0 = x, 1 = y, 2 = z) from its lower corner to its upper
//!   corner; `e % 4` holds the edge's offsets along the two other axes, the lower-numbered axis in
//!   bit 0. So edges 0..4 are the x edges at (y, z) = (0,0), (1,0), (0,1), (1,1); edges 4..8 the
//!   y edges at (x, z); edges 8..12 the z edges at (x, y).
//! * Face `f` (0..6) lies at coordinate `f % 2` of axis `f / 2`: −x, +x, −y, +y, −z, +z.
//!   [`FACE_CORNERS`] lists its corners counter-clockwise seen from outside the cell, and
//!   [`FACE_EDGES`]`[f][i]` is the edge from `FACE_CORNERS[f][i]` to `FACE_CORNERS[f][(i + 1) % 4]`.

/// Offset of each corner from the cell's lowest corner, in cells.
pub const CORNER_OFFSETS: [[usize; 3]; 8] = corner_offsets();

/// Lower and upper corner of each edge.
pub const EDGE_CORNERS: [[usize; 2]; 12] = edge_corners();

/// Corners of each face, counter-clockwise seen from outside the cell.
pub const FACE_CORNERS: [[usize; 4]; 6] = [
    [0, 4, 6, 2],
    [1, 3, 7, 5],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 2, 3, 1],
    [4, 5, 7, 6],
];

/// Edges of each face: `FACE_EDGES[f][i]` joins `FACE_CORNERS[f][i]` and `FACE_CORNERS[f][(i + 1) % 4]`.
pub const FACE_EDGES: [[usize; 4]; 6] = face_edges();

/// Axis (0 = x, 1 = y, 2 = z) along which edge `e` runs.
pub const fn edge_axis(e: usize) -> usize {
    e / 4
}

const fn corner_offsets() -> [[usize; 3]; 8] {
    let mut out = [[0; 3]; 8];
    let mut c = 0;
    while c < 8 {
        out[c] = [c & 1, (c >> 1) & 1, (c >> 2) & 1];
        c += 1;
    }
    out
}

const fn edge_corners() -> [[usize; 2]; 12] {
    let mut out = [[0; 2]; 12];
    let mut e = 0;
    while e < 12 {
        let axis = e / 4;
        let (low_bit, high_bit) = match axis {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let k = e % 4;
        let start = ((k & 1) << low_bit) | ((k >> 1) << high_bit);
        out[e] = [start, start | (1 << axis)];
        e += 1;
    }
    out
}

/// The edge joining two corners that differ along exactly one axis.
const fn edge_between(a: usize, b: usize) -> usize {
    let corners = edge_corners();
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    let mut e = 0;
    while e < 12 {
        if corners[e][0] == lo && corners[e][1] == hi {
            return e;
        }
        e += 1;
    }
    panic!("corners are not joined by a cell edge")
}

const fn face_edges() -> [[usize; 4]; 6] {
    let mut out = [[0; 4]; 6];
    let mut f = 0;
    while f < 6 {
        let mut i = 0;
        while i < 4 {
            out[f][i] = edge_between(FACE_CORNERS[f][i], FACE_CORNERS[f][(i + 1) % 4]);
            i += 1;
        }
        f += 1;
    }
    out
}

/// A directed segment across one face, from the crossing on the face's local edge `from` to the
/// crossing on its local edge `to` (positions 0..4 in [`FACE_EDGES`]`[f]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceSegment {
    pub from: usize,
    pub to: usize,
}

/// The segments of one face: none, one, or two on an ambiguous face.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceSegments {
    segments: [FaceSegment; 2],
    len: usize,
}

impl FaceSegments {
    pub fn as_slice(&self) -> &[FaceSegment] {
        &self.segments[..self.len]
    }
}

/// The per-face rule: how the crossings on a face's edges are joined, from the face's four corner
/// signs alone (`inside[i]` for `FACE_CORNERS[f][i]`).
///
/// Walking the face's edges counter-clockwise (seen from outside the cell), an edge entering the
/// inside is joined to the next edge leaving it. On an ambiguous face (two diagonally opposite inside
/// corners) this cuts each inside corner off on its own: inside corners are separated, outside
/// corners joined. The cell on the other side of the face walks the same edges in the opposite
/// order and so joins the same pairs, with every segment reversed, which is exactly what makes the
/// two cells' surface pieces meet with consistent orientation.
///
/// Segments run from the entering crossing to the leaving one; a surface patch bounded by them, with
/// triangles following the segments' direction, faces toward the outside (increasing value).
pub fn face_segments(inside: [bool; 4]) -> FaceSegments {
    let mut out = FaceSegments {
        segments: [FaceSegment { from: 0, to: 0 }; 2],
        len: 0,
    };
    for from in 0..4 {
        let enters = !inside[from] && inside[(from + 1) % 4];
        if !enters {
            continue;
        }
        let mut to = (from + 1) % 4;
        while !inside[to] || inside[(to + 1) % 4] {
            to = (to + 1) % 4;
        }
        out.segments[out.len] = FaceSegment { from, to };
        out.len += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn position(c: usize) -> [i32; 3] {
        CORNER_OFFSETS[c].map(|v| v as i32)
    }

    #[test]
    fn edges_join_corners_one_step_apart_along_their_axis() {
        for (e, [a, b]) in EDGE_CORNERS.iter().enumerate() {
            assert_eq!(b - a, 1 << edge_axis(e), "edge {e}");
            assert_eq!(
                a & (1 << edge_axis(e)),
                0,
                "edge {e} starts at its lower corner"
            );
        }
        let mut seen = [false; 12];
        for f in FACE_EDGES {
            for e in f {
                seen[e] = true;
            }
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn face_corners_are_counter_clockwise_from_outside() {
        for (f, corners) in FACE_CORNERS.iter().enumerate() {
            let axis = f / 2;
            let side = f % 2;
            let mut normal = [0i32; 3];
            normal[axis] = if side == 1 { 1 } else { -1 };
            for &c in corners {
                assert_eq!(CORNER_OFFSETS[c][axis], side, "face {f} corner {c}");
            }
            for i in 0..4 {
                let p = corners.map(position);
                let (a, b, c) = (p[i], p[(i + 1) % 4], p[(i + 2) % 4]);
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - b[0], c[1] - b[1], c[2] - b[2]];
                let cross = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ];
                let dot: i32 = (0..3).map(|k| cross[k] * normal[k]).sum();
                assert!(dot > 0, "face {f} turns clockwise at corner {i}");
            }
        }
    }

    #[test]
    fn every_crossing_gets_exactly_one_segment_and_inside_corners_stay_apart() {
        for mask in 0..16u8 {
            let inside = [0, 1, 2, 3].map(|i| mask & (1 << i) != 0);
            let crossings: Vec<usize> = (0..4)
                .filter(|&i| inside[i] != inside[(i + 1) % 4])
                .collect();
            let segs = face_segments(inside);
            assert_eq!(
                segs.as_slice().len() * 2,
                crossings.len(),
                "mask {mask:04b}"
            );
            let mut used = [0; 4];
            for s in segs.as_slice() {
                used[s.from] += 1;
                used[s.to] += 1;
                assert!(
                    !inside[s.from] && inside[(s.from + 1) % 4],
                    "segment starts entering"
                );
                assert!(
                    inside[s.to] && !inside[(s.to + 1) % 4],
                    "segment ends leaving"
                );
            }
            for &c in &crossings {
                assert_eq!(used[c], 1, "mask {mask:04b} edge {c}");
            }
            if mask == 0b0101 || mask == 0b1010 {
                for s in segs.as_slice() {
                    assert_eq!(
                        (s.from + 1) % 4,
                        s.to,
                        "ambiguous face cuts off single corners"
                    );
                }
            }
        }
    }

    #[test]
    fn neighbouring_cell_joins_the_same_pairs_in_reverse() {
        for mask in 0..16u8 {
            let inside = [0, 1, 2, 3].map(|i| mask & (1 << i) != 0);
            // The neighbour lists the same corners in the opposite order: local corner i of the
            // neighbour is corner (4 - i) % 4 here, and its edge i is edge (3 - i) here.
            let mirrored = [0, 3, 2, 1].map(|i| inside[i]);
            let here: Vec<(usize, usize)> = face_segments(inside)
                .as_slice()
                .iter()
                .map(|s| (s.from, s.to))
                .collect();
            let mut there: Vec<(usize, usize)> = face_segments(mirrored)
                .as_slice()
                .iter()
                .map(|s| (3 - s.to, 3 - s.from))
                .collect();
            let mut here_sorted = here.clone();
            here_sorted.sort_unstable();
            there.sort_unstable();
            assert_eq!(here_sorted, there, "mask {mask:04b}");
        }
    }
}
