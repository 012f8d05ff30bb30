//! Binned-SAH BVH construction (Wald 2007, "On fast construction of SAH-based bounding volume
//! hierarchies"), then widened into the 4-wide node layout both backends traverse.
//!
//! Every binary node tries up to 16 bins along each of the three axes of its centroid bounds and
//! keeps the plane with the least surface-area cost, or becomes a leaf when that is cheaper.
//! Subtrees of more than [`PARALLEL_MIN`] triangles are built in parallel into their own node
//! arrays and appended in a fixed order, so the result is identical whatever the thread count.
//! Widening pulls grandchildren up into 4-wide nodes (as Embree's BVH4), which halves the levels a
//! traversal descends and lets one SIMD step test four boxes.

use glam::{UVec3, Vec3A};
use rayon::prelude::*;

use crate::kernels::shared::Aabb;
use crate::kernels::shared::BvhNode;

/// Deepest binary leaf below the root plus one. Every level of the 4-wide tree spans at least two
/// binary levels, so it is at most `MAX_DEPTH / 2` deep, and a traversal, which keeps at most
/// three siblings per level, needs at most [`STACK_SIZE`] entries.
const MAX_DEPTH: usize = 42;
/// Entries of the traversal stacks of both backends (`STACK_SIZE` in `kernels/shared/bvh.wgsl`).
pub const STACK_SIZE: usize = 3 * MAX_DEPTH / 2 + 1;
/// Most triangles a leaf may hold.
pub const MAX_LEAF: usize = 4;
const BINS: usize = 16;
/// Cost of visiting a node relative to one ray–triangle test.
const TRAVERSAL_COST: f32 = 1.0;
/// Subtrees with at least this many triangles build their two halves in parallel.
const PARALLEL_MIN: usize = 4096;

/// A BVH over triangles: 4-wide nodes (root first) and, per leaf slot, the triangle it holds.
pub(super) struct Tree {
    pub nodes: Vec<BvhNode>,
    pub order: Vec<u32>,
}

/// A node of the binary tree the builder makes before widening. Interior (`count == 0`):
/// children at `index` and `index + 1`. Leaf: triangle slots `index .. index + count`.
#[derive(Debug, Clone, Copy, Default)]
struct BinaryNode {
    bounds: Option<Bounds>,
    index: u32,
    count: u32,
}

impl BinaryNode {
    fn is_leaf(&self) -> bool {
        self.count > 0
    }

    fn bounds(&self) -> Bounds {
        self.bounds.unwrap_or(Bounds::EMPTY)
    }
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

/// A triangle as the builder moves it: its box and its index. Partitioning moves these records
/// themselves rather than indices into a table, so every pass over a node streams through
/// contiguous memory (Embree's primitive references).
#[derive(Debug, Clone, Copy)]
struct PrimRef {
    bounds: Bounds,
    id: u32,
}

impl PrimRef {
    fn centroid(&self) -> Vec3A {
        (self.bounds.min + self.bounds.max) * 0.5
    }
}

/// A node's box and the bounds of its triangles' centroids (what binning subdivides).
#[derive(Debug, Clone, Copy)]
struct Extent {
    bounds: Bounds,
    centroids: Bounds,
}

impl Extent {
    const EMPTY: Extent = Extent {
        bounds: Bounds::EMPTY,
        centroids: Bounds::EMPTY,
    };

    fn of(refs: &[PrimRef]) -> Extent {
        refs.iter().fold(Extent::EMPTY, |e, r| e.add(r))
    }

