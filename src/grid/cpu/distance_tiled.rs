//! A variant of the distance twin (`distance.rs`, the CPU twin of `kernels/distance.wgsl`) that
//! the CPU backend runs: the nearest triangle within the band of every candidate corner (paper
//! §4.3, the magnitude of `Φ`), with the kernel's steps but not its shape.
//!
//! Like the kernel it gathers the triangles near a tile once and then, corner by corner, tests the
//! previous corner's nearest triangle first and afterwards only the triangles whose lower bound is
//! below the best distance so far. Pruning by lower bounds cannot change the minimum found, so it
//! finds the twin's minimum whatever bounds it uses (its tests compare the two bit for bit). The
//! GPU keeps one chunk per tile and recomputes the box and plane bounds (`gpu/distance.rs` says
//! why); here a tile holds up to `TILE_ROWS`² chunks sharing
//! one gather, and the bounds are tighter (a disk around each triangle) and computed
//! [`SKIP_BLOCK`] triangles at a time as vector instructions, as is the exact test of a block with
//! a triangle below the best distance (the scalar test's branches mispredict; the vector one gives
//! the same bits without them).

use wide::f32x8;

use super::distance::per_tile;
use crate::grid::triangle_tree::{TriangleTree, point_triangle_distance_squared};
use crate::kernels::shared::{BandChunk, BandTile, Nearest, PLANE_SLACK, TreeTriangle};

/// Most triangles gathered for one tile; a tile near more searches the tree once per corner. The
/// kernel's private array holds 256 (`kernels/shared/distance.wgsl`); here the vector bounds and
/// tests make a longer list cheaper than that fallback (benchmark band, one thread: 213 ms with
/// 256, 200 ms with 384, 201 ms with 512).
const GATHER_CAPACITY: usize = 384;

/// Triangles whose bounds are computed and tested together: the lists are kept in blocks of this
/// many, padded with entries whose bound is infinite, so each operation of a bound runs on a whole
/// block (one vector instruction) and a block whose least bound reaches the best distance so far
/// is skipped with one comparison.
const SKIP_BLOCK: usize = 8;

/// The smaller of two numbers, as one vector instruction (no NaN can occur here).
fn min(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}

/// Allowance for rounding in the squared in-plane distance of the disk bound, in squared cells:
/// its terms are squared offsets of a few cells, each rounded a few times in f32 (about 1e-5), so
/// this keeps the bound below the true distance with a wide margin.
const LATERAL_SLACK: f32 = 1e-3;

/// [`SKIP_BLOCK`] gathered triangles of a tile, one array per quantity: their boxes, their
/// planes' signed distance at the tile's lowest corner and their normals, and the disks that hold
/// them (centroid from the tile's lowest corner, radius). Unused entries have empty boxes.
#[derive(Debug, Clone, Copy)]
struct GatherBlock {
    slot: [u32; SKIP_BLOCK],
    min: [[f32; SKIP_BLOCK]; 3],
    max: [[f32; SKIP_BLOCK]; 3],
    plane: [f32; SKIP_BLOCK],
    normal: [[f32; SKIP_BLOCK]; 3],
    centre: [[f32; SKIP_BLOCK]; 3],
    radius: [f32; SKIP_BLOCK],
}

impl GatherBlock {
    const EMPTY: Self = Self {
        slot: [Nearest::NONE; SKIP_BLOCK],
        min: [[f32::INFINITY; SKIP_BLOCK]; 3],
        max: [[f32::NEG_INFINITY; SKIP_BLOCK]; 3],
        plane: [0.0; SKIP_BLOCK],
        normal: [[0.0; SKIP_BLOCK]; 3],
        centre: [[0.0; SKIP_BLOCK]; 3],
        radius: [0.0; SKIP_BLOCK],
    };
}

