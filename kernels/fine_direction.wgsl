// The next conjugate-gradient direction of the fine stage (register::fine): per vertex,
// p = z + β p.
// CPU twin: src/register/cpu/fine_direction.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> state: CgState;
@group(0) @binding(2) var<storage, read> z: array<f64>;
@group(0) @binding(3) var<storage, read_write> p: array<f64>;

const WORKGROUP_SIZE: u32 = 64u;

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
    for (var k = 0u; k < 3u; k += 1u) {
        p[3u * v + k] = z[3u * v + k] + state.beta * p[3u * v + k];
    }
}
