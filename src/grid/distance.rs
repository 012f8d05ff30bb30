//! Signed distance at the grid corners near the surface: `Φ(M)` and `Φ(T)` of the paper (§4.3).
//!
//! Kernel: `kernels/distance.wgsl`. The magnitude is the exact distance to the nearest triangle
//! (Ericson's point–triangle test on offsets that are exact or rounded once, see
//! [`TriangleTree`]), searched in a bounding-volume tree pruned by the band's half-width; the sign
//! is the sweep's (negative inside), so it never disagrees with the inside/outside classification
//! of the same corner, which a pseudo-normal sign can near sharp features. Only corners within the
//! band are searched and stored: the candidates are the surface's footprint dilated by the band's
//! width ([`super::band`]), never a dense box.

use rayon::prelude::*;

use super::RasterError;
use super::band::{Rows, dilated_corners};
use super::cpu::distance_tiled::distance_tiled;
use super::gpu::GpuDistance;
use super::lattice::LatticeMesh;
use super::sparse::GridLine;
use super::sweep::Windings;
use super::triangle_tree::TriangleTree;
use crate::compute::{Backend, kernel_time};
use crate::kernels::shared::{BandChunk, BandTile, Nearest};

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
    let rows = dilated_corners(footprint, half_width);
    let bound = half_width * half_width;
    let nearest = kernel_time::timed(|| -> Result<_, RasterError> {
        Ok(match backend {
            Backend::Cpu => {
                let (chunks, tiles) = tiles(&rows, CPU_CHUNK_LEN)?;
                distance_tiled(&tree, &chunks, &tiles, bound)
            }
            Backend::Gpu(context) => {
                let chunks = chunks(&rows, GPU_CHUNK_LEN)?;
                let job = GpuDistance::upload(context, &tree, &chunks, bound)?;
                job.dispatch(context)?;
                job.read(context)?
            }
        })
    })?;
    Ok(sign_and_keep(
        mesh, &tree, &rows, &nearest, windings, half_width,
    ))
}

/// Corners of a CPU tile along x; tiles are aligned to multiples of it. Longer chunks share one
/// gather among more corners, which pays on the CPU, where the bounds are cached per chunk.
const CPU_CHUNK_LEN: i32 = 8;

/// Corners of a GPU chunk along x. The kernel recomputes every gathered triangle's bound at every
/// corner, and a longer chunk gathers more triangles: on lavapipe the benchmark's band takes
/// 2.27 s with chunks of 8 and 1.86 s with chunks of 4 (1.95 s with 2).
const GPU_CHUNK_LEN: i32 = 4;

/// Rows of a tile along y and along z.
pub(crate) const TILE_ROWS: i32 = 2;

/// The candidate rows cut into chunks at multiples of `chunk_len`, in row order, results numbered
/// in that order.
pub(crate) fn chunks(rows: &Rows, chunk_len: i32) -> Result<Vec<BandChunk>, RasterError> {
    let mut chunks = Vec::with_capacity(rows.runs.len());
    let mut out = 0usize;
    for (r, &[k, j]) in rows.keys.iter().enumerate() {
        for run in rows.of(r) {
            let mut i = run[0];
            while i <= run[1] {
                let end = ((i.div_euclid(chunk_len) + 1) * chunk_len - 1).min(run[1]);
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
    Ok(chunks)
}

/// The [`chunks`] grouped into tiles: the chunks in tile order, and the tiles.
pub(crate) fn tiles(
    rows: &Rows,
    chunk_len: i32,
) -> Result<(Vec<BandChunk>, Vec<BandTile>), RasterError> {
    let mut chunks = chunks(rows, chunk_len)?;
    let tile_of = |c: &BandChunk| {
        (
            c.first[2].div_euclid(TILE_ROWS),
            c.first[1].div_euclid(TILE_ROWS),
            c.first[0].div_euclid(chunk_len),
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

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::grid::cpu::distance::distance_cpu;
    use crate::grid::{GridFrame, edge_faces, footprint, rasterize};
    use crate::mesh::IndexedMesh;

    /// The variant finds the twin's minimum at every corner, bit for bit, whether a tile gathers
    /// all its triangles or falls back to one search per corner.
    #[test]
    fn the_tiled_variant_agrees_with_the_kernel_twin() {
        let meshes = [
            IndexedMesh::torus(1.0, 0.35, 48, 24),
            IndexedMesh::icosphere(Vec3::new(0.1, -0.2, 0.3), 0.8, 3),
        ];
        for (mesh, factor, half_width) in [(&meshes[0], 1.0, 3.0), (&meshes[1], 0.3, 9.0)] {
            let frame = GridFrame::for_mesh(mesh, factor).unwrap();
            let lattice = LatticeMesh::new(frame, mesh).unwrap();
            let crossings = rasterize(&Backend::Cpu, &lattice).unwrap();
            let cells = footprint(&lattice, &crossings, &edge_faces(&lattice));
            let rows = dilated_corners(&cells, half_width);
            let tree = TriangleTree::build(&lattice);
            let bound = half_width * half_width;
            for chunk_len in [1, 4, 8] {
                let (chunks, tiles) = tiles(&rows, chunk_len).unwrap();
                let twin = distance_cpu(&tree, &chunks, &tiles, bound);
                let variant = distance_tiled(&tree, &chunks, &tiles, bound);
                assert_eq!(twin.len(), variant.len());
                let differing: Vec<usize> = (0..twin.len())
                    .filter(|&i| {
                        twin[i].distance_squared.to_bits() != variant[i].distance_squared.to_bits()
                            || (twin[i].slot == Nearest::NONE) != (variant[i].slot == Nearest::NONE)
                    })
                    .collect();
                assert!(
                    differing.is_empty(),
                    "chunks of {chunk_len}: {} of {} corners differ, first {:?}",
                    differing.len(),
                    twin.len(),
                    &differing[..differing.len().min(8)]
                );
            }
        }
    }
}