/// [`SKIP_BLOCK`] triangles near one chunk's segment, one array per quantity so that each
/// operation of [`NearBlock::bounds`] is one vector instruction: the squared distance from the
/// chunk's line to the box across y and z, the box along x (cells from the tree's base), the
/// plane's signed distance at the chunk's first corner and the normal's x component, the squared
/// distance from that corner to the centroid and the centroid's offset along x from it, and the
/// disk's radius. Unused entries have an infinite bound.
#[derive(Debug, Clone, Copy)]
struct NearBlock {
    across: [f32; SKIP_BLOCK],
    box_lo: [f32; SKIP_BLOCK],
    box_hi: [f32; SKIP_BLOCK],
    plane: [f32; SKIP_BLOCK],
    normal_x: [f32; SKIP_BLOCK],
    centre: [f32; SKIP_BLOCK],
    centre_x: [f32; SKIP_BLOCK],
    radius: [f32; SKIP_BLOCK],
}

/// [`SKIP_BLOCK`] triangles for the exact test, one array per coordinate: the chunk's first
/// corner and the vertices, each from its triangle's own base cell, exactly as
/// [`TreeTriangle::distance_squared`] takes them, so the vector test gives the same bits.
#[derive(Debug, Clone, Copy)]
struct TriangleBlock {
    corner: [[f32; SKIP_BLOCK]; 3],
    a: [[f32; SKIP_BLOCK]; 3],
    b: [[f32; SKIP_BLOCK]; 3],
    c: [[f32; SKIP_BLOCK]; 3],
}

impl TriangleBlock {
    const EMPTY: Self = Self {
        corner: [[0.0; SKIP_BLOCK]; 3],
        a: [[0.0; SKIP_BLOCK]; 3],
        b: [[0.0; SKIP_BLOCK]; 3],
        c: [[0.0; SKIP_BLOCK]; 3],
    };

    fn set(&mut self, j: usize, t: &TreeTriangle, first: [i32; 3]) {
        for (k, &first) in first.iter().enumerate() {
            self.corner[k][j] = (first - t.base[k]) as f32;
            self.a[k][j] = t.a[k];
            self.b[k][j] = t.b[k];
            self.c[k][j] = t.c[k];
        }
    }

