// The fine stage's matrix applied to a vector x (register::fine): per vertex v,
// (A x)_v = M_v x_v + Σ_u (α_disp I + α_edge ê êᵀ)(x_v − x_u) + Σ w moved_p over the cover pairs
// touching v (moved by fine_cover), and the term x_v·(A x)_v of xᵀAx.
// CPU twin: src/register/cpu/fine_apply.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> state: CgState;
@group(0) @binding(2) var<storage, read> fit: array<f64>;
@group(0) @binding(3) var<storage, read> offsets: array<u32>;
@group(0) @binding(4) var<storage, read> neighbours: array<u32>;
@group(0) @binding(5) var<storage, read> directions: array<f64>;
@group(0) @binding(6) var<storage, read> cover_offsets: array<u32>;
@group(0) @binding(7) var<storage, read> cover_entries: array<u32>;
@group(0) @binding(8) var<storage, read> cover_weights: array<f64>;
@group(0) @binding(9) var<storage, read> moved: array<f64>;
@group(0) @binding(10) var<storage, read> x: array<f64>;
@group(0) @binding(11) var<storage, read_write> out: array<f64>;
@group(0) @binding(12) var<storage, read_write> terms: array<f64>;

const WORKGROUP_SIZE: u32 = 64u;

fn x_at(v: u32) -> vec3<f64> {
    return vec3<f64>(x[3u * v], x[3u * v + 1u], x[3u * v + 2u]);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let v = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if v >= params.vertices || state.done != 0u {
        return;
    }
    let i = 9u * v;
    let m = mat3x3<f64>(
        vec3<f64>(fit[i], fit[i + 1u], fit[i + 2u]),
        vec3<f64>(fit[i + 3u], fit[i + 4u], fit[i + 5u]),
        vec3<f64>(fit[i + 6u], fit[i + 7u], fit[i + 8u]),
    );
    let xv = x_at(v);
    var y = mat_vec(m, xv);
    for (var k = offsets[v]; k < offsets[v + 1u]; k += 1u) {
        let e = vec3<f64>(directions[3u * k], directions[3u * k + 1u], directions[3u * k + 2u]);
        let diff = xv - x_at(neighbours[k]);
        y = y + (diff * params.disp_weight + (e * params.edge_weight) * dot3(e, diff));
    }
    for (var j = cover_offsets[v]; j < cover_offsets[v + 1u]; j += 1u) {
        let pair = cover_entries[j] >> 2u;
        let w = cover_weights[3u * pair + (cover_entries[j] & 3u)];
        let pulled = vec3<f64>(moved[3u * pair], moved[3u * pair + 1u], moved[3u * pair + 2u]);
        y = y + pulled * w;
    }
    out[3u * v] = y.x;
    out[3u * v + 1u] = y.y;
    out[3u * v + 2u] = y.z;
    terms[2u * v] = dot3(xv, y);
    terms[2u * v + 1u] = f64(0.0);
}
