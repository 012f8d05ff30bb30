//! Table-driven marching cubes with one per-face resolution of ambiguous faces (see [`super::cube`]
//! and [`super::cases`]): the output is closed and 2-manifold for any input, noise included.
//!
//! The work is split by z so it runs in parallel yet gives bit-identical output for any thread
//! count: a counting pass numbers the crossed edges plane by plane (prefix sums over fixed-order
//! counts), then positions are written plane by plane and triangles slab by slab, each into its own
//! place in the output. No per-edge index array over the volume is ever built: a vertex's index is
//! recovered from the packed inside bits by a popcount rank.

use super::ScalarGrid;
use super::cases::cell_case;
use super::inside_bits::{InsideBits, bit, bit_pair, x_crossings};
use super::sparse::row_starts;
use crate::mesh::IndexedMesh;
use glam::Vec3;
use rayon::prelude::*;

/// Crossing parameters are clamped to `[T_MIN, 1 - T_MIN]` along their grid edge. No vertex then
/// sits on a grid corner, which is what keeps every triangle's area away from zero: three
/// crossings strictly inside three different edges of a cube are never collinear. The shift is at
/// most a thousandth of a cell, far below the interpolation error itself.
pub const T_MIN: f32 = 1e-3;

/// The isosurface `value = iso` of a grid, as a welded triangle mesh.
///
/// A corner is inside when `value < iso`; `value == iso` and NaN count as outside, as does every
/// corner on the grid's boundary, so the surface is always closed. There is one vertex per crossed
/// grid edge, placed by linear interpolation, and triangles are counter-clockwise seen from outside,
/// so normals point toward increasing value.
///
/// Vertices are numbered plane by plane (z), and within a plane: crossed x edges, crossed y edges,
/// then crossed z edges towards the next plane, each row by row (y) and along x. Triangles follow
/// cells in z, y, x order.
pub fn marching_cubes(grid: &ScalarGrid, iso: f32) -> IndexedMesh {
    let [nx, ny, nz] = grid.dims();
    if nx < 3 || ny < 3 || nz < 3 {
        return IndexedMesh::default();
    }
    let inside = InsideBits::new(grid, iso);
    let numbering = Numbering::new(&inside, grid.dims());
    let positions = positions(grid, iso, &inside, &numbering);
    let slabs: Vec<Vec<[u32; 3]>> = (0..nz - 1)
        .into_par_iter()
        .map(|k| slab_triangles(&inside, &numbering, ny, k))
        .collect();
    let triangles = slabs.concat();
    IndexedMesh::new(positions, triangles)
}

/// Global index of every crossed grid edge, stored as one rank per 64-corner word.
struct Numbering {
    /// Index of the first vertex of each plane; `nz + 1` entries.
    plane_base: Vec<u32>,
    /// Index, relative to its plane's base, of the first crossing in each word of each row, for
    /// x, y and z edges. Laid out like [`InsideBits`].
    x_rank: Vec<u32>,
    y_rank: Vec<u32>,
    z_rank: Vec<u32>,
}

impl Numbering {
    fn new(inside: &InsideBits, [_, ny, nz]: [usize; 3]) -> Self {
        let words = inside.words();
        let plane_len = ny * words;
        let mut x_rank = vec![0u32; nz * plane_len];
        let mut y_rank = vec![0u32; nz * plane_len];
        let mut z_rank = vec![0u32; nz * plane_len];
        let counts: Vec<u32> = x_rank
            .par_chunks_mut(plane_len)
            .zip(y_rank.par_chunks_mut(plane_len))
            .zip(z_rank.par_chunks_mut(plane_len))
            .enumerate()
            .map(|(k, ((xr, yr), zr))| {
                let mut next = 0u32;
                for j in 0..ny {
                    let row = inside.row(j, k);
                    for w in 0..words {
                        xr[j * words + w] = next;
                        next += x_crossings(row, w).count_ones();
                    }
                }
                for j in 0..ny - 1 {
                    let (row, up) = (inside.row(j, k), inside.row(j + 1, k));
                    for w in 0..words {
                        yr[j * words + w] = next;
                        next += (row[w] ^ up[w]).count_ones();
                    }
                }
                if k + 1 < nz {
                    for j in 0..ny {
                        let (row, above) = (inside.row(j, k), inside.row(j, k + 1));
                        for w in 0..words {
                            zr[j * words + w] = next;
                            next += (row[w] ^ above[w]).count_ones();
                        }
                    }
                }
                next
            })
            .collect();
        let plane_base = row_starts(counts);
        Self {
            plane_base,
            x_rank,
            y_rank,
            z_rank,
        }
    }

    fn vertex_count(&self) -> usize {
        self.plane_base.last().map_or(0, |&n| n as usize)
    }
}

/// Bits of `word` below bit `b`.
#[inline]
fn below(word: u64, b: usize) -> u32 {
    (word & ((1u64 << b) - 1)).count_ones()
}

/// Where along an edge the surface crosses, from the values at its lower end `a` and upper end
/// `b`, clamped to `[T_MIN, 1 - T_MIN]`. An outside value below `iso` (a boundary corner) or NaN is
/// read as `iso`; a non-finite ratio falls back to the middle.
#[inline]
fn crossing(a: f32, b: f32, a_inside: bool, iso: f32) -> f32 {
    let (a, b) = if a_inside {
        (a, b.max(iso))
    } else {
        (a.max(iso), b)
    };
    let t = (iso - a) / (b - a);
    let t = if t.is_finite() { t } else { 0.5 };
    t.clamp(T_MIN, 1.0 - T_MIN)
}

