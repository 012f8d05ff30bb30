//! A bounding-volume tree over a lattice mesh for nearest-triangle queries from grid corners.
//!
//! Unlike a world-space tree, every distance here is measured from offsets that are exact or
//! rounded once: a corner's offset from a triangle's lowest cell is an exact integer, and the
//! triangle's corners are stored as f32 offsets from that cell, so the error of a distance follows
//! the triangle's size, not the grid's extent. Node boxes are rounded outwards, so pruning by them
//! never drops the nearest triangle. The tree is split at the median (balanced: depth at most
//! [`STACK_SIZE`] for any mesh that fits in memory) and laid out depth first, the left child
//! right after its parent.

use bytemuck::Zeroable;
use rayon::prelude::*;

use super::lattice::LatticeMesh;
use crate::kernels::shared::{CELL_UNITS, LatticePoint, TreeNode, TreeTriangle, TriangleBox};

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;

/// Traversal stack entries; a median-split tree over `n` triangles is `log2(n / LEAF_SIZE) + 1`
/// deep.
pub const STACK_SIZE: usize = 40;

impl TreeTriangle {
    /// Squared distance in cells from grid corner `corner`; the body the distance kernel shares.
    pub fn distance_squared(&self, corner: [i32; 3]) -> f32 {
        let p: [f32; 3] = std::array::from_fn(|k| (corner[k] - self.base[k]) as f32);
        point_triangle_distance_squared(p, self.a, self.b, self.c)
    }
}

impl TriangleBox {
    /// Squared distance from `p` (cells from the tree's base) to the box, 0 inside.
    pub fn distance_squared(&self, p: [f32; 3]) -> f32 {
        box_distance_squared(self.min, self.max, p)
    }
}

/// The tree over a mesh, in cells from `base` (the mesh's lowest cell).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleTree {
    base: [i32; 3],
    nodes: Vec<TreeNode>,
    triangles: Vec<TreeTriangle>,
    boxes: Vec<TriangleBox>,
    disks: Vec<[f32; 4]>,
}

/// The centroid of `t` (cells from its base) and the largest distance from it to a corner,
/// enlarged to cover the rounding of both in f32: every point of the triangle lies within the
/// radius of the centroid.
fn disk(t: &TreeTriangle) -> [f32; 4] {
    let centroid: [f32; 3] = std::array::from_fn(|k| (t.a[k] + t.b[k] + t.c[k]) / 3.0);
    let reach = |v: [f32; 3]| {
        let d: [f32; 3] = std::array::from_fn(|k| v[k] - centroid[k]);
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    };
    let radius = reach(t.a).max(reach(t.b)).max(reach(t.c));
    [
        centroid[0],
        centroid[1],
        centroid[2],
        radius * (1.0 + 1e-5) + 1e-5,
    ]
}

/// One triangle while building: its index and the centre of its box.
#[derive(Clone, Copy)]
struct Item {
    id: u32,
    centroid: [f32; 3],
}

/// Subtrees with more triangles than this build their halves in parallel.
const PARALLEL_BUILD: usize = 4096;

impl TriangleTree {
    pub fn build(mesh: &LatticeMesh) -> Self {
        let points = mesh.points();
        let base: [i32; 3] =
            std::array::from_fn(|a| points.iter().map(|p| p.cell[a]).min().unwrap_or(0));
        let coordinate = |p: &LatticePoint, a: usize| {
            f64::from(p.cell[a] - base[a]) + f64::from(p.frac[a]) / CELL_UNITS as f64
        };
        let boxes_by_id: Vec<TriangleBox> = mesh
            .triangles()
            .par_iter()
            .map(|tri| {
                let p = tri.map(|v| points[v as usize]);
                let min: [f64; 3] = std::array::from_fn(|a| {
                    p.iter()
                        .map(|q| coordinate(q, a))
                        .fold(f64::INFINITY, f64::min)
                });
                let max: [f64; 3] = std::array::from_fn(|a| {
                    p.iter()
                        .map(|q| coordinate(q, a))
                        .fold(f64::NEG_INFINITY, f64::max)
                });
                TriangleBox {
                    min: min.map(round_down),
                    max: max.map(round_up),
                }
            })
            .collect();
        let mut items: Vec<Item> = boxes_by_id
            .iter()
            .enumerate()
            .map(|(t, b)| Item {
                id: t as u32,
                centroid: std::array::from_fn(|a| (b.min[a] + b.max[a]) * 0.5),
            })
            .collect();
        let mut nodes = vec![TreeNode::zeroed(); node_count(items.len())];
        if !items.is_empty() {
            build_node(&mut items, &boxes_by_id, &mut nodes, 0, 0);
        }
        let triangles: Vec<TreeTriangle> = items
            .par_iter()
            .map(|item| tree_triangle(mesh, item.id))
            .collect();
        let boxes = items
            .iter()
            .map(|item| boxes_by_id[item.id as usize])
            .collect();
        let disks = triangles.par_iter().map(disk).collect();
        Self {
            base,
            nodes,
            triangles,
            boxes,
            disks,
        }
    }

