//! Signed distance at the grid corners near the surface: `Φ(M)` and `Φ(T)` of the paper (§4.3).
//!
//! Kernel: `kernels/distance.wgsl`. The magnitude is the exact distance to the nearest triangle
//! (Ericson's point–triangle test on offsets that are exact or rounded once, see
//! [`TriangleTree`]), searched in a bounding-volume tree pruned by the band's half-width; the sign
//! is the sweep's (negative inside), so it never disagrees with the inside/outside classification
//! of the same corner, which a pseudo-normal sign can near sharp features. Only corners within the
//! band are searched and stored: the candidates are the surface's footprint dilated by the band's
//! width ([`super::band`]), never a dense box.

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

use super::RasterError;
use super::band::{Rows, dilated_corners};
use super::distance_gpu::GpuDistance;
use super::lattice::LatticeMesh;
use super::sparse::GridLine;
use super::sweep::Windings;
use super::triangle_tree::{TriangleBox, TriangleTree};
use crate::compute::Backend;
use crate::compute::registry::{GpuStructLayout, SharedWgsl};

/// The nearest triangle slot of one corner and its squared distance in cells; `slot` is
/// [`Nearest::NONE`] when no triangle lies within the band.
///
/// Mirrors `struct Nearest` in `kernels/shared/distance.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Nearest {
    pub distance_squared: f32,
    pub slot: u32,
}

impl Nearest {
    pub const NONE: u32 = u32::MAX;

    /// The layout the WGSL mirror must have, checked against naga in `tests/kernels_validate.rs`.
    pub const LAYOUT: GpuStructLayout = GpuStructLayout {
        name: "Nearest",
        wgsl: &SharedWgsl::DISTANCE,
        size: size_of::<Self>(),
        members: &[
            (
                "distance_squared",
                core::mem::offset_of!(Self, distance_squared),
            ),
            ("slot", core::mem::offset_of!(Self, slot)),
        ],
    };
}

/// Signed distances at every corner within `half_width` cells of the surface.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NarrowBand {
    half_width: f32,
    corners: Vec<[i32; 3]>,
    values: Vec<f32>,
    nearest: Vec<u32>,
}

impl NarrowBand {
    /// Half-width of the band, in cells.
    pub fn half_width(&self) -> f32 {
        self.half_width
    }

    /// The corners in the band, sorted by `(z, y, x)`.
    pub fn corners(&self) -> &[[i32; 3]] {
        &self.corners
    }

    /// Signed distance of each corner in world units: negative inside.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The mesh triangle nearest to each corner.
    pub fn nearest(&self) -> &[u32] {
        &self.nearest
    }

    pub fn len(&self) -> usize {
        self.corners.len()
    }

    pub fn is_empty(&self) -> bool {
        self.corners.is_empty()
    }

    /// Signed distance at `corner` in world units, when it lies in the band.
    pub fn get(&self, corner: [i32; 3]) -> Option<f32> {
        let key = |c: &[i32; 3]| [c[2], c[1], c[0]];
        self.corners
            .binary_search_by_key(&key(&corner), key)
            .ok()
            .map(|i| self.values[i])
    }
}

/// Signed distance at every corner within `half_width` cells of `mesh`'s surface.
///
/// `footprint` is the set of cells the surface meets ([`super::footprint`]) and `windings` the
/// sweep of the same mesh, which gives the sign. Fails when `half_width` is not a positive number,
/// or when the GPU backend cannot run the kernel.
pub fn signed_distance(
    backend: &Backend,
    mesh: &LatticeMesh,
    footprint: &[[i32; 3]],
    windings: &Windings,
    half_width: f32,
) -> Result<NarrowBand, RasterError> {
    if !(half_width.is_finite() && half_width > 0.0) {
        return Err(RasterError::Band(half_width));
    }
    let tree = TriangleTree::build(mesh);
    if tree.nodes().is_empty() {
        return Ok(NarrowBand {
            half_width,
            ..NarrowBand::default()
        });
    }
    let rows = dilated_corners(footprint, half_width.floor() as i32);
    let (chunks, tiles) = tiles(&rows)?;
    let bound = half_width * half_width;
    let nearest = match backend {
        Backend::Cpu => distance_cpu(&tree, &chunks, &tiles, bound),
        Backend::Gpu(context) => {
            let job = GpuDistance::upload(context, &tree, &chunks, bound)?;
            job.dispatch(context)?;
            job.read(context)?
        }
    };
    Ok(sign_and_keep(
        mesh, &tree, &rows, &nearest, windings, half_width,
    ))
}

/// Corners of a tile along x; tiles are aligned to multiples of it.
const CHUNK_LEN: i32 = 4;

/// Rows of a tile along y and along z.
const TILE_ROWS: i32 = 2;