    fn add(self, r: &PrimRef) -> Extent {
        Extent {
            bounds: self.bounds.union(r.bounds),
            centroids: self.centroids.grow(r.centroid()),
        }
    }
}

/// Builds the BVH of the triangles whose boxes are `boxes` (at least one).
pub(super) fn build(boxes: &[Aabb]) -> Tree {
    let mut refs: Vec<PrimRef> = boxes
        .par_iter()
        .enumerate()
        .map(|(id, b)| PrimRef {
            bounds: Bounds {
                min: b.min.into(),
                max: b.max.into(),
            },
            id: id as u32,
        })
        .collect();
    // Unions are exact in any order, so the parallel reduction is deterministic.
    let extent = refs.par_chunks(PARALLEL_MIN).map(Extent::of).reduce(
        || Extent::EMPTY,
        |a, b| Extent {
            bounds: a.bounds.union(b.bounds),
            centroids: a.centroids.union(b.centroids),
        },
    );
    let mut nodes = vec![BinaryNode::default()];
    nodes[0] = subtree(&mut refs, 0, extent, 0, &mut nodes);
    Tree {
        nodes: widen(&nodes),
        order: refs.par_iter().map(|r| r.id).collect(),
    }
}

/// Builds the subtree over `refs` (leaf slots `first..`), appending its descendants to `out`, and
/// returns its root with child indices relative to the start of `out`.
fn subtree(
    refs: &mut [PrimRef],
    first: u32,
    extent: Extent,
    depth: usize,
    out: &mut Vec<BinaryNode>,
) -> BinaryNode {
    let count = refs.len();
    let Some((mid, left_extent, right_extent)) = split(refs, extent, depth) else {
        return node(extent.bounds, first, count as u32);
    };
    let (left, right) = refs.split_at_mut(mid);
    let right_first = first + mid as u32;
    let pair = out.len();
    if count >= PARALLEL_MIN {
        let detached = |refs: &mut [PrimRef], first: u32, extent: Extent| {
            let mut nodes = Vec::new();
            let root = subtree(refs, first, extent, depth + 1, &mut nodes);
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
        out.extend([BinaryNode::default(); 2]);
        out[pair] = subtree(left, first, left_extent, depth + 1, out);
        out[pair + 1] = subtree(right, right_first, right_extent, depth + 1, out);
    }
    node(extent.bounds, pair as u32, 0)
}

fn node(bounds: Bounds, index: u32, count: u32) -> BinaryNode {
    BinaryNode {
        bounds: Some(bounds),
        index,
        count,
    }
}

/// Appends a subtree built into its own array, moving its child indices (and its root's, in
/// `out[slot]`) by the array's new offset. Leaf indices are slots and stay as they are.
fn attach(out: &mut Vec<BinaryNode>, slot: usize, descendants: Vec<BinaryNode>) {
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

/// Reorders `refs` into two non-empty halves and returns the length of the first and the extents
/// of both, or `None` when the node should be a leaf.
fn split(refs: &mut [PrimRef], extent: Extent, depth: usize) -> Option<(usize, Extent, Extent)> {
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
        return Some(median_split(refs, size));
    }
    let binning = Binning::new(extent.centroids, size, count);
    let best = best_plane(refs, &binning);
    let leaf_cost = count as f32;
    let split_cost = TRAVERSAL_COST + best.cost / extent.bounds.half_area();
    if count <= MAX_LEAF && split_cost >= leaf_cost {
        return None;
    }
    let (mid, left, right) =
        partition(refs, |r| binning.bins(r.centroid())[best.axis] < best.plane);
    if mid == 0 || mid == count {
        return Some(median_split(refs, size));
    }
    Some((mid, left, right))
}

/// The smallest `k` with `2^k >= n`.
fn ceil_log2(n: usize) -> usize {
    (usize::BITS - n.saturating_sub(1).leading_zeros()) as usize
}

/// Splits at the median centroid along the widest axis, ties broken by triangle index so the two
/// halves do not depend on the selection algorithm.
fn median_split(refs: &mut [PrimRef], size: Vec3A) -> (usize, Extent, Extent) {
    let axis = widest_axis(size);
    let mid = refs.len() / 2;
    refs.select_nth_unstable_by(mid, |a, b| {
        let (ca, cb) = (a.centroid()[axis], b.centroid()[axis]);
        ca.total_cmp(&cb).then(a.id.cmp(&b.id))
    });
    (mid, Extent::of(&refs[..mid]), Extent::of(&refs[mid..]))
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

/// Moves the refs satisfying `left` to the front, returning how many there are and the extents
/// of both sides, gathered in the same pass.
fn partition(refs: &mut [PrimRef], left: impl Fn(&PrimRef) -> bool) -> (usize, Extent, Extent) {
    let (mut left_extent, mut right_extent) = (Extent::EMPTY, Extent::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    while i < j {
        let r = refs[i];
        if left(&r) {
            left_extent = left_extent.add(&r);
            i += 1;
        } else {
            right_extent = right_extent.add(&r);
            j -= 1;
            refs.swap(i, j);
        }
    }
    (i, left_extent, right_extent)
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

fn best_plane(refs: &[PrimRef], binning: &Binning) -> Plane {
    let fill = |refs: &[PrimRef]| {
        let mut bins = [[EMPTY_BIN; BINS]; 3];
        for r in refs {
            let k = binning.bins(r.centroid());
            for (axis_bins, k) in bins.iter_mut().zip(k) {
                let bin = &mut axis_bins[k];
                bin.bounds = bin.bounds.union(r.bounds);
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

/// Widens the binary tree into 4-wide nodes. A wide node takes its binary node's two children and
/// replaces each interior one by its own two children, so every wide level spans at least two
/// binary levels; a slot still free then goes to the interior child of largest area (the one a
/// line is likeliest to enter). Children are numbered in the order they are first reached.
fn widen(binary: &[BinaryNode]) -> Vec<BvhNode> {
    let mut wide = vec![BvhNode::empty()];
    let mut pending = vec![(0usize, 0usize)];
    while let Some((b, w)) = pending.pop() {
        let mut node = BvhNode::empty();
        let (children, len) = gather(binary, b);
        for (k, &c) in children[..len].iter().enumerate() {
            let child = binary[c];
            let bounds = child.bounds();
            node.min_x[k] = bounds.min.x;
            node.min_y[k] = bounds.min.y;
            node.min_z[k] = bounds.min.z;
            node.max_x[k] = bounds.max.x;
            node.max_y[k] = bounds.max.y;
            node.max_z[k] = bounds.max.z;
            if child.is_leaf() {
                node.child[k] = child.index;
                node.count[k] = child.count;
            } else {
                node.child[k] = wide.len() as u32;
                node.count[k] = 0;
                pending.push((c, wide.len()));
                wide.push(BvhNode::empty());
            }
        }
        wide[w] = node;
    }
    wide
}

/// The binary nodes that become the children of the wide node made from binary node `b` (the
/// first `len` of the array: one for a leaf, two to four otherwise). No allocation: a tree of
/// 50k triangles has some 18k wide nodes.
fn gather(binary: &[BinaryNode], b: usize) -> ([usize; 4], usize) {
    let mut children = [b; 4];
    if binary[b].is_leaf() {
        return (children, 1);
    }
    let split = |c: usize| {
        let i = binary[c].index as usize;
        [i, i + 1]
    };
    let mut len = 0;
    for c in split(b) {
        if binary[c].is_leaf() {
            children[len] = c;
            len += 1;
        } else {
            let [l, r] = split(c);
            children[len] = l;
            children[len + 1] = r;
            len += 2;
        }
    }
    while len < 4 {
        let largest = children[..len]
            .iter()
            .enumerate()
            .filter(|(_, c)| !binary[**c].is_leaf())
            .fold(None, |best: Option<(usize, f32)>, (k, &c)| {
                let area = binary[c].bounds().half_area();
                match best {
                    Some((_, a)) if a >= area => best,
                    _ => Some((k, area)),
                }
            });
        let Some((k, _)) = largest else {
            break;
        };
        let [l, r] = split(children[k]);
        children.copy_within(k + 1..len, k + 2);
        children[k] = l;
        children[k + 1] = r;
        len += 1;
    }
    (children, len)
}