fn positions(grid: &ScalarGrid, iso: f32, inside: &InsideBits, numbering: &Numbering) -> Vec<Vec3> {
    let [nx, ny, nz] = grid.dims();
    let mut positions = vec![Vec3::ZERO; numbering.vertex_count()];
    let mut chunks = Vec::with_capacity(nz);
    let mut rest: &mut [Vec3] = &mut positions;
    for k in 0..nz {
        let len = (numbering.plane_base[k + 1] - numbering.plane_base[k]) as usize;
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(len);
        chunks.push(head);
        rest = tail;
    }
    let values = grid.values();
    let (origin, h) = (grid.origin(), grid.spacing());
    let words = inside.words();
    let at = |i: usize, j: usize, k: usize| values[i + nx * (j + ny * k)];
    chunks.into_par_iter().enumerate().for_each(|(k, out)| {
        let mut next = 0usize;
        let mut emit = |x: f32, y: f32, z: f32| {
            out[next] = origin + h * Vec3::new(x, y, z);
            next += 1;
        };
        for j in 0..ny {
            let row = inside.row(j, k);
            for w in 0..words {
                let mut bits = x_crossings(row, w);
                while bits != 0 {
                    let i = w * 64 + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let t = crossing(at(i, j, k), at(i + 1, j, k), bit(row, i), iso);
                    emit(i as f32 + t, j as f32, k as f32);
                }
            }
        }
        for j in 0..ny - 1 {
            let (row, up) = (inside.row(j, k), inside.row(j + 1, k));
            for w in 0..words {
                let mut bits = row[w] ^ up[w];
                while bits != 0 {
                    let i = w * 64 + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let t = crossing(at(i, j, k), at(i, j + 1, k), bit(row, i), iso);
                    emit(i as f32, j as f32 + t, k as f32);
                }
            }
        }
        if k + 1 < nz {
            for j in 0..ny {
                let (row, above) = (inside.row(j, k), inside.row(j, k + 1));
                for w in 0..words {
                    let mut bits = row[w] ^ above[w];
                    while bits != 0 {
                        let i = w * 64 + bits.trailing_zeros() as usize;
                        bits &= bits - 1;
                        let t = crossing(at(i, j, k), at(i, j, k + 1), bit(row, i), iso);
                        emit(i as f32, j as f32, k as f32 + t);
                    }
                }
            }
        }
    });
    positions
}

/// Triangles of the cells between planes `k` and `k + 1`.
fn slab_triangles(
    inside: &InsideBits,
    numbering: &Numbering,
    ny: usize,
    k: usize,
) -> Vec<[u32; 3]> {
    let words = inside.words();
    let mut triangles = Vec::new();
    for j in 0..ny - 1 {
        let rows = [
            inside.row(j, k),
            inside.row(j + 1, k),
            inside.row(j, k + 1),
            inside.row(j + 1, k + 1),
        ];
        for w in 0..words {
            let word = |r: &[u64], w: usize| r.get(w).copied().unwrap_or(0);
            let any = rows.iter().fold(0, |m, r| m | r[w]);
            let all = rows.iter().fold(!0, |m, r| m & r[w]);
            let any_next = rows.iter().fold(0, |m, r| m | word(r, w + 1));
            let all_next = rows.iter().fold(!0, |m, r| m & word(r, w + 1));
            // Cell i is mixed unless its 8 corners (bits i and i + 1 of the four rows) agree.
            // Bits from nx - 1 on are zero (border and padding), so no cell past the row's end
            // is ever mixed.
            let some_inside = any | (any >> 1) | (any_next << 63);
            let all_inside = all & ((all >> 1) | (all_next << 63));
            let mut mixed = some_inside & !all_inside;
            while mixed != 0 {
                let i = w * 64 + mixed.trailing_zeros() as usize;
                mixed &= mixed - 1;
                let config = bit_pair(rows[0], i)
                    | bit_pair(rows[1], i) << 2
                    | bit_pair(rows[2], i) << 4
                    | bit_pair(rows[3], i) << 6;
                let case = cell_case(config);
                let mut index = [0u32; 12];
                let mut mask = case.edge_mask;
                while mask != 0 {
                    let e = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    index[e] = edge_vertex(inside, numbering, e, i, j, k);
                }
                triangles.extend(
                    case.triangles
                        .iter()
                        .map(|t| t.map(|e| index[usize::from(e)])),
                );
            }
        }
    }
    triangles
}

/// Vertex index of cube edge `e` (numbering of [`super::cube`]) of cell `(i, j, k)`: the rank of
/// its crossing among the crossed edges of its plane and kind, plus the plane's base.
#[inline]
fn edge_vertex(
    inside: &InsideBits,
    numbering: &Numbering,
    e: usize,
    i: usize,
    j: usize,
    k: usize,
) -> u32 {
    let (a, b) = (e & 1, (e >> 1) & 1);
    let (plane, local) = match e / 4 {
        0 => {
            let (j, k) = (j + a, k + b);
            let row = inside.row(j, k);
            let w = i / 64;
            let rank = numbering.x_rank[inside.row_start(j, k) + w];
            (k, rank + below(x_crossings(row, w), i % 64))
        }
        1 => {
            let (i, k) = (i + a, k + b);
            let (row, up) = (inside.row(j, k), inside.row(j + 1, k));
            let w = i / 64;
            let rank = numbering.y_rank[inside.row_start(j, k) + w];
            (k, rank + below(row[w] ^ up[w], i % 64))
        }
        _ => {
            let (i, j) = (i + a, j + b);
            let (row, above) = (inside.row(j, k), inside.row(j, k + 1));
            let w = i / 64;
            let rank = numbering.z_rank[inside.row_start(j, k) + w];
            (k, rank + below(row[w] ^ above[w], i % 64))
        }
    };
    numbering.plane_base[plane] + local
}
