// Correspondence projection (paper §4.2): for each source point p with unit normal n, the nearest
// hit of the line p + t·n on the target in either direction, found in one stack traversal of the
// BVH ordered by |t|, with watertight ray–triangle tests (Woop, Benthin & Wald 2013).
// CPU twin: src/project/cpu/project.rs. Prepended: shared/bvh.wgsl.

@group(0) @binding(0) var<storage, read> params: QueryParams;
@group(0) @binding(1) var<storage, read> nodes: array<BvhNode>;
@group(0) @binding(2) var<storage, read> triangles: array<BvhTriangle>;
@group(0) @binding(3) var<storage, read> normals: array<NormalTriple>;
@group(0) @binding(4) var<storage, read> points: array<array<f32, 3>>;
@group(0) @binding(5) var<storage, read> directions: array<array<f32, 3>>;
@group(0) @binding(6) var<storage, read_write> correspondences: array<Correspondence>;

const WORKGROUP_SIZE: u32 = 64u;
// Box intervals are widened by 4ε ≥ 2γ₃ (Ize 2013) so rounding never culls a box the line enters.
const WIDEN: f32 = 4.76837158e-7;
// Smaller direction components are replaced by ±this before the reciprocal: no NaN, no infinity.
const MIN_DIRECTION: f32 = 1e-18;

struct Slabs {
    origin: vec3<f32>,
    inv: vec3<f32>,
}

fn safe_component(d: f32) -> f32 {
    if abs(d) < MIN_DIRECTION {
        return select(MIN_DIRECTION, -MIN_DIRECTION, d < 0.0);
    }
    return d;
}

fn make_slabs(origin: vec3<f32>, direction: vec3<f32>) -> Slabs {
    let safe = vec3<f32>(safe_component(direction.x), safe_component(direction.y), safe_component(direction.z));
    return Slabs(origin, vec3<f32>(1.0) / safe);
}

// Per child: min |t| over the line's parameters inside the child's box and inside [lo, hi]
// (`key`), and whether there are any (`hit`).
struct SlabKeys {
    key: vec4<f32>,
    hit: vec4<bool>,
}

fn slab_keys(slabs: Slabs, node: BvhNode, lo: f32, hi: f32) -> SlabKeys {
    let tx0 = (node.min_x - slabs.origin.x) * slabs.inv.x;
    let tx1 = (node.max_x - slabs.origin.x) * slabs.inv.x;
    let ty0 = (node.min_y - slabs.origin.y) * slabs.inv.y;
    let ty1 = (node.max_y - slabs.origin.y) * slabs.inv.y;
    let tz0 = (node.min_z - slabs.origin.z) * slabs.inv.z;
    let tz1 = (node.max_z - slabs.origin.z) * slabs.inv.z;
    let enter_box = max(max(min(tx0, tx1), min(ty0, ty1)), min(tz0, tz1));
    let exit_box = min(min(max(tx0, tx1), max(ty0, ty1)), max(tz0, tz1));
    let enter = max(enter_box - abs(enter_box) * WIDEN, vec4<f32>(lo));
    let exit = min(exit_box + abs(exit_box) * WIDEN, vec4<f32>(hi));
    return SlabKeys(max(max(enter, -exit), vec4<f32>(0.0)), enter <= exit);
}

// The axis permutation making the direction's largest component z (keeping the winding) and the
// shear mapping the direction to +z.
struct Shear {
    kx: u32,
    ky: u32,
    kz: u32,
    s: vec3<f32>,
    origin: vec3<f32>,
}

fn make_shear(origin: vec3<f32>, direction: vec3<f32>) -> Shear {
    let a = abs(direction);
    var kz = 2u;
    if a.x >= a.y && a.x >= a.z {
        kz = 0u;
    } else if a.y >= a.z {
        kz = 1u;
    }
    var kx = (kz + 1u) % 3u;
    var ky = (kz + 2u) % 3u;
    if direction[kz] < 0.0 {
        let k = kx;
        kx = ky;
        ky = k;
    }
    let dz = direction[kz];
    return Shear(kx, ky, kz, vec3<f32>(direction[kx] / dz, direction[ky] / dz, 1.0 / dz), origin);
}

