// Axis-aligned bounding box. Mirrored by `surftrack::kernels::shared::Aabb` (src/kernels/shared/aabb.rs); a test
// compares the two layouts. `vec3<f32>` aligns to 16 bytes, so each corner is followed by an
// explicit u32 that kernels write as 0: the 32 bytes are then fully defined and comparable bit for
// bit with the CPU twin's output.
struct Aabb {
    min: vec3<f32>,
    pad_min: u32,
    max: vec3<f32>,
    pad_max: u32,
}
