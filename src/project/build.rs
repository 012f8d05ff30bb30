//! Binned-SAH BVH construction (Wald 2007, "On fast construction of SAH-based bounding volume
//! hierarchies"), flattened into the node layout both backends traverse.
//!
//! Every node tries 16 bins along each of the three axes of its centroid bounds and keeps the
//! plane with the least surface-area cost, or becomes a leaf when that is cheaper. Subtrees of
//! more than [`PARALLEL_MIN`] triangles are built in parallel into their own node arrays and
//! appended in a fixed order, so the result is identical whatever the thread count.

use bytemuck::Zeroable;
use glam::{UVec3, Vec3A};
use rayon::prelude::*;

use super::BvhNode;
use crate::compute::Aabb;

/// Deepest leaf below the root plus one; the traversal stacks of both backends hold this many
/// entries (`STACK_SIZE` in `kernels/shared/bvh.wgsl`), one per level at most.
pub const MAX_DEPTH: usize = 64;
/// Most triangles a leaf may hold.
pub const MAX_LEAF: usize = 4;
const BINS: usize = 16;
/// Cost of visiting a node relative to one ray–triangle test.
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with at least this many triangles build their two halves in parallel.
const PARALLEL_MIN: usize = 4096;

/// A BVH over triangles: nodes (root first, node 1 unused) and, per leaf slot, the triangle it
/// holds.
pub(super) struct Tree {
    pub nodes: Vec<BvhNode>,
    pub order: Vec<u32>,
}