    /// Squared distances from the corner `step` cells along x from the chunk's first corner to
    /// the block's triangles: [`point_triangle_distance_squared`] on all of them at once, its
    /// Voronoi regions as masks taken in the same order, with the same operations on the same
    /// operands. The rare lanes that fall through every region (degenerate triangles) are computed
    /// one by one.
    fn exact(&self, step: f32) -> [f32; SKIP_BLOCK] {
        let v = f32x8::from;
        let zero = f32x8::ZERO;
        let p = [
            v(self.corner[0]) + f32x8::splat(step),
            v(self.corner[1]),
            v(self.corner[2]),
        ];
        let (a, b, c) = (self.a.map(v), self.b.map(v), self.c.map(v));
        let sub = |x: [f32x8; 3], y: [f32x8; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
        let dot = |x: [f32x8; 3], y: [f32x8; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        let along = |x: [f32x8; 3], d: [f32x8; 3], s: f32x8| {
            [x[0] + d[0] * s, x[1] + d[1] * s, x[2] + d[2] * s]
        };
        let squared = |x: [f32x8; 3], q: [f32x8; 3]| {
            let d = sub(x, q);
            dot(d, d)
        };
        let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
        let (d1, d2) = (dot(ab, ap), dot(ac, ap));
        let bp = sub(p, b);
        let (d3, d4) = (dot(ab, bp), dot(ac, bp));
        let cp = sub(p, c);
        let (d5, d6) = (dot(ab, cp), dot(ac, cp));
        let vc = d1 * d4 - d3 * d2;
        let vb = d5 * d2 - d1 * d6;
        let va = d3 * d6 - d5 * d4;
        let (e1, e2) = (d4 - d3, d5 - d6);
        let sum = va + vb + vc;
        let regions = [
            (d1.simd_le(zero) & d2.simd_le(zero), dot(ap, ap)),
            (d3.simd_ge(zero) & d4.simd_le(d3), dot(bp, bp)),
            (d6.simd_ge(zero) & d5.simd_le(d6), dot(cp, cp)),
            (
                vc.simd_le(zero) & d1.simd_ge(zero) & d3.simd_le(zero) & (d1 - d3).simd_gt(zero),
                squared(p, along(a, ab, d1 / (d1 - d3))),
            ),
            (
                vb.simd_le(zero) & d2.simd_ge(zero) & d6.simd_le(zero) & (d2 - d6).simd_gt(zero),
                squared(p, along(a, ac, d2 / (d2 - d6))),
            ),
            (
                va.simd_le(zero) & e1.simd_ge(zero) & e2.simd_ge(zero) & (e1 + e2).simd_gt(zero),
                squared(p, along(b, sub(c, b), e1 / (e1 + e2))),
            ),
            (
                sum.simd_gt(zero),
                squared(p, along(along(a, ab, vb / sum), ac, vc / sum)),
            ),
        ];
        let mut out = f32x8::splat(f32::NAN);
        let mut taken = f32x8::ZERO.simd_gt(zero);
        for (mask, value) in regions.iter().rev() {
            out = mask.select(*value, out);
            taken |= *mask;
        }
        let mut out = out.to_array();
        let mut rest = !taken.to_bitmask() & ((1 << SKIP_BLOCK) - 1);
        while rest != 0 {
            let j = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            let lane = |x: &[[f32; SKIP_BLOCK]; 3]| [x[0][j], x[1][j], x[2][j]];
            let corner = lane(&self.corner);
            out[j] = point_triangle_distance_squared(
                [corner[0] + step, corner[1], corner[2]],
                lane(&self.a),
                lane(&self.b),
                lane(&self.c),
            );
        }
        out
    }
}

impl NearBlock {
    const EMPTY: Self = Self {
        across: [f32::INFINITY; SKIP_BLOCK],
        box_lo: [0.0; SKIP_BLOCK],
        box_hi: [0.0; SKIP_BLOCK],
        plane: [0.0; SKIP_BLOCK],
        normal_x: [0.0; SKIP_BLOCK],
        centre: [0.0; SKIP_BLOCK],
        centre_x: [0.0; SKIP_BLOCK],
        radius: [0.0; SKIP_BLOCK],
    };

    /// Lower bounds of the squared distance from the corner `step` cells along x from the chunk's
    /// first corner (at `x` cells from the tree's base) to each triangle of the block.
    ///
    /// Each bound is the larger of two: the box's, and the disk's. A triangle lies in its plane
    /// within `radius` of its centroid, so its distance is at least
    /// `sqrt(h² + max(l − radius, 0)²)` for the plane distance `h` and the distance `l` within
    /// the plane from the corner's projection to the centroid (for a degenerate triangle, whose
    /// normal is zero, `h` is 0 and this is the bounding sphere's bound). On a nearly flat surface
    /// the plane distance alone ties for every triangle below the corner; the disk bound leaves
    /// only the few whose disks hold the corner's projection.
    fn bounds(&self, x: f32, step: f32) -> f32x8 {
        let v = f32x8::from;
        let zero = f32x8::ZERO;
        let x = f32x8::splat(x);
        let step = f32x8::splat(step);
        let slack = f32x8::splat(PLANE_SLACK);
        let gap = (v(self.box_lo) - x)
            .fast_max(x - v(self.box_hi))
            .fast_max(zero);
        let to_box = v(self.across) + gap * gap;
        let h = (v(self.plane) + v(self.normal_x) * step).abs();
        let below = (h - slack).fast_max(zero);
        let above = h + slack;
        let centre = v(self.centre) + step * (step - f32x8::splat(2.0) * v(self.centre_x));
        let lateral = (centre - above * above - f32x8::splat(LATERAL_SLACK))
            .fast_max(zero)
            .sqrt()
            - v(self.radius);
        let lateral = lateral.fast_max(zero);
        to_box.fast_max(below * below + lateral * lateral)
    }
}

/// The least of a block's bounds.
fn least_of(b: f32x8) -> f32 {
    let b = b.to_array();
    let four: [f32; 4] = std::array::from_fn(|k| min(b[k], b[k + 4]));
    min(min(four[0], four[2]), min(four[1], four[3]))
}

/// What one worker keeps between tiles: the tile's gathered triangles, and per chunk the near
/// ones with their bounds at the current corner.
#[derive(Debug, Default)]
struct Scratch {
    slots: Vec<u32>,
    gathered: Vec<GatherBlock>,
    near: Vec<u32>,
    blocks: Vec<NearBlock>,
    bounds: Vec<f32x8>,
    least: Vec<f32>,
    /// The near triangles' vertices for the exact test, filled block by block when a block is
    /// first tested in the current chunk (most blocks never are).
    exact: Vec<Option<TriangleBlock>>,
}

/// One closure call per tile; the results are then placed at their chunks' output offsets.
pub fn distance_tiled(
    tree: &TriangleTree,
    chunks: &[BandChunk],
    tiles: &[BandTile],
    bound: f32,
) -> Vec<Nearest> {
    per_tile(chunks, tiles, bound, Scratch::default, |scratch, own| {
        tile_nearest(tree, own, bound, scratch)
    })
}

/// Fills `g.gathered` with the triangles of `g.slots`, relative to the tile's lowest corner.
fn fill_gathered(tree: &TriangleTree, first_corner: [i32; 3], g: &mut Scratch) {
    g.gathered.clear();
    for (n, &slot) in g.slots.iter().enumerate() {
        let j = n % SKIP_BLOCK;
        if j == 0 {
            g.gathered.push(GatherBlock::EMPTY);
        }
        let Some(block) = g.gathered.last_mut() else {
            continue;
        };
        let b = &tree.boxes()[slot as usize];
        let t = &tree.triangles()[slot as usize];
        let disk = &tree.disks()[slot as usize];
        let p: [f32; 3] = std::array::from_fn(|k| (first_corner[k] - t.base[k]) as f32);
        block.slot[j] = slot;
        for a in 0..3 {
            block.min[a][j] = b.min[a];
            block.max[a][j] = b.max[a];
            block.normal[a][j] = t.normal[a];
            block.centre[a][j] = disk[a] - p[a];
        }
        block.plane[j] = t.normal[0] * p[0] + t.normal[1] * p[1] + t.normal[2] * p[2] - t.offset;
        block.radius[j] = disk[3];
    }
}

/// Fills `g.near` and `g.blocks` with the gathered triangles whose boxes lie within the band of
/// some corner of chunk `c`: a box farther than that from all of the chunk's segment holds no
/// corner's nearest triangle. The test runs on whole blocks; only the triangles that pass are
/// copied.
fn fill_near(
    tree: &TriangleTree,
    c: &BandChunk,
    first_corner: [i32; 3],
    bound: f32,
    g: &mut Scratch,
) {
    let start = tree.local(c.first);
    let offset: [f32; 3] = std::array::from_fn(|k| (c.first[k] - first_corner[k]) as f32);
    let last_x = start[0] + (c.len - 1) as f32;
    g.near.clear();
    g.blocks.clear();
    let v = f32x8::from;
    let zero = f32x8::ZERO;
    let at = |a: usize| f32x8::splat(start[a]);
    let shift = |a: usize| f32x8::splat(offset[a]);
    for block in &g.gathered {
        let gap = |a: usize| {
            (v(block.min[a]) - at(a))
                .fast_max(at(a) - v(block.max[a]))
                .fast_max(zero)
        };
        let (gy, gz) = (gap(1), gap(2));
        let across = gy * gy + gz * gz;
        let along = (v(block.min[0]) - f32x8::splat(last_x))
            .fast_max(at(0) - v(block.max[0]))
            .fast_max(zero);
        let mut keep = (across + along * along)
            .simd_lt(f32x8::splat(bound))
            .to_bitmask();
        if keep == 0 {
            continue;
        }
        let plane = v(block.plane)
            + v(block.normal[0]) * shift(0)
            + v(block.normal[1]) * shift(1)
            + v(block.normal[2]) * shift(2);
        let to: [f32x8; 3] = std::array::from_fn(|a| v(block.centre[a]) - shift(a));
        let centre = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
        let (across, plane, centre, centre_x) = (
            across.to_array(),
            plane.to_array(),
            centre.to_array(),
            to[0].to_array(),
        );
        while keep != 0 {
            let k = keep.trailing_zeros() as usize;
            keep &= keep - 1;
            let j = g.near.len() % SKIP_BLOCK;
            if j == 0 {
                g.blocks.push(NearBlock::EMPTY);
            }
            let Some(near) = g.blocks.last_mut() else {
                continue;
            };
            near.across[j] = across[k];
            near.box_lo[j] = block.min[0][k];
            near.box_hi[j] = block.max[0][k];
            near.plane[j] = plane[k];
            near.normal_x[j] = block.normal[0][k];
            near.centre[j] = centre[k];
            near.centre_x[j] = centre_x[k];
            near.radius[j] = block.radius[k];
            g.near.push(block.slot[k]);
        }
    }
}

/// The nearest triangle within `bound` (squared cells) of each corner of the chunks of one tile,
/// chunk after chunk.
///
/// The triangles whose boxes lie within the band of the tile's box are gathered once, and for
/// each chunk those near its segment are kept. For each corner the bounds of all of them are
/// computed; when none is below `bound` the corner lies outside the band. Otherwise the previous
/// corner's nearest triangle (for a chunk's first corner, the one with the least bound) is tested
/// first, which nearly always gives the final distance, and then only triangles whose bound is
/// below the best so far. A tile near more than [`GATHER_CAPACITY`] triangles searches the tree
/// once per corner instead (cheaper there than gathering chunk by chunk, measured).
fn tile_nearest(
    tree: &TriangleTree,
    chunks: &[BandChunk],
    bound: f32,
    g: &mut Scratch,
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
            let mut hint = Nearest::NONE;
            for i in 0..c.len as i32 {
                let corner = [c.first[0] + i, c.first[1], c.first[2]];
                // The previous corner's nearest triangle bounds the search from the start.
                let seed = match tree.triangles().get(hint as usize) {
                    Some(t) => t.distance_squared(corner).min(bound),
                    None => bound,
                };
                let found = if seed < bound { hint } else { Nearest::NONE };
                let (distance_squared, slot) = tree.nearest(corner, seed, found);
                hint = slot;
                out.push(Nearest {
                    distance_squared,
                    slot,
                });
            }
        }
        return out;
    }
    fill_gathered(tree, first_corner, g);
    for c in chunks {
        fill_near(tree, c, first_corner, bound, g);
        let start_x = tree.local(c.first)[0];
        let blocks = g.blocks.len();
        g.bounds.resize(blocks, f32x8::ZERO);
        g.least.resize(blocks, 0.0);
        g.exact.clear();
        g.exact.resize(blocks, None);
        let mut hint = None;
        for i in 0..c.len as i32 {
            let step = i as f32;
            let corner = [c.first[0] + i, c.first[1], c.first[2]];
            let mut overall = f32::INFINITY;
            for ((block, bounds), least) in g.blocks.iter().zip(&mut g.bounds).zip(&mut g.least) {
                *bounds = block.bounds(start_x + step, step);
                *least = least_of(*bounds);
                overall = min(overall, *least);
            }
            let mut best = bound;
            let mut found = None;
            if overall < best {
                // The previous corner's nearest triangle, or else the one with the least bound.
                let first = hint.unwrap_or_else(|| {
                    g.bounds
                        .iter()
                        .flat_map(|b| b.to_array())
                        .position(|lower| lower == overall)
                        .unwrap_or(0)
                });
                if g.bounds[first / SKIP_BLOCK].to_array()[first % SKIP_BLOCK] < best {
                    let d = tree.triangles()[g.near[first] as usize].distance_squared(corner);
                    if d < best {
                        best = d;
                        found = Some(first);
                    }
                }
                for (b, (bounds, &least)) in g.bounds.iter().zip(&g.least).enumerate() {
                    if least >= best {
                        continue;
                    }
                    let lower = bounds.to_array();
                    let exact = g.exact[b]
                        .get_or_insert_with(|| {
                            let mut block = TriangleBlock::EMPTY;
                            let slots = g.near.iter().skip(b * SKIP_BLOCK).take(SKIP_BLOCK);
                            for (j, &slot) in slots.enumerate() {
                                block.set(j, &tree.triangles()[slot as usize], c.first);
                            }
                            block
                        })
                        .exact(step);
                    for (j, (&lower, &d)) in lower.iter().zip(&exact).enumerate() {
                        let k = b * SKIP_BLOCK + j;
                        if lower < best && k != first && d < best {
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
