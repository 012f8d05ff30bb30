// A triangle crossing a grid edge, and a run of constant winding number along a grid line.
// Mirrored by `surftrack::kernels::shared::GridCrossing` and
// `surftrack::kernels::shared::WindingRun` (src/kernels/shared/crossing.rs); a test compares the layouts.

// `flags`: bits 0-1 axis, bit 2 set when walking the edge towards +axis enters the surface.
struct GridCrossing {
    corner: array<i32, 3>,
    triangle: u32,
    t: f32,
    flags: u32,
}

const ENTER_BIT: u32 = 4u;

// Corners from `start` on have winding number `winding`; `start == RUN_CONTINUES` marks a sweep slot
// that starts no run.
struct WindingRun {
    start: i32,
    winding: i32,
}

const RUN_CONTINUES: i32 = -2147483647 - 1;
