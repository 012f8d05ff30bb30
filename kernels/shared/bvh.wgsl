// BVH layout and query records shared by project.wgsl and closest_point.wgsl. Mirrored by Rust
// structs in src/kernels/shared/bvh/ (node.rs, triangle.rs, correspondence.rs, query_params.rs) and constants
// there (Bvh::STACK_SIZE, Status codes); tests compare both with what naga reports for this file.
// `vec3<f32>` aligns to 16 bytes, so every vec3 is followed by a 4-byte member, a payload or an
// explicit padding word written as 0.

// Entries of a traversal stack: at most three per level, and the tree is at most 20 levels deep.
const STACK_SIZE: u32 = 64u;
// `count` of an unused child slot.
const EMPTY_CHILD: u32 = 0xffffffffu;

const STATUS_MISS: u32 = 0u;
const STATUS_ACCEPTED: u32 = 1u;
const STATUS_NORMAL_MISMATCH: u32 = 2u;
const NO_TRIANGLE: u32 = 0xffffffffu;

// A 4-wide node: the boxes of its four children axis by axis (lane k is child k). Per child,
// `count` is 0 for an interior node (`child` is its node index), the number of triangles of a
// leaf (`child` is its first slot), or EMPTY_CHILD for an unused slot.
struct BvhNode {
    min_x: vec4<f32>,
    min_y: vec4<f32>,
    min_z: vec4<f32>,
    max_x: vec4<f32>,
    max_y: vec4<f32>,
    max_z: vec4<f32>,
    child: vec4<u32>,
    count: vec4<u32>,
}

// A triangle in leaf order: corners in the target's winding, and its index in the target mesh.
struct BvhTriangle {
    a: vec3<f32>,
    id: u32,
    b: vec3<f32>,
    pad_b: u32,
    c: vec3<f32>,
    pad_c: u32,
}

// One vector per corner (a, b, c) or per edge (ab, bc, ca).
struct NormalTriple {
    a: vec3<f32>,
    pad_a: u32,
    b: vec3<f32>,
    pad_b: u32,
    c: vec3<f32>,
    pad_c: u32,
}

// Angle-weighted pseudo-normals (Bærentzen & Aanæs 2005) of a triangle's corners and edges.
struct PseudoNormals {
    vertices: NormalTriple,
    edges: NormalTriple,
}

struct Correspondence {
    point: vec3<f32>,
    distance: f32,
    normal: vec3<f32>,
    triangle: u32,
    barycentric: vec3<f32>,
    status: u32,
}

struct QueryParams {
    max_distance: f32,
    cos_max_angle: f32,
    pad: array<u32, 2>,
}

fn load_vec3(p: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(p[0], p[1], p[2]);
}

fn miss() -> Correspondence {
    return Correspondence(vec3<f32>(0.0), 0.0, vec3<f32>(0.0), NO_TRIANGLE, vec3<f32>(0.0), STATUS_MISS);
}

// `w.x·a + w.y·b + w.z·c`, normalised (zero when the blend vanishes).
fn blend(t: NormalTriple, w: vec3<f32>) -> vec3<f32> {
    let n = t.a * w.x + t.b * w.y + t.c * w.z;
    let length2 = dot(n, n);
    if length2 > 0.0 {
        return n / sqrt(length2);
    }
    return vec3<f32>(0.0);
}

// The traversal both query kernels share (twin: src/project/cpu/traversal.rs): a stack of nodes
// with their keys, private to each invocation. A kernel tests a node's leaf children, then asks
// `descend` for the interior child to visit next and, when there is none, `pop`s one.
const NO_NODE: u32 = 0xffffffffu;
var<private> stack_node: array<u32, STACK_SIZE>;
var<private> stack_key: array<f32, STACK_SIZE>;
var<private> sp: u32;

// The interior children `k` of `node` with `visit[k]` and `key[k] <= best`, nearest first: returns
// the nearest (NO_NODE when there is none) and pushes the others, farthest first.
fn descend(node: BvhNode, key: vec4<f32>, visit: vec4<bool>, best: f32) -> u32 {
    var near_node: array<u32, 4>;
    var near_key: array<f32, 4>;
    var n_near = 0u;
    for (var k = 0u; k < 4u; k += 1u) {
        if visit[k] && node.count[k] == 0u && key[k] <= best {
            // Insertion by key, nearest first.
            var j = n_near;
            while j > 0u && near_key[j - 1u] > key[k] {
                near_node[j] = near_node[j - 1u];
                near_key[j] = near_key[j - 1u];
                j -= 1u;
            }
            near_node[j] = node.child[k];
            near_key[j] = key[k];
            n_near += 1u;
        }
    }
    if n_near == 0u {
        return NO_NODE;
    }
    for (var j = n_near - 1u; j > 0u; j -= 1u) {
        stack_node[sp] = near_node[j];
        stack_key[sp] = near_key[j];
        sp += 1u;
    }
    return near_node[0];
}

// The next stacked node whose key is not above `best`, NO_NODE when none is left.
fn pop(best: f32) -> u32 {
    while sp > 0u {
        sp -= 1u;
        if stack_key[sp] <= best {
            return stack_node[sp];
        }
    }
    return NO_NODE;
}
