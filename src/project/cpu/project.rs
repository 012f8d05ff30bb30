//! CPU twin of `kernels/project.wgsl`: for each source point `p` with unit normal `n`, the
//! nearest hit of the line `p + t·n` on the target in either direction (paper §4.2 casts the
//! normal ray both ways and keeps the nearer hit), found in one stack traversal ordered by `|t|`.
//!
//! One query per rayon task, each independent of the others, so results do not depend on the
//! thread count.

use glam::Vec3;
use rayon::prelude::*;

use crate::project::options::QueryParams;
use crate::project::slab::{MISS_KEY, Slabs};
use crate::project::watertight::Shear;
use crate::project::{Bvh, Correspondence, Status};

/// Projects every point along its direction (unit, or zero for a query to skip).
pub(in crate::project) fn project_cpu(
    bvh: &Bvh,
    points: &[Vec3],
    directions: &[Vec3],
    params: &QueryParams,
) -> Vec<Correspondence> {
    points
        .par_iter()
        .zip(directions)
        .map(|(&p, &n)| project_point(bvh, p, n, params))
        .collect()
}

/// The body of one kernel invocation.
fn project_point(bvh: &Bvh, p: Vec3, n: Vec3, params: &QueryParams) -> Correspondence {
    if n == Vec3::ZERO {
        return Correspondence::MISS;
    }
    let Some(hit) = nearest_hit(bvh, p, n, -f32::MAX, params.max_distance) else {
        return Correspondence::MISS;
    };
    let slot = hit.slot as usize;
    let normal = bvh.normals()[slot].blend(hit.weights);
    let status = if normal.dot(n) >= params.cos_max_angle {
        Status::Accepted
    } else {
        Status::NormalMismatch
    };
    Correspondence::new(
        p + n * hit.t,
        hit.t,
        normal,
        bvh.triangles()[slot].id,
        Vec3::from_array(hit.weights),
        status,
    )
}

/// The hit nearest to the origin of a line: leaf slot, parameter and barycentric weights.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(in crate::project) struct LineHit {
    pub slot: u32,
    pub t: f32,
    pub weights: [f32; 3],
}

/// The hit of `origin + t·direction` with the least `|t|` among `t ∈ [floor, ∞)`,
/// `|t| <= max_distance`; ties go to the lower triangle id, so the answer does not depend on the
/// order in which leaves are visited.
///
/// Nodes are visited nearest first; a node's key is the least `|t|` at which the line is inside its
/// box, and nodes whose key exceeds the best `|t|` so far are skipped.
#[inline(never)]
pub(in crate::project) fn nearest_hit(
    bvh: &Bvh,
    origin: Vec3,
    direction: Vec3,
    floor: f32,
    max_distance: f32,
) -> Option<LineHit> {
    let nodes = bvh.nodes();
    let triangles = bvh.triangles();
    let slabs = Slabs::new(origin, direction);
    let shear = Shear::new(origin, direction);
    let mut best = max_distance;
    let mut best_id = u32::MAX;
    let mut found: Option<LineHit> = None;
    let mut stack = [(0u32, 0.0f32); Bvh::STACK_SIZE];
    let mut sp = 0usize;
    let mut node = nodes[0];
    loop {
        if node.is_leaf() {
            for slot in node.index..node.index + node.count {
                let tri = &triangles[slot as usize];
                let Some(hit) = shear.intersect(tri) else {
                    continue;
                };
                let distance = hit.t.abs();
                if hit.t >= floor && (distance < best || (distance == best && tri.id < best_id)) {
                    best = distance;
                    best_id = tri.id;
                    found = Some(LineHit {
                        slot,
                        t: hit.t,
                        weights: hit.weights,
                    });
                }
            }
        } else {
            let lo = floor.max(-best);
            let left = node.index as usize;
            let key_left = slabs.key(&nodes[left], lo, best);
            let key_right = slabs.key(&nodes[left + 1], lo, best);
            let hit_left = key_left != MISS_KEY;
            let hit_right = key_right != MISS_KEY;
            if hit_left && hit_right {
                let (near, far, far_key) = if key_right < key_left {
                    (left + 1, left, key_left)
                } else {
                    (left, left + 1, key_right)
                };
                stack[sp] = (far as u32, far_key);
                sp += 1;
                node = nodes[near];
                continue;
            }
            if hit_left || hit_right {
                node = nodes[if hit_left { left } else { left + 1 }];
                continue;
            }
        }
        loop {
            if sp == 0 {
                return found;
            }
            sp -= 1;
            let (next, key) = stack[sp];
            if key <= best {
                node = nodes[next as usize];
                break;
            }
        }
    }
}

pub static NODES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
pub static TRIS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