    pub fn base(&self) -> [i32; 3] {
        self.base
    }

    pub fn nodes(&self) -> &[TreeNode] {
        &self.nodes
    }

    pub fn triangles(&self) -> &[TreeTriangle] {
        &self.triangles
    }

    pub fn boxes(&self) -> &[TriangleBox] {
        &self.boxes
    }

    /// Per triangle slot, a disk in its plane that holds it: the centroid (cells from the
    /// triangle's `base`) and a radius rounded up.
    pub fn disks(&self) -> &[[f32; 4]] {
        &self.disks
    }

    /// Cells from the tree's base to `corner`, exact.
    pub fn local(&self, corner: [i32; 3]) -> [f32; 3] {
        std::array::from_fn(|k| (corner[k] - self.base[k]) as f32)
    }

    /// Appends to `out` the slots of every triangle whose box lies closer than `bound` (squared)
    /// to the box `lo ..= hi` (cells from the base); stops at `capacity` slots and returns false
    /// when there are more.
    pub fn gather(
        &self,
        lo: [f32; 3],
        hi: [f32; 3],
        bound: f32,
        capacity: usize,
        out: &mut Vec<u32>,
    ) -> bool {
        if self.nodes.is_empty() {
            return true;
        }
        let near = |min: [f32; 3], max: [f32; 3]| {
            let d: f32 = (0..3)
                .map(|a| {
                    let g = (min[a] - hi[a]).max(lo[a] - max[a]).max(0.0);
                    g * g
                })
                .sum();
            d < bound
        };
        let mut stack = [0u32; STACK_SIZE];
        let mut depth = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if near(n.min, n.max) {
                if n.count > 0 {
                    for slot in n.index..n.index + n.count {
                        let b = &self.boxes[slot as usize];
                        if near(b.min, b.max) {
                            if out.len() == capacity {
                                return false;
                            }
                            out.push(slot);
                        }
                    }
                } else {
                    stack[depth] = n.index;
                    depth += 1;
                    node += 1;
                    continue;
                }
            }
            if depth == 0 {
                return true;
            }
            depth -= 1;
            node = stack[depth] as usize;
        }
    }

    /// The triangle slot nearest to `corner` and its squared distance in cells, when closer than
    /// `best` (squared); otherwise `(best, found)` unchanged. A full traversal, nearer child first.
    pub fn nearest(&self, corner: [i32; 3], mut best: f32, mut found: u32) -> (f32, u32) {
        if self.nodes.is_empty() {
            return (best, found);
        }
        let p = self.local(corner);
        let mut stack = [0u32; STACK_SIZE];
        let mut depth = 0;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if n.count > 0 {
                for slot in n.index..n.index + n.count {
                    let d = self.triangles[slot as usize].distance_squared(corner);
                    if d < best {
                        best = d;
                        found = slot;
                    }
                }
            } else {
                let (left, right) = (node + 1, n.index as usize);
                let dl = node_distance_squared(&self.nodes[left], p);
                let dr = node_distance_squared(&self.nodes[right], p);
                let (near, far, dn, df) = if dl <= dr {
                    (left, right, dl, dr)
                } else {
                    (right, left, dr, dl)
                };
                if dn < best {
                    if df < best {
                        stack[depth] = far as u32;
                        depth += 1;
                    }
                    node = near;
                    continue;
                }
            }
            // Pop the next subtree still closer than the best so far.
            loop {
                if depth == 0 {
                    return (best, found);
                }
                depth -= 1;
                node = stack[depth] as usize;
                if node_distance_squared(&self.nodes[node], p) < best {
                    break;
                }
            }
        }
    }
}

/// Nodes of a median-split tree over `n` triangles.
fn node_count(n: usize) -> usize {
    if n == 0 {
        0
    } else if n <= LEAF_SIZE {
        1
    } else {
        1 + node_count(n / 2) + node_count(n - n / 2)
    }
}

