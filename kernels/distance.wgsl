// Narrow-band distance: the nearest triangle of each candidate corner, within the band.
// CPU twin: src/grid/cpu/distance.rs (`main`, the body of `main` here) with
// src/grid/triangle_tree.rs (`gather`, `nearest`, `point_triangle_distance_squared`). The CPU
// backend runs a variant, src/grid/cpu/distance_tiled.rs, which follows the same steps but prunes
// with tighter bounds computed eight triangles at a time, so all three find the same minimum.
// Prepended: shared/distance.wgsl.
//
// One invocation per tile: chunks of candidate corners along x whose triangles are gathered once
// (src/grid/gpu/distance.rs makes each chunk a tile of its own, see there why). The triangles
// whose boxes lie within the band of the tile's box are gathered; each corner bounds every
// gathered triangle's distance from below (the larger of its box's and its plane's), tests the
// previous corner's nearest first (for a chunk's first corner, the one with the least bound), then
// those whose bound is below the best so far. A tile near more than GATHER_CAPACITY triangles
// searches the tree once per corner instead. The bounds are recomputed where the CPU twin caches
// them, so an invocation keeps only its gathered slots in private memory.

@group(0) @binding(0) var<storage, read> params: array<DistanceParams>;
@group(0) @binding(1) var<storage, read> nodes: array<TreeNode>;
@group(0) @binding(2) var<storage, read> triangles: array<TreeTriangle>;
@group(0) @binding(3) var<storage, read> boxes: array<TriangleBox>;
@group(0) @binding(4) var<storage, read> chunks: array<BandChunk>;
@group(0) @binding(5) var<storage, read> tiles: array<BandTile>;
@group(0) @binding(6) var<storage, read_write> nearest: array<Nearest>;

const WORKGROUP_SIZE: u32 = 64u;

fn vec(a: array<f32, 3>) -> vec3<f32> {
    return vec3<f32>(a[0], a[1], a[2]);
}

fn box_distance_squared(lo: vec3<f32>, hi: vec3<f32>, p: vec3<f32>) -> f32 {
    let d = max(max(lo - p, p - hi), vec3<f32>(0.0));
    return d.x * d.x + d.y * d.y + d.z * d.z;
}

fn node_distance_squared(n: u32, p: vec3<f32>) -> f32 {
    return box_distance_squared(vec(nodes[n].min), vec(nodes[n].max), p);
}

// Squared distance between the boxes lo..hi and min..max.
fn boxes_distance_squared(lo: vec3<f32>, hi: vec3<f32>, min_: vec3<f32>, max_: vec3<f32>) -> f32 {
    let g = max(max(min_ - hi, lo - max_), vec3<f32>(0.0));
    return g.x * g.x + g.y * g.y + g.z * g.z;
}

fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

