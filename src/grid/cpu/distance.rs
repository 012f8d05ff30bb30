//! CPU twin of `kernels/distance.wgsl`: the nearest triangle within the band of every candidate
//! corner, one closure call per tile with the kernel's steps and names.
//!
//! The kernel gathers the triangles whose boxes lie within the band of the tile's box (the loop
//! [`TriangleTree::gather`] runs here), then for each corner tests the previous corner's nearest
//! triangle first (for a chunk's first corner, the one with the least bound) and afterwards every
//! gathered triangle whose lower bound is below the best so far. A tile near more than
//! [`GATHER_CAPACITY`] triangles searches the tree once per corner instead (the kernel's `search`,
//! [`TriangleTree::nearest`] here). The CPU backend runs the tiled variant
//! (`distance_tiled.rs`), which finds the same minimum with tighter bounds; the tests of
//! `grid/distance.rs` compare the two.

use rayon::prelude::*;

use crate::grid::triangle_tree::TriangleTree;
use crate::kernels::shared::{BandChunk, BandTile, GATHER_CAPACITY, Nearest, PLANE_SLACK};

/// The nearest triangle of every corner of `chunks`, at its chunk's output offset.
pub fn distance_cpu(
    tree: &TriangleTree,
    chunks: &[BandChunk],
    tiles: &[BandTile],
    bound: f32,
) -> Vec<Nearest> {
    per_tile(chunks, tiles, bound, || (), |_, own| main(tree, own, bound))
}

/// Runs `body` once per tile, on the tile's own chunks with a scratch value from `init`, and
/// writes each tile's results, chunk by chunk in tile order, at its chunks' output offsets.
pub(in crate::grid) fn per_tile<S>(
    chunks: &[BandChunk],
    tiles: &[BandTile],
    bound: f32,
    init: impl Fn() -> S + Sync + Send,
    body: impl Fn(&mut S, &[BandChunk]) -> Vec<Nearest> + Sync + Send,
) -> Vec<Nearest> {
    let per_tile: Vec<Vec<Nearest>> = tiles
        .par_iter()
        .map_init(&init, |scratch, tile| {
            body(
                scratch,
                &chunks[tile.first as usize..(tile.first + tile.count) as usize],
            )
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

/// Corner `i` of chunk `c`.
fn corner_of(c: &BandChunk, i: u32) -> [i32; 3] {
    [c.first[0] + i as i32, c.first[1], c.first[2]]
}

/// A lower bound of the squared distance from `corner` (at `p` from the tree's base) to the
/// triangle in `slot`: the larger of its box's and its plane's, the plane's reduced by
/// [`PLANE_SLACK`] for rounding.
fn lower_bound(tree: &TriangleTree, slot: u32, corner: [i32; 3], p: [f32; 3]) -> f32 {
    let to_box = tree.boxes()[slot as usize].distance_squared(p);
    let t = &tree.triangles()[slot as usize];
    let local: [f32; 3] = std::array::from_fn(|k| (corner[k] - t.base[k]) as f32);
    let along = t.normal[0] * local[0] + t.normal[1] * local[1] + t.normal[2] * local[2];
    let to_plane = ((along - t.offset).abs() - PLANE_SLACK).max(0.0);
    to_box.max(to_plane * to_plane)
}

/// The body of one kernel invocation: the results of one tile's corners, chunk by chunk.
fn main(tree: &TriangleTree, own: &[BandChunk], bound: f32) -> Vec<Nearest> {
    let mut first_corner = [i32::MAX; 3];
    let mut last_corner = [i32::MIN; 3];
    for c in own {
        let last = corner_of(c, c.len - 1);
        for a in 0..3 {
            first_corner[a] = first_corner[a].min(c.first[a]);
            last_corner[a] = last_corner[a].max(last[a]);
        }
    }
    let (lo, hi) = (tree.local(first_corner), tree.local(last_corner));
    let mut slots = Vec::with_capacity(GATHER_CAPACITY);
    let complete = tree.gather(lo, hi, bound, GATHER_CAPACITY, &mut slots);
    let corners = own
        .iter()
        .flat_map(|c| (0..c.len).map(move |i| (i, corner_of(c, i))));
    if !complete {
        return corners
            .map(|(_, corner)| {
                let (distance_squared, slot) = tree.nearest(corner, bound, Nearest::NONE);
                Nearest {
                    distance_squared,
                    slot,
                }
            })
            .collect();
    }
    let mut hint = None;
    corners
        .map(|(i, corner)| {
            if i == 0 {
                hint = None;
            }
            let p = tree.local(corner);
            let bounds: Vec<f32> = slots
                .iter()
                .map(|&s| lower_bound(tree, s, corner, p))
                .collect();
            // The previous corner's nearest triangle, or else the one with the least bound.
            let start_k = hint.unwrap_or_else(|| {
                let mut least = f32::INFINITY;
                let mut start_k = 0;
                for (k, &lower) in bounds.iter().enumerate() {
                    if lower < least {
                        least = lower;
                        start_k = k;
                    }
                }
                start_k
            });
            let mut best = bound;
            let mut found = None;
            let order = std::iter::once(start_k).chain((0..slots.len()).filter(|&k| k != start_k));
            for k in order.filter(|&k| k < slots.len()) {
                if bounds[k] < best {
                    let d = tree.triangles()[slots[k] as usize].distance_squared(corner);
                    if d < best {
                        best = d;
                        found = Some(k);
                    }
                }
            }
            hint = found;
            Nearest {
                distance_squared: best,
                slot: found.map_or(Nearest::NONE, |k| slots[k]),
            }
        })
        .collect()
}
