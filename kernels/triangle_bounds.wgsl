// Per-triangle axis-aligned bounding boxes, the leaves of a BVH over a target mesh.
// CPU twin: src/project/cpu/triangle_bounds.rs. Prepended: shared/aabb.wgsl.
//
// Positions and triangles are read as `array<f32, 3>` / `array<u32, 3>` (4-byte aligned, 12-byte
// stride), so the host uploads `[Vec3]` and `[[u32; 3]]` as they are, without padding to vec4.

@group(0) @binding(0) var<storage, read> positions: array<array<f32, 3>>;
@group(0) @binding(1) var<storage, read> triangles: array<array<u32, 3>>;
@group(0) @binding(2) var<storage, read_write> bounds: array<Aabb>;

const WORKGROUP_SIZE: u32 = 64u;

fn load_position(v: u32) -> vec3<f32> {
    let p = positions[v];
    return vec3<f32>(p[0], p[1], p[2]);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    // The grid may wrap into rows (src/compute/dispatch.rs) and overshoot the end; the host sizes
    // `triangles` exactly, so its length is the triangle count.
    let t = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if t >= arrayLength(&triangles) {
        return;
    }
    let tri = triangles[t];
    let a = load_position(tri[0]);
    let b = load_position(tri[1]);
    let c = load_position(tri[2]);
    bounds[t] = Aabb(min(min(a, b), c), 0u, max(max(a, b), c), 0u);
}
