// The sums of the fine stage's per-vertex terms (register::fine), two per vertex: per chunk of
// REDUCE_CHUNK vertices, each term summed in vertex order, as the CPU's `ordered_sum` sums its
// chunks; fine_scalars then sums the chunks in order. The two backends therefore add the same
// numbers in the same order.
// CPU twin: src/register/cpu/fine_reduce.rs. Prepended: shared/fine.wgsl.

@group(0) @binding(0) var<storage, read> params: FineParams;
@group(0) @binding(1) var<storage, read> terms: array<f64>;
@group(0) @binding(2) var<storage, read_write> partials: array<f64>;

const WORKGROUP_SIZE: u32 = 64u;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let c = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if c >= params.chunks {
        return;
    }
    let end = min((c + 1u) * REDUCE_CHUNK, params.vertices);
    var first = f64(0.0);
    var second = f64(0.0);
    for (var v = c * REDUCE_CHUNK; v < end; v += 1u) {
        first += terms[2u * v];
        second += terms[2u * v + 1u];
    }
    partials[2u * c] = first;
    partials[2u * c + 1u] = second;
}