fn shear_vertex(shear: Shear, p: vec3<f32>) -> vec3<f32> {
    let z = p[shear.kz] - shear.origin[shear.kz];
    return vec3<f32>(
        p[shear.kx] - shear.origin[shear.kx] - shear.s.x * z,
        p[shear.ky] - shear.origin[shear.ky] - shear.s.y * z,
        shear.s.z * z,
    );
}

// The 2-D edge function p.x·q.y − p.y·q.x, evaluated on the lexicographically ordered pair and
// negated when the order was swapped. A GPU compiler may fuse a product-difference into an FMA,
// which breaks the exact antisymmetry E(p, q) = −E(q, p) watertightness rests on; one expression
// on the ordered pair restores it. (On the CPU the plain expression is exactly antisymmetric.)
fn edge_function(p: vec2<f32>, q: vec2<f32>) -> f32 {
    let swapped = q.x < p.x || (q.x == p.x && q.y < p.y);
    let lo = select(p, q, swapped);
    let hi = select(q, p, swapped);
    let e = lo.x * hi.y - lo.y * hi.x;
    return select(e, -e, swapped);
}

struct TriangleHit {
    hit: bool,
    t: f32,
    weights: vec3<f32>,
}

// Where the ray meets the triangle, at any t (both faces); no hit when it misses or lies in the
// triangle's plane.
fn intersect(shear: Shear, tri: BvhTriangle) -> TriangleHit {
    let a = shear_vertex(shear, tri.a);
    let b = shear_vertex(shear, tri.b);
    let c = shear_vertex(shear, tri.c);
    let u = edge_function(c.xy, b.xy);
    let v = edge_function(a.xy, c.xy);
    let w = edge_function(b.xy, a.xy);
    var result = TriangleHit(false, 0.0, vec3<f32>(0.0));
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return result;
    }
    let det = u + v + w;
    if det == 0.0 {
        return result;
    }
    let rcp = 1.0 / det;
    result.hit = true;
    result.t = (u * a.z + v * b.z + w * c.z) * rcp;
    result.weights = vec3<f32>(u * rcp, v * rcp, w * rcp);
    return result;
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
    let n = load_vec3(directions[i]);
    if all(n == vec3<f32>(0.0)) {
        correspondences[i] = miss();
        return;
    }
    let slabs = make_slabs(p, n);
    let shear = make_shear(p, n);
    var best = params.max_distance;
    var best_id = NO_TRIANGLE;
    var best_slot = NO_TRIANGLE;
    var best_t = 0.0;
    var best_weights = vec3<f32>(0.0);
    sp = 0u;
    var node = nodes[0];
    loop {
        let keys = slab_keys(slabs, node, -best, best);
        for (var k = 0u; k < 4u; k += 1u) {
            let count = node.count[k];
            if !keys.hit[k] || count == 0u || count == EMPTY_CHILD {
                continue;
            }
            for (var slot = node.child[k]; slot < node.child[k] + count; slot += 1u) {
                let tri = triangles[slot];
                let hit = intersect(shear, tri);
                let distance = abs(hit.t);
                if hit.hit && (distance < best || (distance == best && tri.id < best_id)) {
                    best = distance;
                    best_id = tri.id;
                    best_slot = slot;
                    best_t = hit.t;
                    best_weights = hit.weights;
                }
            }
        }
        var next = descend(node, keys.key, keys.hit, best);
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
    let normal = blend(normals[best_slot], best_weights);
    var status = STATUS_NORMAL_MISMATCH;
    if dot(normal, n) >= params.cos_max_angle {
        status = STATUS_ACCEPTED;
    }
    correspondences[i] = Correspondence(p + n * best_t, best_t, normal, best_id, best_weights, status);
}
