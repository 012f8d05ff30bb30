// The start of a fine-stage solve from the warm displacements d (register::fine): per vertex,
// r = b − A d (A d by fine_cover and fine_apply), z = P r, p = z, and the terms rᵀz and |r|²;
// where b = 0 the solution is d = 0 and nothing else is written.
// CPU twin: src/register/cpu/fine_start.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> state: CgState;
@group(0) @binding(2) var<storage, read> b: array<f64>;
@group(0) @binding(3) var<storage, read> preconditioner: array<f64>;
@group(0) @binding(4) var<storage, read> ad: array<f64>;
@group(0) @binding(5) var<storage, read_write> d: array<f64>;
@group(0) @binding(6) var<storage, read_write> r: array<f64>;
@group(0) @binding(7) var<storage, read_write> z: array<f64>;
@group(0) @binding(8) var<storage, read_write> p: array<f64>;
@group(0) @binding(9) var<storage, read_write> terms: array<f64>;

const WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let v = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if v >= params.vertices {
        return;
    }
    if state.b_norm == f64(0.0) {
        d[3u * v] = f64(0.0);
        d[3u * v + 1u] = f64(0.0);
        d[3u * v + 2u] = f64(0.0);
        return;
    }
    let i = 9u * v;
    let m = mat3x3<f64>(
        vec3<f64>(preconditioner[i], preconditioner[i + 1u], preconditioner[i + 2u]),
        vec3<f64>(preconditioner[i + 3u], preconditioner[i + 4u], preconditioner[i + 5u]),
        vec3<f64>(preconditioner[i + 6u], preconditioner[i + 7u], preconditioner[i + 8u]),
    );
    let bv = vec3<f64>(b[3u * v], b[3u * v + 1u], b[3u * v + 2u]);
    let rv = bv - vec3<f64>(ad[3u * v], ad[3u * v + 1u], ad[3u * v + 2u]);
    let zv = mat_vec(m, rv);
    for (var k = 0u; k < 3u; k += 1u) {
        r[3u * v + k] = rv[k];
        z[3u * v + k] = zv[k];
        p[3u * v + k] = zv[k];
    }
    terms[2u * v] = dot3(rv, zv);
    terms[2u * v + 1u] = dot3(rv, rv);
}
