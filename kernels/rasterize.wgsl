// Rasterization: every crossing of a triangle with a grid edge (thesis §3.4.2).
// CPU twin: src/grid/cpu/rasterize.rs (the candidate loop) with src/grid/predicates.rs (`line_crossing`,
// the body below, line for line). Prepended: shared/lattice.wgsl, shared/exact.wgsl,
// shared/crossing.wgsl.
//
// One invocation per candidate: a triangle and a grid line strictly inside its projected cell
// range. `offsets[t]` is the first candidate of triangle t and `offsets[triangle count]` the total;
// a triangle's candidates run axis by axis, then row by row (v), then along the row (u). Crossings
// are appended through `count`; the host sorts them, so their order here does not matter.

@group(0) @binding(0) var<storage, read> points: array<LatticePoint>;
@group(0) @binding(1) var<storage, read> triangles: array<array<u32, 3>>;
@group(0) @binding(2) var<storage, read> offsets: array<u32>;
@group(0) @binding(3) var<storage, read_write> crossings: array<GridCrossing>;
@group(0) @binding(4) var<storage, read_write> count: array<atomic<u32>>;

const WORKGROUP_SIZE: u32 = 64u;

fn cell_of(p: LatticePoint) -> vec3<i32> {
    return vec3<i32>(p.cell[0], p.cell[1], p.cell[2]);
}

// Lattice offsets from cell `base` (below 2^31: the host checks every triangle's span).
fn local_point(p: LatticePoint, base: vec3<i32>) -> vec3<i32> {
    let frac = vec3<i32>(bitcast<i32>(p.frac[0]), bitcast<i32>(p.frac[1]), bitcast<i32>(p.frac[2]));
    return ((cell_of(p) - base) << vec3<u32>(FRACTION_BITS)) + frac;
}

fn cross2(a: vec3<i32>, b: vec3<i32>, c: vec3<i32>, u: u32, v: u32) -> vec2<u32> {
    return sub64(mul_i32(b[u] - a[u], c[v] - a[v]), mul_i32(b[v] - a[v], c[u] - a[u]));
}

fn first_sign(a: i32, b: i32) -> i32 {
    return select(sign(b), sign(a), a != 0);
}

fn edge_sign(p: vec3<i32>, q: vec3<i32>, u: u32, v: u32, xu: i32, xv: i32) -> i32 {
    let du = q[u] - p[u];
    let dv = q[v] - p[v];
    let e = sign64(sub64(mul_i32(du, xv - p[v]), mul_i32(dv, xu - p[u])));
    if e != 0 {
        return e;
    }
    if u < v {
        return first_sign(dv, -du);
    }
    return first_sign(-du, dv);
}

struct Side {
    value: vec4<u32>,
    side: i32,
}

fn plane_side(n: array<vec2<u32>, 3>, a: vec3<i32>, q: vec3<i32>) -> Side {
    let s = add128(add128(mul64_i32(n[0], a.x - q.x), mul64_i32(n[1], a.y - q.y)),
        mul64_i32(n[2], a.z - q.z));
    var side = sign128(s);
    if side == 0 {
        side = select(select(sign64(n[2]), sign64(n[1]), sign64(n[1]) != 0), sign64(n[0]),
            sign64(n[0]) != 0);
    }
    return Side(s, side);
}

fn corner_at(axis: u32, u: u32, v: u32, along: i32, xu: i32, xv: i32) -> vec3<i32> {
    var q = vec3<i32>(0);
    q[axis] = along;
    q[u] = xu;
    q[v] = xv;
    return q;
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let k = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    let triangle_count = arrayLength(&triangles);
    if k >= offsets[triangle_count] {
        return;
    }
    var first = 0u;
    var last = triangle_count - 1u;
    while first < last {
        let mid = first + (last - first + 1u) / 2u;
        if offsets[mid] <= k {
            first = mid;
        } else {
            last = mid - 1u;
        }
    }
    let t = first;
    let tri = triangles[t];
    let pa = points[tri[0]];
    let pb = points[tri[1]];
    let pc = points[tri[2]];
    let lo = min(min(cell_of(pa), cell_of(pb)), cell_of(pc));
    let hi = max(max(cell_of(pa), cell_of(pb)), cell_of(pc));
    let a = local_point(pa, lo);
    let b = local_point(pb, lo);
    let c = local_point(pc, lo);

    // The candidate's axis and line.
    var r = k - offsets[t];
    var axis = 0u;
    for (; axis < 2u; axis += 1u) {
        let u = (axis + 1u) % 3u;
        let v = (axis + 2u) % 3u;
        let lines = u32(hi[u] - lo[u]) * u32(hi[v] - lo[v]);
        if r < lines {
            break;
        }
        r -= lines;
    }
    let u = (axis + 1u) % 3u;
    let v = (axis + 2u) % 3u;
    let width = u32(hi[u] - lo[u]);
    let line_u = lo[u] + 1 + i32(r % width);
    let line_v = lo[v] + 1 + i32(r / width);

    // src/grid/predicates.rs, `line_crossing`.
    let d = cross2(a, b, c, u, v);
    let want = sign64(d);
    if want == 0 {
        return;
    }
    let xu = (line_u - lo[u]) << FRACTION_BITS;
    let xv = (line_v - lo[v]) << FRACTION_BITS;
    if edge_sign(a, b, u, v, xu, xv) != want || edge_sign(b, c, u, v, xu, xv) != want
        || edge_sign(c, a, u, v, xu, xv) != want {
        return;
    }
    let n = array<vec2<u32>, 3>(cross2(a, b, c, 1u, 2u), cross2(a, b, c, 2u, 0u),
        cross2(a, b, c, 0u, 1u));
    var below = lo[axis];
    var above = hi[axis];
    while below < above {
        let mid = below + (above - below + 1) / 2;
        let q = corner_at(axis, u, v, (mid - lo[axis]) << FRACTION_BITS, xu, xv);
        if plane_side(n, a, q).side == want {
            below = mid;
        } else {
            above = mid - 1;
        }
    }
    let s = plane_side(n, a, corner_at(axis, u, v, (below - lo[axis]) << FRACTION_BITS, xu, xv));
    let fraction = f32_from_128(s.value) / f32_from_64(d) * (1.0 / f32(1u << FRACTION_BITS));
    var corner = vec3<i32>(0);
    corner[axis] = below;
    corner[u] = line_u;
    corner[v] = line_v;
    let slot = atomicAdd(&count[0], 1u);
    crossings[slot] = GridCrossing(
        array<i32, 3>(corner.x, corner.y, corner.z),
        t,
        clamp(fraction, 0.0, 0.99999994),
        axis | select(0u, ENTER_BIT, want < 0),
    );
}