fn segment_distance_squared(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> f32 {
    let ab = b - a;
    let len = dot3(ab, ab);
    var s = 0.0;
    if len > 0.0 {
        s = clamp(dot3(p - a, ab) / len, 0.0, 1.0);
    }
    let q = p - (a + ab * s);
    return dot3(q, q);
}

fn point_triangle_distance_squared(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> f32 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot3(ab, ap);
    let d2 = dot3(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return dot3(ap, ap);
    }
    let bp = p - b;
    let d3 = dot3(ab, bp);
    let d4 = dot3(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return dot3(bp, bp);
    }
    let cp = p - c;
    let d5 = dot3(ab, cp);
    let d6 = dot3(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return dot3(cp, cp);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0 {
        let q = p - (a + ab * (d1 / (d1 - d3)));
        return dot3(q, q);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0 {
        let q = p - (a + ac * (d2 / (d2 - d6)));
        return dot3(q, q);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0 {
        let q = p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
        return dot3(q, q);
    }
    let sum = va + vb + vc;
    if sum > 0.0 {
        let q = p - (a + ab * (vb / sum) + ac * (vc / sum));
        return dot3(q, q);
    }
    return min(min(segment_distance_squared(p, a, b), segment_distance_squared(p, b, c)),
        segment_distance_squared(p, c, a));
}

fn triangle_distance_squared(slot: u32, corner: vec3<i32>) -> f32 {
    let t = triangles[slot];
    let p = vec3<f32>(corner - vec3<i32>(t.base[0], t.base[1], t.base[2]));
    return point_triangle_distance_squared(p, vec(t.a), vec(t.b), vec(t.c));
}

// A lower bound of the squared distance from `corner` (at `p` from the tree's base) to the
// triangle in `slot`: the larger of its box's and its plane's, the plane's reduced by PLANE_SLACK
// for rounding. src/grid/cpu/distance_tiled.rs caches these terms per tile and chunk, with a disk
// bound besides.
fn lower_bound(slot: u32, corner: vec3<i32>, p: vec3<f32>) -> f32 {
    let to_box = box_distance_squared(vec(boxes[slot].min), vec(boxes[slot].max), p);
    let t = triangles[slot];
    let local = vec3<f32>(corner - vec3<i32>(t.base[0], t.base[1], t.base[2]));
    let to_plane = max(abs(dot3(vec(t.normal), local) - t.offset) - PLANE_SLACK, 0.0);
    return max(to_box, to_plane * to_plane);
}

struct Best {
    distance_squared: f32,
    slot: u32,
}

// A full traversal, nearer child first, pruned by the best so far.
fn search(corner: vec3<i32>, p: vec3<f32>, start: Best) -> Best {
    var best = start;
    var stack: array<u32, TREE_STACK_SIZE>;
    var depth = 0u;
    var node = 0u;
    loop {
        let count = nodes[node].count;
        var descend = false;
        if count > 0u {
            let first = nodes[node].index;
            for (var slot = first; slot < first + count; slot += 1u) {
                let d = triangle_distance_squared(slot, corner);
                if d < best.distance_squared {
                    best = Best(d, slot);
                }
            }
        } else {
            let left = node + 1u;
            let right = nodes[node].index;
            let dl = node_distance_squared(left, p);
            let dr = node_distance_squared(right, p);
            var near = left;
            var far = right;
            var dn = dl;
            var df = dr;
            if dl > dr {
                near = right;
                far = left;
                dn = dr;
                df = dl;
            }
            if dn < best.distance_squared {
                if df < best.distance_squared {
                    stack[depth] = far;
                    depth += 1u;
                }
                node = near;
                descend = true;
            }
        }
        if descend {
            continue;
        }
        // Pop the next subtree still closer than the best so far.
        var done = true;
        while depth > 0u {
            depth -= 1u;
            node = stack[depth];
            if node_distance_squared(node, p) < best.distance_squared {
                done = false;
                break;
            }
        }
        if done {
            break;
        }
    }
    return best;
}

fn chunk_first(c: u32) -> vec3<i32> {
    return vec3<i32>(chunks[c].first[0], chunks[c].first[1], chunks[c].first[2]);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let q = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if q >= arrayLength(&tiles) {
        return;
    }
    let tile = tiles[q];
    let base = vec3<i32>(params[0].base[0], params[0].base[1], params[0].base[2]);
    let bound = params[0].bound;
    var first_corner = vec3<i32>(2147483647);
    var last_corner = vec3<i32>(-2147483647 - 1);
    for (var c = tile.first; c < tile.first + tile.count; c += 1u) {
        let f = chunk_first(c);
        first_corner = min(first_corner, f);
        last_corner = max(last_corner, f + vec3<i32>(i32(chunks[c].len) - 1, 0, 0));
    }
    let lo = vec3<f32>(first_corner - base);
    let hi = vec3<f32>(last_corner - base);

    // `gather`: a traversal collecting every triangle whose box is within the band of lo..hi.
    var slots: array<u32, GATHER_CAPACITY>;
    var gathered = 0u;
    var complete = true;
    var stack: array<u32, TREE_STACK_SIZE>;
    var depth = 0u;
    var node = 0u;
    loop {
        if boxes_distance_squared(lo, hi, vec(nodes[node].min), vec(nodes[node].max)) < bound {
            let count = nodes[node].count;
            if count > 0u {
                let start = nodes[node].index;
                for (var slot = start; slot < start + count; slot += 1u) {
                    if boxes_distance_squared(lo, hi, vec(boxes[slot].min), vec(boxes[slot].max))
                        < bound {
                        if gathered == GATHER_CAPACITY {
                            complete = false;
                            break;
                        }
                        slots[gathered] = slot;
                        gathered += 1u;
                    }
                }
                if !complete {
                    break;
                }
            } else {
                stack[depth] = nodes[node].index;
                depth += 1u;
                node += 1u;
                continue;
            }
        }
        if depth == 0u {
            break;
        }
        depth -= 1u;
        node = stack[depth];
    }

    if !complete {
        for (var c = tile.first; c < tile.first + tile.count; c += 1u) {
            for (var i = 0u; i < chunks[c].len; i += 1u) {
                let corner = chunk_first(c) + vec3<i32>(i32(i), 0, 0);
                let best = search(corner, vec3<f32>(corner - base), Best(bound, NO_SLOT));
                nearest[chunks[c].out + i] = Nearest(best.distance_squared, best.slot);
            }
        }
        return;
    }

    for (var c = tile.first; c < tile.first + tile.count; c += 1u) {
        let first = chunk_first(c);
        var hint = NO_SLOT;
        for (var i = 0u; i < chunks[c].len; i += 1u) {
            let corner = first + vec3<i32>(i32(i), 0, 0);
            let p = vec3<f32>(corner - base);
            // The previous corner's nearest triangle, or else the one with the least bound.
            var start_k = hint;
            if start_k == NO_SLOT {
                var least = bitcast<f32>(0x7f800000u);
                start_k = 0u;
                for (var k = 0u; k < gathered; k += 1u) {
                    let lower = lower_bound(slots[k], corner, p);
                    if lower < least {
                        least = lower;
                        start_k = k;
                    }
                }
            }
            var best = bound;
            var found = NO_SLOT;
            if start_k < gathered && lower_bound(slots[start_k], corner, p) < best {
                let d = triangle_distance_squared(slots[start_k], corner);
                if d < best {
                    best = d;
                    found = start_k;
                }
            }
            for (var k = 0u; k < gathered; k += 1u) {
                if k != start_k && lower_bound(slots[k], corner, p) < best {
                    let d = triangle_distance_squared(slots[k], corner);
                    if d < best {
                        best = d;
                        found = k;
                    }
                }
            }
            hint = found;
            var slot = NO_SLOT;
            if found != NO_SLOT {
                slot = slots[found];
            }
            nearest[chunks[c].out + i] = Nearest(best, slot);
        }
    }
}