#[derive(Debug, Clone, Copy)]
struct Bounds {
    min: Vec3A,
    max: Vec3A,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    fn union(self, other: Bounds) -> Bounds {
        Bounds {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    fn grow(self, p: Vec3A) -> Bounds {
        Bounds {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Half the surface area (the SAH only compares ratios); 0 for an empty box.
    fn half_area(self) -> f32 {
        let d = (self.max - self.min).max(Vec3A::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
}

/// What the builder knows of each triangle: its box and that box's centre.
struct Prims {
    boxes: Vec<Bounds>,
    centroids: Vec<Vec3A>,
}

/// A node's box and the bounds of its triangles' centroids (what binning subdivides).
#[derive(Debug, Clone, Copy)]
struct Extent {
    bounds: Bounds,
    centroids: Bounds,
}

impl Extent {
    fn of(prims: &Prims, refs: &[u32]) -> Extent {
        refs.iter().fold(
            Extent {
                bounds: Bounds::EMPTY,
                centroids: Bounds::EMPTY,
            },
            |e, &r| Extent {
                bounds: e.bounds.union(prims.boxes[r as usize]),
                centroids: e.centroids.grow(prims.centroids[r as usize]),
            },
        )
    }
}

/// Builds the BVH of the triangles whose boxes are `boxes` (at least one).
pub(super) fn build(boxes: &[Aabb]) -> Tree {
    let boxes: Vec<Bounds> = boxes
        .par_iter()
        .map(|b| Bounds {
            min: b.min.into(),
            max: b.max.into(),
        })
        .collect();
    let centroids = boxes.par_iter().map(|b| (b.min + b.max) * 0.5).collect();
    let prims = Prims { boxes, centroids };
    let count = u32::try_from(prims.boxes.len()).unwrap_or(u32::MAX);
    let mut order: Vec<u32> = (0..count).collect();
    let extent = Extent::of(&prims, &order);
    // Node 1 is padding: child pairs are pushed two at a time from index 2 on, so each pair
    // fills one 64-byte line of a 64-byte-aligned array.
    let mut nodes = vec![BvhNode::zeroed(); 2];
    nodes[0] = subtree(&prims, &mut order, 0, extent, 0, &mut nodes);
    Tree { nodes, order }
}

/// Builds the subtree over `refs` (leaf slots `first..`), appending its descendants to `out`, and
/// returns its root with child indices relative to the start of `out`.
fn subtree(
    prims: &Prims,
    refs: &mut [u32],
    first: u32,
    extent: Extent,
    depth: usize,
    out: &mut Vec<BvhNode>,
) -> BvhNode {
    let count = refs.len();
    let Some(mid) = split(prims, refs, extent, depth) else {
        return node(extent.bounds, first, count as u32);
    };
    let (left, right) = refs.split_at_mut(mid);
    let left_extent = Extent::of(prims, left);
    let right_extent = Extent::of(prims, right);
    let right_first = first + mid as u32;
    let pair = out.len();
    if count >= PARALLEL_MIN {
        let detached = |refs: &mut [u32], first: u32, extent: Extent| {
            let mut nodes = Vec::new();
            let root = subtree(prims, refs, first, extent, depth + 1, &mut nodes);
            (root, nodes)
        };
        let ((left_root, left_nodes), (right_root, right_nodes)) = rayon::join(
            || detached(left, first, left_extent),
            || detached(right, right_first, right_extent),
        );
        out.push(left_root);
        out.push(right_root);
        attach(out, pair, left_nodes);
        attach(out, pair + 1, right_nodes);
    } else {
        out.extend([BvhNode::zeroed(); 2]);
        out[pair] = subtree(prims, left, first, left_extent, depth + 1, out);
        out[pair + 1] = subtree(prims, right, right_first, right_extent, depth + 1, out);
    }
    node(extent.bounds, pair as u32, 0)
}

fn node(bounds: Bounds, index: u32, count: u32) -> BvhNode {
    BvhNode {
        min: bounds.min.into(),
        index,
        max: bounds.max.into(),
        count,
    }
}

/// Appends a subtree built into its own array, moving its child indices (and its root's, in
/// `out[slot]`) by the array's new offset. Leaf indices are slots and stay as they are.
fn attach(out: &mut Vec<BvhNode>, slot: usize, descendants: Vec<BvhNode>) {
    let base = out.len() as u32;
    if !out[slot].is_leaf() {
        out[slot].index += base;
    }
    out.extend(descendants.into_iter().map(|mut n| {
        if !n.is_leaf() {
            n.index += base;
        }
        n
    }));
}

/// Reorders `refs` into two non-empty halves and returns the length of the first, or `None` when
/// the node should be a leaf.
fn split(prims: &Prims, refs: &mut [u32], extent: Extent, depth: usize) -> Option<usize> {
    let count = refs.len();
    if count <= 1 {
        return None;
    }
    let size = extent.centroids.max - extent.centroids.min;
    // Near the depth limit, or when every centroid coincides, halving by count is the only split
    // that still bounds the depth.
    let halvings_left = (MAX_DEPTH - 1).saturating_sub(depth);
    if ceil_log2(count) >= halvings_left || size.max_element() <= 0.0 {
        if count <= MAX_LEAF {
            return None;
        }
        return Some(median_split(prims, refs, size));
    }
    let binning = Binning::new(extent.centroids, size, count);
    let best = best_plane(prims, refs, &binning);
    let leaf_cost = count as f32;
    let split_cost = TRAVERSAL_COST + best.cost / extent.bounds.half_area();
    if count <= MAX_LEAF && split_cost >= leaf_cost {
        return None;
    }
    let mid = partition(refs, |r| {
        binning.bins(prims.centroids[r as usize])[best.axis] < best.plane
    });
    if mid == 0 || mid == count {
        return Some(median_split(prims, refs, size));
    }
    Some(mid)
}

/// The smallest `k` with `2^k >= n`.
fn ceil_log2(n: usize) -> usize {
    (usize::BITS - n.saturating_sub(1).leading_zeros()) as usize
}

/// Splits at the median centroid along the widest axis, ties broken by triangle index so the two
/// halves do not depend on the selection algorithm.
fn median_split(prims: &Prims, refs: &mut [u32], size: Vec3A) -> usize {
    let axis = widest_axis(size);
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |&a, &b| {
        let ca = prims.centroids[a as usize][axis];
        let cb = prims.centroids[b as usize][axis];
        ca.total_cmp(&cb).then(a.cmp(&b))
    });
    mid
}

fn widest_axis(size: Vec3A) -> usize {
    if size.x >= size.y && size.x >= size.z {
        0
    } else if size.y >= size.z {
        1
    } else {
        2
    }
}

/// Moves the refs satisfying `left` to the front, returning how many there are.
fn partition(refs: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let (mut i, mut j) = (0, refs.len());
    while i < j {
        if left(refs[i]) {
            i += 1;
        } else {
            j -= 1;
            refs.swap(i, j);
        }
    }
    i
}

/// Maps centroids to bins along all three axes at once.
struct Binning {
    origin: Vec3A,
    /// Bins per unit length; 0 along an axis where all centroids coincide (nothing to split).
    scale: Vec3A,
    /// Bins in use: 16, or fewer for small nodes, where setting up and sweeping 16 bins would
    /// cost more than the binning itself.
    len: usize,
}

impl Binning {
    fn new(centroids: Bounds, size: Vec3A, count: usize) -> Self {
        let len = count.clamp(4, BINS);
        let scale = Vec3A::select(
            size.cmpgt(Vec3A::ZERO),
            Vec3A::splat(len as f32) / size,
            Vec3A::ZERO,
        );
        Self {
            origin: centroids.min,
            scale,
            len,
        }
    }

    /// The centroid's bin along x, y and z. The float-to-int conversion saturates (NaN gives 0),
    /// so every centroid lands in some bin.
    #[inline(always)]
    fn bins(&self, centroid: Vec3A) -> [usize; 3] {
        let k = ((centroid - self.origin) * self.scale).as_uvec3();
        k.min(UVec3::splat(self.len as u32 - 1))
            .to_array()
            .map(|k| k as usize)
    }

    fn splits(&self, axis: usize) -> bool {
        self.scale[axis] > 0.0
    }
}

#[derive(Debug, Clone, Copy)]
struct Bin {
    bounds: Bounds,
    count: u32,
}

const EMPTY_BIN: Bin = Bin {
    bounds: Bounds::EMPTY,
    count: 0,
};

/// The cheapest plane: triangles in bins `< plane` of `axis` go left. `cost` is the SAH numerator
/// `area(left)·count(left) + area(right)·count(right)`.
#[derive(Debug, Clone, Copy)]
struct Plane {
    axis: usize,
    plane: usize,
    cost: f32,
}

fn best_plane(prims: &Prims, refs: &[u32], binning: &Binning) -> Plane {
    let fill = |refs: &[u32]| {
        let mut bins = [[EMPTY_BIN; BINS]; 3];
        for &r in refs {
            let r = r as usize;
            let bounds = prims.boxes[r];
            let k = binning.bins(prims.centroids[r]);
            for (axis_bins, k) in bins.iter_mut().zip(k) {
                let bin = &mut axis_bins[k];
                bin.bounds = bin.bounds.union(bounds);
                bin.count += 1;
            }
        }
        bins
    };
    // Min, max and counts combine exactly in any order, so the parallel reduction is deterministic.
    let bins = if refs.len() >= PARALLEL_MIN {
        refs.par_chunks(PARALLEL_MIN)
            .map(fill)
            .reduce(|| [[EMPTY_BIN; BINS]; 3], merge_bins)
    } else {
        fill(refs)
    };
    let len = binning.len;
    let mut best = Plane {
        axis: 0,
        plane: 0,
        cost: f32::INFINITY,
    };
    for (axis, bins) in bins.iter().enumerate() {
        if !binning.splits(axis) {
            continue;
        }
        let mut right_cost = [0.0f32; BINS];
        let mut right = EMPTY_BIN;
        for plane in (1..len).rev() {
            right.bounds = right.bounds.union(bins[plane].bounds);
            right.count += bins[plane].count;
            right_cost[plane] = right.bounds.half_area() * right.count as f32;
        }
        let mut left = EMPTY_BIN;
        for plane in 1..len {
            left.bounds = left.bounds.union(bins[plane - 1].bounds);
            left.count += bins[plane - 1].count;
            let cost = left.bounds.half_area() * left.count as f32 + right_cost[plane];
            if cost < best.cost {
                best = Plane { axis, plane, cost };
            }
        }
    }
    best
}

fn merge_bins(mut a: [[Bin; BINS]; 3], b: [[Bin; BINS]; 3]) -> [[Bin; BINS]; 3] {
    for (axis, bins) in a.iter_mut().enumerate() {
        for (bin, other) in bins.iter_mut().zip(&b[axis]) {
            bin.bounds = bin.bounds.union(other.bounds);
            bin.count += other.count;
        }
    }
    a
}
