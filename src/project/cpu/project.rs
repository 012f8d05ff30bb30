//! CPU twin of `kernels/project.wgsl`: for each source point `p` with unit normal `n`, the
//! nearest hit of the line `p + t·n` on the target in either direction (paper §4.2 casts the
//! normal ray both ways and keeps the nearer hit), found in one stack traversal ordered by `|t|`.
//!
//! One query per rayon task, each independent of the others, so results do not depend on the
//! thread count.

use glam::Vec3;
use rayon::prelude::*;

use super::traversal::Stack;
use crate::kernels::shared::{BvhNode, Correspondence, QueryParams, Status};
use crate::project::Bvh;
use crate::project::slab::Slabs;
use crate::project::watertight::Shear;

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
/// At each node the four children's keys (the least `|t|` at which the line is inside the box)
/// are computed at once; leaf children are tested on the spot, then interior children whose key
/// does not exceed the best `|t|` so far are visited nearest first, the others kept on the stack.
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
    let mut stack = Stack::new();
    let mut node: &BvhNode = &nodes[0];
    loop {
        let (keys, hits) = slabs.keys(node, floor.max(-best), best);
        let hits = hits.bitmask();
        for k in 0..4 {
            let count = node.count[k];
            if hits & (1 << k) == 0 || count == 0 || count == BvhNode::EMPTY {
                continue;
            }
            for slot in node.child[k]..node.child[k] + count {
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
        }
        let next = stack
            .descend(node, keys.to_array(), |k| hits & (1 << k) != 0, best)
            .or_else(|| stack.pop(best));
        match next {
            Some(next) => node = &nodes[next as usize],
            None => return found,
        }
    }
}
