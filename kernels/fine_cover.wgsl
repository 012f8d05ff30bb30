// The cover term's half of the fine stage's matrix product (register::fine): per cover pair p,
// moved_p = M_p Σ_k w_k x_k over its three source vertices; fine_apply gathers them per vertex.
// CPU twin: src/register/cpu/fine_cover.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> state: CgState;
@group(0) @binding(2) var<storage, read> corners: array<u32>;
@group(0) @binding(3) var<storage, read> weights: array<f64>;
@group(0) @binding(4) var<storage, read> matrices: array<f64>;
@group(0) @binding(5) var<storage, read> x: array<f64>;
@group(0) @binding(6) var<storage, read_write> moved: array<f64>;

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
    let p = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if p >= params.pairs || state.done != 0u {
        return;
    }
    let blend = x_at(corners[3u * p]) * weights[3u * p]
        + x_at(corners[3u * p + 1u]) * weights[3u * p + 1u]
        + x_at(corners[3u * p + 2u]) * weights[3u * p + 2u];
    let i = 9u * p;
    let m = mat3x3<f64>(
        vec3<f64>(matrices[i], matrices[i + 1u], matrices[i + 2u]),
        vec3<f64>(matrices[i + 3u], matrices[i + 4u], matrices[i + 5u]),
        vec3<f64>(matrices[i + 6u], matrices[i + 7u], matrices[i + 8u]),
    );
    let y = mat_vec(m, blend);
    moved[3u * p] = y.x;
    moved[3u * p + 1u] = y.y;
    moved[3u * p + 2u] = y.z;
}