/// Most triangles gathered for one tile (the kernel's private array); a tile near more falls
/// back to one tree search per corner.
pub(crate) const GATHER_CAPACITY: usize = 256;

/// Corners `first + (i, 0, 0)` for `i < len`, whose results go to `out + i`: the part of one row of
/// candidate corners that lies in one tile.
///
/// Mirrors `struct BandChunk` in `kernels/shared/distance.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct BandChunk {
    pub first: [i32; 3],
    pub len: u32,
    pub out: u32,
}

impl BandChunk {
    /// The layout the WGSL mirror must have, checked against naga in `tests/kernels_validate.rs`.
    pub const LAYOUT: GpuStructLayout = GpuStructLayout {
        name: "BandChunk",
        wgsl: &SharedWgsl::DISTANCE,
        size: size_of::<Self>(),
        members: &[
            ("first", core::mem::offset_of!(Self, first)),
            ("len", core::mem::offset_of!(Self, len)),
            ("out", core::mem::offset_of!(Self, out)),
        ],
    };
}

/// The chunks `first .. first + count` (in tile order) of one tile: up to [`CHUNK_LEN`] ×
/// [`TILE_ROWS`] × [`TILE_ROWS`] candidate corners whose triangles are gathered once.
///
/// Mirrors `struct BandTile` in `kernels/shared/distance.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct BandTile {
    pub first: u32,
    pub count: u32,
}

impl BandTile {
    /// The layout the WGSL mirror must have, checked against naga in `tests/kernels_validate.rs`.
    pub const LAYOUT: GpuStructLayout = GpuStructLayout {
        name: "BandTile",
        wgsl: &SharedWgsl::DISTANCE,
        size: size_of::<Self>(),
        members: &[
            ("first", core::mem::offset_of!(Self, first)),
            ("count", core::mem::offset_of!(Self, count)),
        ],
    };
}

/// The candidate rows cut into chunks at multiples of [`CHUNK_LEN`], results numbered in row
/// order, then grouped into tiles (chunks in tile order, and the tiles).
pub(crate) fn tiles(rows: &Rows) -> Result<(Vec<BandChunk>, Vec<BandTile>), RasterError> {
    let mut chunks = Vec::with_capacity(rows.runs.len());
    let mut out = 0usize;
    for (r, &[k, j]) in rows.keys.iter().enumerate() {
        for run in rows.of(r) {
            let mut i = run[0];
            while i <= run[1] {
                let end = ((i.div_euclid(CHUNK_LEN) + 1) * CHUNK_LEN - 1).min(run[1]);
                let len = end - i + 1;
                chunks.push(BandChunk {
                    first: [i, j, k],
                    len: len as u32,
                    out: u32::try_from(out).map_err(|_| RasterError::TooManyItems(out))?,
                });
                out += len as usize;
                i = end + 1;
            }
        }
    }
    let tile_of = |c: &BandChunk| {
        (
            c.first[2].div_euclid(TILE_ROWS),
            c.first[1].div_euclid(TILE_ROWS),
            c.first[0].div_euclid(CHUNK_LEN),
        )
    };
    chunks.par_sort_by_key(tile_of);
    let mut tiles: Vec<BandTile> = Vec::new();
    for (n, c) in chunks.iter().enumerate() {
        match tiles.last_mut() {
            Some(t) if tile_of(&chunks[t.first as usize]) == tile_of(c) => t.count += 1,
            _ => tiles.push(BandTile {
                first: n as u32,
                count: 1,
            }),
        }
    }
    Ok((chunks, tiles))
}

/// Bounds tested together before any is looked at alone.
const SKIP_BLOCK: usize = 8;

