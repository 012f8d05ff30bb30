//! CPU twin of `kernels/closest_point.wgsl`: for each point, the nearest point of the target
//! surface, its distance signed by the target's orientation (negative inside), found in one stack
//! traversal ordered by box distance.
//!
//! One query per rayon task, each independent of the others, so results do not depend on the
//! thread count.

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use crate::project::options::QueryParams;
use crate::project::point_triangle::{closest_on_triangle, side_normal};
use crate::project::{Bvh, BvhNode, Correspondence, Status};

/// The nearest surface point of every point.
pub(in crate::project) fn closest_point_cpu(
    bvh: &Bvh,
    points: &[Vec3],
    params: &QueryParams,
) -> Vec<Correspondence> {
    points
        .par_iter()
        .map(|&p| closest_point(bvh, p, params))
        .collect()
}

/// Squared distance from `p` to `node`'s box (0 inside).
#[inline(always)]
fn box_distance2(node: &BvhNode, p: Vec3A) -> f32 {
    let d = (Vec3A::from(node.min) - p)
        .max(p - Vec3A::from(node.max))
        .max(Vec3A::ZERO);
    d.dot(d)
}

/// The body of one kernel invocation. Ties in distance go to the lower triangle id, so the answer
/// does not depend on the order in which leaves are visited.
fn closest_point(bvh: &Bvh, p: Vec3, params: &QueryParams) -> Correspondence {
    if !p.is_finite() {
        return Correspondence::MISS;
    }
    let nodes = bvh.nodes();
    let triangles = bvh.triangles();
    let pa = Vec3A::from(p);
    let mut best = params.max_distance * params.max_distance;
    let mut best_id = u32::MAX;
    let mut best_slot = u32::MAX;
    let mut stack = [(0u32, 0.0f32); Bvh::STACK_SIZE];
    let mut sp = 0usize;
    let mut node = nodes[0];
    loop {
        if node.is_leaf() {
            for slot in node.index..node.index + node.count {
                let tri = &triangles[slot as usize];
                let q = closest_on_triangle(p, tri).point;
                let distance2 = (p - q).length_squared();
                if distance2 < best || (distance2 == best && tri.id < best_id) {
                    best = distance2;
                    best_id = tri.id;
                    best_slot = slot;
                }
            }
        } else {
            let left = node.index as usize;
            let key_left = box_distance2(&nodes[left], pa);
            let key_right = box_distance2(&nodes[left + 1], pa);
            let hit_left = key_left <= best;
            let hit_right = key_right <= best;
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
                return finish(bvh, p, best_slot);
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

/// The correspondence for the nearest triangle `slot` (none found: `u32::MAX`).
fn finish(bvh: &Bvh, p: Vec3, slot: u32) -> Correspondence {
    let slot = slot as usize;
    let Some(tri) = bvh.triangles().get(slot) else {
        return Correspondence::MISS;
    };
    let nearest = closest_on_triangle(p, tri);
    let side = side_normal(tri, &bvh.pseudo_normals()[slot], nearest.feature);
    let distance = (p - nearest.point).length();
    let signed = if (p - nearest.point).dot(side) < 0.0 {
        -distance
    } else {
        distance
    };
    Correspondence::new(
        nearest.point,
        signed,
        bvh.normals()[slot].blend(nearest.weights),
        tri.id,
        Vec3::from_array(nearest.weights),
        Status::Accepted,
    )
}
