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
use super::triangle_tree::TriangleTree;
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
    let chunks = chunks(&rows)?;
    let bound = half_width * half_width;
    let nearest = match backend {
        Backend::Cpu => distance_cpu(&tree, &chunks, bound),
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

/// Corners per chunk: a chunk's triangles are gathered once for all its corners.
const CHUNK_LEN: i32 = 16;

/// Most triangles gathered for one chunk (the kernel's private array); a chunk near more falls
/// back to one tree search per corner.
pub(crate) const GATHER_CAPACITY: usize = 256;

/// Corners `first + (i, 0, 0)` for `i < len`, whose results go to `out + i`: a piece of a row of
/// candidate corners, at most [`CHUNK_LEN`] long.
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

/// The candidate rows cut into chunks, in row order, results numbered consecutively.
fn chunks(rows: &Rows) -> Result<Vec<BandChunk>, RasterError> {
    let mut chunks = Vec::with_capacity(rows.runs.len());
    let mut out = 0usize;
    for (r, &[k, j]) in rows.keys.iter().enumerate() {
        for run in rows.of(r) {
            let mut i = run[0];
            while i <= run[1] {
                let len = (run[1] - i + 1).min(CHUNK_LEN);
                chunks.push(BandChunk {
                    first: [i, j, k],
                    len: len as u32,
                    out: u32::try_from(out).map_err(|_| RasterError::TooManyItems(out))?,
                });
                out += len as usize;
                i += len;
            }
        }
    }
    Ok(chunks)
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
pub static STATS: [std::sync::atomic::AtomicUsize; 4] =
    [const { std::sync::atomic::AtomicUsize::new(0) }; 4];

/// What a chunk keeps of each gathered triangle: the parts of its lower bound that do not depend
/// on the corner's x (structure of arrays, reused across chunks).
#[derive(Debug, Default)]
struct Gathered {
    slots: Vec<u32>,
    /// Squared distance from the chunk's line to the triangle's box across y and z.
    across: Vec<f32>,
    min_x: Vec<f32>,
    max_x: Vec<f32>,
    /// Signed distance of the chunk's first corner to the triangle's plane, and its change per
    /// step along x.
    plane: Vec<f32>,
    plane_step: Vec<f32>,
    bounds: Vec<f32>,
}

/// CPU twin of `kernels/distance.wgsl`: one closure call per kernel invocation (one chunk).
fn distance_cpu(tree: &TriangleTree, chunks: &[BandChunk], bound: f32) -> Vec<Nearest> {
    chunks
        .par_iter()
        .with_min_len(16)
        .map_init(Gathered::default, |scratch, chunk| {
            chunk_nearest(tree, chunk, bound, scratch)
        })
        .flat_map_iter(|(nearest, len)| nearest.into_iter().take(len))
        .collect()
}

/// The nearest triangle of each corner of `chunk` within `bound` (squared cells).
///
/// The triangles whose boxes lie within the band of the chunk's segment are gathered once. For
/// each corner a lower bound of every gathered triangle's distance is the larger of its box's and
/// its plane's. The previous corner's nearest triangle (for the first corner, the one with the
/// least bound) is tested first, which nearly always gives the final distance, and then only
/// triangles whose bound is below the best so far. Pruning by lower bounds cannot change the
/// minimum found.
fn chunk_nearest(
    tree: &TriangleTree,
    chunk: &BandChunk,
    bound: f32,
    g: &mut Gathered,
) -> ([Nearest; CHUNK_LEN as usize], usize) {
    let mut out = [Nearest {
        distance_squared: bound,
        slot: Nearest::NONE,
    }; CHUNK_LEN as usize];
    let lo = tree.local(chunk.first);
    let hi = [lo[0] + (chunk.len - 1) as f32, lo[1], lo[2]];
    g.slots.clear();
    let complete = tree.gather(lo, hi, bound, GATHER_CAPACITY, &mut g.slots);
    if !complete {
        for (i, result) in out.iter_mut().enumerate().take(chunk.len as usize) {
            let corner = [chunk.first[0] + i as i32, chunk.first[1], chunk.first[2]];
            let (distance_squared, slot) = tree.nearest(corner, bound, Nearest::NONE);
            *result = Nearest {
                distance_squared,
                slot,
            };
        }
        return (out, chunk.len as usize);
    }
    g.across.clear();
    g.min_x.clear();
    g.max_x.clear();
    g.plane.clear();
    g.plane_step.clear();
    for &slot in &g.slots {
        let b = &tree.boxes()[slot as usize];
        let gap = |a: usize| (b.min[a] - lo[a]).max(lo[a] - b.max[a]).max(0.0);
        g.across.push(gap(1) * gap(1) + gap(2) * gap(2));
        g.min_x.push(b.min[0]);
        g.max_x.push(b.max[0]);
        let t = &tree.triangles()[slot as usize];
        let p: [f32; 3] = std::array::from_fn(|k| (chunk.first[k] - t.base[k]) as f32);
        g.plane
            .push(t.normal[0] * p[0] + t.normal[1] * p[1] + t.normal[2] * p[2] - t.offset);
        g.plane_step.push(t.normal[0]);
    }
    g.bounds.resize(g.slots.len(), 0.0);
    let mut hint = None;
    STATS[0].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    STATS[1].fetch_add(g.slots.len(), std::sync::atomic::Ordering::Relaxed);
    STATS[2].fetch_add(chunk.len as usize, std::sync::atomic::Ordering::Relaxed);
    for (i, result) in out.iter_mut().enumerate().take(chunk.len as usize) {
        let x = lo[0] + i as f32;
        let step = i as f32;
        let corner = [chunk.first[0] + i as i32, chunk.first[1], chunk.first[2]];
        for ((lower, (&across, (&min_x, &max_x))), (&plane, &plane_step)) in g
            .bounds
            .iter_mut()
            .zip(g.across.iter().zip(g.min_x.iter().zip(&g.max_x)))
            .zip(g.plane.iter().zip(&g.plane_step))
        {
            let gap = max(max(min_x - x, x - max_x), 0.0);
            let to_plane = max((plane + plane_step * step).abs() - PLANE_SLACK, 0.0);
            *lower = max(across + gap * gap, to_plane * to_plane);
        }
        // The previous corner's nearest triangle, or else the one with the least bound.
        let first = match if std::env::var_os("ARGMIN").is_some() {
            None
        } else {
            hint
        } {
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
            let d = tree.triangles()[g.slots[first] as usize].distance_squared(corner);
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
                    STATS[3].fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let d = tree.triangles()[g.slots[k] as usize].distance_squared(corner);
                    if d < best {
                        best = d;
                        found = Some(k);
                    }
                }
            }
        }
        hint = found;
        let found = found.map_or(Nearest::NONE, |k| g.slots[k]);
        *result = Nearest {
            distance_squared: best,
            slot: found,
        };
    }
    (out, chunk.len as usize)
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