/// The larger of two numbers, as one vector instruction (no NaN can occur here).
fn max(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// Allowance for rounding in the plane lower bound, in cells: the bound only prunes, so making it
/// smaller can cost time but never the nearest triangle.
const PLANE_SLACK: f32 = 1e-4;

/// What a tile keeps of each gathered triangle (structure of arrays, reused across tiles): its
/// box, and its plane's signed distance at the tile's lowest corner with the plane's normal.
#[derive(Debug, Default)]
struct Gathered {
    slots: Vec<u32>,
    boxes: Vec<TriangleBox>,
    plane: Vec<f32>,
    normal: Vec<[f32; 3]>,
    /// Per chunk, of the triangles near its segment: their slots, squared distance from the
    /// chunk's line to the box across y and z, the plane's signed distance at the chunk's first
    /// corner, the box along x and the normal's x component.
    near: Vec<u32>,
    across: Vec<f32>,
    plane_at: Vec<f32>,
    box_x: Vec<[f32; 2]>,
    normal_x: Vec<f32>,
    bounds: Vec<f32>,
}

/// CPU twin of `kernels/distance.wgsl`: one closure call per kernel invocation (one tile); the
/// results are then placed at their chunks' output offsets. Here a tile holds up to
/// [`TILE_ROWS`]² chunks sharing one gather, and the lower bounds are cached per tile and chunk;
/// the GPU runs one chunk per tile and recomputes the bounds ([`GpuDistance`] says why). Both
/// find the least distance within the band, so they agree up to rounding.
fn distance_cpu(
    tree: &TriangleTree,
    chunks: &[BandChunk],
    tiles: &[BandTile],
    bound: f32,
) -> Vec<Nearest> {
    let per_tile: Vec<Vec<Nearest>> = tiles
        .par_iter()
        .map_init(Gathered::default, |scratch, tile| {
            let own = &chunks[tile.first as usize..(tile.first + tile.count) as usize];
            tile_nearest(tree, own, bound, scratch)
        })
        .collect();
    let total = chunks.iter().map(|c| c.len as usize).sum();
    let mut nearest = vec![
        Nearest {
            distance_squared: bound,
            slot: Nearest::NONE,
        };
        total
    ];
    for (tile, results) in tiles.iter().zip(per_tile) {
        let own = &chunks[tile.first as usize..(tile.first + tile.count) as usize];
        let mut results = results.into_iter();
        for chunk in own {
            let out = chunk.out as usize;
            for (slot, r) in nearest[out..out + chunk.len as usize]
                .iter_mut()
                .zip(&mut results)
            {
                *slot = r;
            }
        }
    }
    nearest
}

/// The nearest triangle within `bound` (squared cells) of each corner of the chunks of one tile,
/// chunk after chunk.
///
/// The triangles whose boxes lie within the band of the tile's box are gathered once. For each
/// corner a lower bound of every gathered triangle's distance is the larger of its box's and its
/// plane's. The previous corner's nearest triangle (for a chunk's first corner, the one with the
/// least bound) is tested first, which nearly always gives the final distance, and then only
/// triangles whose bound is below the best so far. Pruning by lower bounds cannot change the
/// minimum found.
fn tile_nearest(
    tree: &TriangleTree,
    chunks: &[BandChunk],
    bound: f32,
    g: &mut Gathered,
) -> Vec<Nearest> {
    let mut out = Vec::with_capacity(chunks.iter().map(|c| c.len as usize).sum());
    let mut first_corner = [i32::MAX; 3];
    let mut last_corner = [i32::MIN; 3];
    for c in chunks {
        for a in 0..3 {
            first_corner[a] = first_corner[a].min(c.first[a]);
            last_corner[a] =
                last_corner[a].max(c.first[a] + if a == 0 { c.len as i32 - 1 } else { 0 });
        }
    }
    let lo = tree.local(first_corner);
    let hi = tree.local(last_corner);
    g.slots.clear();
    if !tree.gather(lo, hi, bound, GATHER_CAPACITY, &mut g.slots) {
        for c in chunks {
            for i in 0..c.len as i32 {
                let corner = [c.first[0] + i, c.first[1], c.first[2]];
                let (distance_squared, slot) = tree.nearest(corner, bound, Nearest::NONE);
                out.push(Nearest {
                    distance_squared,
                    slot,
                });
            }
        }
        return out;
    }
    g.boxes.clear();
    g.plane.clear();
    g.normal.clear();
    for &slot in &g.slots {
        g.boxes.push(tree.boxes()[slot as usize]);
        let t = &tree.triangles()[slot as usize];
        let p: [f32; 3] = std::array::from_fn(|k| (first_corner[k] - t.base[k]) as f32);
        g.plane
            .push(t.normal[0] * p[0] + t.normal[1] * p[1] + t.normal[2] * p[2] - t.offset);
        g.normal.push(t.normal);
    }
    for c in chunks {
        let start = tree.local(c.first);
        let offset: [f32; 3] = std::array::from_fn(|k| (c.first[k] - first_corner[k]) as f32);
        let last_x = start[0] + (c.len - 1) as f32;
        // The triangles near the chunk's segment: a box farther than the band from all of the
        // segment holds no corner's nearest triangle.
        g.near.clear();
        g.across.clear();
        g.plane_at.clear();
        g.box_x.clear();
        g.normal_x.clear();
        for (k, ((b, &plane), n)) in g.boxes.iter().zip(&g.plane).zip(&g.normal).enumerate() {
            let gap = |a: usize| max(max(b.min[a] - start[a], start[a] - b.max[a]), 0.0);
            let across = gap(1) * gap(1) + gap(2) * gap(2);
            let along = max(max(b.min[0] - last_x, start[0] - b.max[0]), 0.0);
            if across + along * along < bound {
                g.near.push(g.slots[k]);
                g.across.push(across);
                g.plane_at
                    .push(plane + n[0] * offset[0] + n[1] * offset[1] + n[2] * offset[2]);
                g.box_x.push([b.min[0], b.max[0]]);
                g.normal_x.push(n[0]);
            }
        }
        g.bounds.resize(g.near.len(), 0.0);
        let mut hint = None;
        for i in 0..c.len as i32 {
            let x = start[0] + i as f32;
            let step = i as f32;
            let corner = [c.first[0] + i, c.first[1], c.first[2]];
            for ((lower, (&across, b)), (&plane, &n)) in g
                .bounds
                .iter_mut()
                .zip(g.across.iter().zip(&g.box_x))
                .zip(g.plane_at.iter().zip(&g.normal_x))
            {
                let gap = max(max(b[0] - x, x - b[1]), 0.0);
                let to_plane = max((plane + n * step).abs() - PLANE_SLACK, 0.0);
                *lower = max(across + gap * gap, to_plane * to_plane);
            }
            // The previous corner's nearest triangle, or else the one with the least bound.
            let first = match hint {
                Some(k) => k,
                None => {
                    let mut first = 0;
                    let mut least = f32::INFINITY;
                    for (k, &lower) in g.bounds.iter().enumerate() {
                        if lower < least {
                            least = lower;
                            first = k;
                        }
                    }
                    first
                }
            };
            let mut best = bound;
            let mut found = None;
            if g.bounds.get(first).is_some_and(|&lower| lower < best) {
                let d = tree.triangles()[g.near[first] as usize].distance_squared(corner);
                if d < best {
                    best = d;
                    found = Some(first);
                }
            }
            // Blocks whose bounds all reach the best so far are skipped with one vector test.
            for (b, block) in g.bounds.chunks(SKIP_BLOCK).enumerate() {
                if !block.iter().fold(false, |any, &lower| any | (lower < best)) {
                    continue;
                }
                for (j, &lower) in block.iter().enumerate() {
                    let k = b * SKIP_BLOCK + j;
                    if lower < best && k != first {
                        let d = tree.triangles()[g.near[k] as usize].distance_squared(corner);
                        if d < best {
                            best = d;
                            found = Some(k);
                        }
                    }
                }
            }
            hint = found;
            out.push(Nearest {
                distance_squared: best,
                slot: found.map_or(Nearest::NONE, |k| g.near[k]),
            });
        }
    }
    out
}

/// Keeps the candidates within the band, in row order, with the sweep's sign.
fn sign_and_keep(
    mesh: &LatticeMesh,
    tree: &TriangleTree,
    rows: &Rows,
    nearest: &[Nearest],
    windings: &Windings,
    half_width: f32,
) -> NarrowBand {
    let spacing = mesh.frame().spacing();
    let mut offsets = Vec::with_capacity(rows.keys.len() + 1);
    let mut n = 0usize;
    for r in 0..rows.keys.len() {
        offsets.push(n);
        n += rows
            .of(r)
            .iter()
            .map(|run| (run[1] - run[0] + 1) as usize)
            .sum::<usize>();
    }
    offsets.push(n);
    let kept: Vec<Vec<([i32; 3], f32, u32)>> = (0..rows.keys.len())
        .into_par_iter()
        .with_min_len(8)
        .map(|r| {
            let [k, j] = rows.keys[r];
            let runs = windings.on_line(&GridLine {
                axis: 0,
                at: [j, k],
            });
            let mut next_run = 0;
            let mut winding = 0;
            let corners = rows.of(r).iter().flat_map(|run| run[0]..=run[1]);
            corners
                .zip(&nearest[offsets[r]..offsets[r + 1]])
                .filter_map(|(i, near)| {
                    while next_run < runs.len() && runs[next_run].start <= i {
                        winding = runs[next_run].winding;
                        next_run += 1;
                    }
                    if near.slot == Nearest::NONE {
                        return None;
                    }
                    let d = near.distance_squared.sqrt();
                    if d > half_width {
                        return None;
                    }
                    let signed = if winding >= 1 { -d } else { d };
                    let id = tree.triangles()[near.slot as usize].id;
                    Some(([i, j, k], signed * spacing, id))
                })
                .collect()
        })
        .collect();
    let total = kept.iter().map(Vec::len).sum();
    let mut band = NarrowBand {
        half_width,
        corners: Vec::with_capacity(total),
        values: Vec::with_capacity(total),
        nearest: Vec::with_capacity(total),
    };
    for (corner, value, id) in kept.into_iter().flatten() {
        band.corners.push(corner);
        band.values.push(value);
        band.nearest.push(id);
    }
    band
}
