//! CPU twin of `kernels/closest_point.wgsl`: for each point, the nearest point of the target
//! surface, its distance signed by the target's orientation (negative inside), found in one stack
//! traversal ordered by box distance.
//!
//! One query per rayon task, each independent of the others, so results do not depend on the
//! thread count.

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::traversal::Stack;
use crate::geometry::{Region, region};
use crate::kernels::shared::{
    BvhNode, BvhTriangle, Correspondence, NormalTriple, PseudoNormals, QueryParams, Status,
};
use crate::project::Bvh;

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

/// Per child: the squared distance from `p` to the child's box (0 inside).
#[inline(always)]
fn box_distance2(node: &BvhNode, p: [Vec4; 3]) -> Vec4 {
    let axis = |min: [f32; 4], max: [f32; 4], p: Vec4| {
        let d = (Vec4::from(min) - p)
            .max(p - Vec4::from(max))
            .max(Vec4::ZERO);
        d * d
    };
    axis(node.min_x, node.max_x, p[0])
        + axis(node.min_y, node.max_y, p[1])
        + axis(node.min_z, node.max_z, p[2])
}

/// The body of one kernel invocation. Ties in distance go to the lower triangle id, so the answer
/// does not depend on the order in which leaves are visited.
fn closest_point(bvh: &Bvh, p: Vec3, params: &QueryParams) -> Correspondence {
    if !p.is_finite() {
        return Correspondence::MISS;
    }
    let nodes = bvh.nodes();
    let triangles = bvh.triangles();
    let splat = p.to_array().map(Vec4::splat);
    let mut best = params.max_distance * params.max_distance;
    let mut best_id = u32::MAX;
    let mut best_slot = u32::MAX;
    let mut stack = Stack::new();
    let mut node: &BvhNode = &nodes[0];
    loop {
        let keys = box_distance2(node, splat);
        for k in 0..4 {
            let count = node.count[k];
            if count == 0 || count == BvhNode::EMPTY || keys[k] > best {
                continue;
            }
            for slot in node.child[k]..node.child[k] + count {
                let tri = &triangles[slot as usize];
                let q = closest_on_triangle(p, tri).point;
                let distance2 = (p - q).length_squared();
                if distance2 < best || (distance2 == best && tri.id < best_id) {
                    best = distance2;
                    best_id = tri.id;
                    best_slot = slot;
                }
            }
        }
        let next = stack
            .descend(node, keys.to_array(), |_| true, best)
            .or_else(|| stack.pop(best));
        match next {
            Some(next) => node = &nodes[next as usize],
            None => return finish(bvh, p, best_slot),
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
    let side = side_normal(tri, &bvh.pseudo_normals()[slot], nearest.region);
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

/// The nearest point, its barycentric weights and the region it lies in, which decides the sign
/// of the distance.
pub(in crate::project) struct Nearest {
    pub point: Vec3,
    pub weights: [f32; 3],
    pub region: Region<f32>,
}

/// The point of `tri` nearest to `p`, with the weights `closest_on_triangle` in
/// `kernels/closest_point.wgsl` computes.
#[inline(always)]
pub(in crate::project) fn closest_on_triangle(p: Vec3, tri: &BvhTriangle) -> Nearest {
    let [a, b, c] = tri.corners();
    let found = region(p, a, b, c);
    let weights = match found {
        Region::Vertex(k) => {
            let mut w = [0.0; 3];
            w[k] = 1.0;
            w
        }
        Region::Edge(0, s) => [1.0 - s, s, 0.0],
        Region::Edge(1, s) => [0.0, 1.0 - s, s],
        Region::Edge(_, s) => [1.0 - s, 0.0, s],
        Region::Face(v, w) => [1.0 - v - w, v, w],
        // Only a degenerate (zero-area) triangle gets here; its corner a is as good as any point.
        Region::Degenerate => [1.0, 0.0, 0.0],
    };
    let point = match found {
        Region::Vertex(k) => [a, b, c][k],
        Region::Degenerate => a,
        _ => a * weights[0] + b * weights[1] + c * weights[2],
    };
    Nearest {
        point,
        weights,
        region: found,
    }
}

/// The normal whose side of the surface `p` is on when its nearest point lies in `region`: the
/// face normal inside the face, the pseudo-normal on an edge or at a corner.
fn side_normal(tri: &BvhTriangle, pseudo: &PseudoNormals, region: Region<f32>) -> Vec3 {
    let pick = |t: &NormalTriple, k: usize| match k {
        0 => t.a,
        1 => t.b,
        _ => t.c,
    };
    match region {
        Region::Vertex(k) => pick(&pseudo.vertices, k),
        Region::Edge(k, _) => pick(&pseudo.edges, k),
        Region::Degenerate => pick(&pseudo.vertices, 0),
        Region::Face(..) => (tri.b - tri.a).cross(tri.c - tri.a),
    }
}