/// Writes the subtree over `items` into `nodes`, whose first entry is node number `at`, with leaf
/// slots from `first`, reordering `items` into leaf order, and returns the subtree's box. Halves
/// are built in parallel; the layout is fixed by the counts alone, so it does not depend on the
/// thread count.
fn build_node(
    items: &mut [Item],
    boxes: &[TriangleBox],
    nodes: &mut [TreeNode],
    at: usize,
    first: usize,
) -> TriangleBox {
    if items.len() <= LEAF_SIZE {
        let mut min = [f32::INFINITY; 3];
        let mut max = [f32::NEG_INFINITY; 3];
        for item in items.iter() {
            let b = &boxes[item.id as usize];
            for a in 0..3 {
                min[a] = min[a].min(b.min[a]);
                max[a] = max[a].max(b.max[a]);
            }
        }
        nodes[0] = TreeNode {
            min,
            index: first as u32,
            max,
            count: items.len() as u32,
        };
        return TriangleBox { min, max };
    }
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for item in items.iter() {
        for a in 0..3 {
            lo[a] = lo[a].min(item.centroid[a]);
            hi[a] = hi[a].max(item.centroid[a]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0);
    let half = items.len() / 2;
    items.select_nth_unstable_by(half, |x, y| {
        x.centroid[axis]
            .total_cmp(&y.centroid[axis])
            .then(x.id.cmp(&y.id))
    });
    let left_nodes = node_count(half);
    let (left_items, right_items) = items.split_at_mut(half);
    let (own, children) = nodes.split_at_mut(1);
    let (left, right) = children.split_at_mut(left_nodes);
    let right_at = at + 1 + left_nodes;
    let (l, r) = if left_items.len() > PARALLEL_BUILD {
        rayon::join(
            || build_node(left_items, boxes, left, at + 1, first),
            || build_node(right_items, boxes, right, right_at, first + half),
        )
    } else {
        (
            build_node(left_items, boxes, left, at + 1, first),
            build_node(right_items, boxes, right, right_at, first + half),
        )
    };
    // The node's box is the union of its children's: the same as over its triangles, without
    // visiting their boxes again at every level.
    let min = std::array::from_fn(|a| l.min[a].min(r.min[a]));
    let max = std::array::from_fn(|a| l.max[a].max(r.max[a]));
    own[0] = TreeNode {
        min,
        index: right_at as u32,
        max,
        count: 0,
    };
    TriangleBox { min, max }
}

/// Triangle `t` with its corners as offsets from its lowest cell.
fn tree_triangle(mesh: &LatticeMesh, t: u32) -> TreeTriangle {
    let corners = mesh.corners(t as usize);
    let base: [i32; 3] =
        std::array::from_fn(|a| corners.iter().map(|p| p.cell[a]).min().unwrap_or(0));
    let local = |p: &LatticePoint| -> [f64; 3] {
        std::array::from_fn(|a| {
            f64::from(p.cell[a] - base[a]) + f64::from(p.frac[a]) / CELL_UNITS as f64
        })
    };
    let [a, b, c] = corners.map(|p| local(&p));
    let (u, v): ([f64; 3], [f64; 3]) = (
        std::array::from_fn(|k| b[k] - a[k]),
        std::array::from_fn(|k| c[k] - a[k]),
    );
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let normal = if length > 0.0 {
        n.map(|x| x / length)
    } else {
        [0.0; 3]
    };
    TreeTriangle {
        base,
        id: t,
        a: a.map(|x| x as f32),
        b: b.map(|x| x as f32),
        c: c.map(|x| x as f32),
        normal: normal.map(|x| x as f32),
        offset: (normal[0] * a[0] + normal[1] * a[1] + normal[2] * a[2]) as f32,
    }
}

/// Largest f32 not above `x`.
fn round_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x { f.next_down() } else { f }
}

/// Smallest f32 not below `x`.
fn round_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x { f.next_up() } else { f }
}

/// Squared distance from `p` to a node's box (0 inside).
fn node_distance_squared(n: &TreeNode, p: [f32; 3]) -> f32 {
    box_distance_squared(n.min, n.max, p)
}

fn box_distance_squared(min: [f32; 3], max: [f32; 3], p: [f32; 3]) -> f32 {
    let d: [f32; 3] = std::array::from_fn(|a| (min[a] - p[a]).max(p[a] - max[a]).max(0.0));
    d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn along(a: [f32; 3], d: [f32; 3], s: f32) -> [f32; 3] {
    [a[0] + d[0] * s, a[1] + d[1] * s, a[2] + d[2] * s]
}

/// Squared distance from `p` to the triangle `abc` by the Voronoi regions of its corners, edges
/// and face (Ericson, Real-Time Collision Detection §5.1.5). Each division is guarded by its
/// denominator's sign and a degenerate triangle falls through to its edges, so the result is always
/// finite.
pub(crate) fn point_triangle_distance_squared(
    p: [f32; 3],
    a: [f32; 3],
    b: [f32; 3],
    c: [f32; 3],
) -> f32 {
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return dot(ap, ap);
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return dot(bp, bp);
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return dot(cp, cp);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0 {
        let q = sub(p, along(a, ab, d1 / (d1 - d3)));
        return dot(q, q);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0 {
        let q = sub(p, along(a, ac, d2 / (d2 - d6)));
        return dot(q, q);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0 {
        let q = sub(p, along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
        return dot(q, q);
    }
    let sum = va + vb + vc;
    if sum > 0.0 {
        let (v, w) = (vb / sum, vc / sum);
        let q = sub(p, along(along(a, ab, v), ac, w));
        return dot(q, q);
    }
    segment_distance_squared(p, a, b)
        .min(segment_distance_squared(p, b, c))
        .min(segment_distance_squared(p, c, a))
}

fn segment_distance_squared(p: [f32; 3], a: [f32; 3], b: [f32; 3]) -> f32 {
    let (ab, ap) = (sub(b, a), sub(p, a));
    let len = dot(ab, ab);
    let s = if len > 0.0 {
        (dot(ap, ab) / len).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = sub(p, along(a, ab, s));
    dot(q, q)
}
