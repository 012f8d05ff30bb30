// Closest point on the target (evaluation and the fine stage, paper §4.2): for each point p, the
// nearest point q of the target surface and |p − q| signed by the target's orientation (negative
// inside), found in one stack traversal of the BVH ordered by box distance. The sign comes from
// the pseudo-normal of the feature q lies on (Bærentzen & Aanæs 2005).
// CPU twin: src/project/cpu/closest_point.rs. Prepended: shared/bvh.wgsl.

@group(0) @binding(0) var<storage, read> params: QueryParams;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read> triangles: array<BvhTriangle>;
@group(0) @binding(3) var<storage, read> normals: array<NormalTriple>;
@group(0) @binding(4) var<storage, read> pseudo_normals: array<PseudoNormals>;
@group(0) @binding(5) var<storage, read> points: array<array<f32, 3>>;
@group(0) @binding(6) var<storage, read_write> correspondences: array<Correspondence>;

const WORKGROUP_SIZE: u32 = 64u;

// Where on the triangle the nearest point lies: corners 0..2, edges 3..5 (ab, bc, ca), face 6.
const FEATURE_EDGE: u32 = 3u;
const FEATURE_FACE: u32 = 6u;

struct Nearest {
    point: vec3<f32>,
    weights: vec3<f32>,
    feature: u32,
}

fn nearest_at(tri: BvhTriangle, weights: vec3<f32>, feature: u32) -> Nearest {
    return Nearest(tri.a * weights.x + tri.b * weights.y + tri.c * weights.z, weights, feature);
}

// Ericson 2005, "Real-Time Collision Detection" §5.1.5: Voronoi regions, vertex, edge, then face.
fn closest_on_triangle(p: vec3<f32>, tri: BvhTriangle) -> Nearest {
    let a = tri.a;
    let b = tri.b;
    let c = tri.c;
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return Nearest(a, vec3<f32>(1.0, 0.0, 0.0), 0u);
    }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return Nearest(b, vec3<f32>(0.0, 1.0, 0.0), 1u);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let s = d1 / (d1 - d3);
        return nearest_at(tri, vec3<f32>(1.0 - s, s, 0.0), FEATURE_EDGE);
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return Nearest(c, vec3<f32>(0.0, 0.0, 1.0), 2u);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let s = d2 / (d2 - d6);
        return nearest_at(tri, vec3<f32>(1.0 - s, 0.0, s), FEATURE_EDGE + 2u);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return nearest_at(tri, vec3<f32>(0.0, 1.0 - s, s), FEATURE_EDGE + 1u);
    }
    let sum = va + vb + vc;
    if !(sum > 0.0) {
        // Only a degenerate (zero-area) triangle gets here; its corner a is as good as any point.
        return Nearest(a, vec3<f32>(1.0, 0.0, 0.0), 0u);
    }
    let v = vb / sum;
    let w = vc / sum;
    return nearest_at(tri, vec3<f32>(1.0 - v - w, v, w), FEATURE_FACE);
}

fn pick(t: NormalTriple, k: u32) -> vec3<f32> {
    if k == 0u {
        return t.a;
    }
    if k == 1u {
        return t.b;
    }
    return t.c;
}

// The normal whose side of the surface p is on: face normal inside the face, the pseudo-normal
// on an edge or at a corner.
fn side_normal(tri: BvhTriangle, pseudo: PseudoNormals, feature: u32) -> vec3<f32> {
    if feature < FEATURE_EDGE {
        return pick(pseudo.vertices, feature);
    }
    if feature < FEATURE_FACE {
        return pick(pseudo.edges, feature - FEATURE_EDGE);
    }
    return cross(tri.b - tri.a, tri.c - tri.a);
}

// Per child: the squared distance from p to the child's box (0 inside).
fn box_distance2(node: BvhNode, p: vec3<f32>) -> vec4<f32> {
    let dx = max(max(node.min_x - p.x, p.x - node.max_x), vec4<f32>(0.0));
    let dy = max(max(node.min_y - p.y, p.y - node.max_y), vec4<f32>(0.0));
    let dz = max(max(node.min_z - p.z, p.z - node.max_z), vec4<f32>(0.0));
    return dx * dx + dy * dy + dz * dz;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let i = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if i >= arrayLength(&points) {
        return;
    }
    let p = load_vec3(points[i]);
    var best = params.max_distance * params.max_distance;
    var best_id = NO_TRIANGLE;
    var best_slot = NO_TRIANGLE;
    sp = 0u;
    var node = nodes[0];
    loop {
        let keys = box_distance2(node, p);
        for (var k = 0u; k < 4u; k += 1u) {
            let count = node.count[k];
            if count == 0u || count == EMPTY_CHILD || keys[k] > best {
                continue;
            }
            for (var slot = node.child[k]; slot < node.child[k] + count; slot += 1u) {
                let tri = triangles[slot];
                let q = closest_on_triangle(p, tri).point;
                let distance2 = dot(p - q, p - q);
                if distance2 < best || (distance2 == best && tri.id < best_id) {
                    best = distance2;
                    best_id = tri.id;
                    best_slot = slot;
                }
            }
        }
        var next = descend(node, keys, vec4<bool>(true), best);
        if next == NO_NODE {
            next = pop(best);
        }
        if next == NO_NODE {
            break;
        }
        node = nodes[next];
    }
    if best_slot == NO_TRIANGLE {
        correspondences[i] = miss();
        return;
    }
    let tri = triangles[best_slot];
    let nearest = closest_on_triangle(p, tri);
    let side = side_normal(tri, pseudo_normals[best_slot], nearest.feature);
    let offset = p - nearest.point;
    var distance = sqrt(dot(offset, offset));
    if dot(offset, side) < 0.0 {
        distance = -distance;
    }
    correspondences[i] = Correspondence(
        nearest.point,
        distance,
        blend(normals[best_slot], nearest.weights),
        best_id,
        nearest.weights,
        STATUS_ACCEPTED,
    );
}
