// A triangle crossing a grid edge, and a run of constant winding number along a grid line.
// Mirrored by `surftrack::grid::GridCrossing` (src/grid/crossing.rs) and
// `surftrack::grid::WindingRun` (src/grid/sweep.rs); a test compares the layouts.

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
