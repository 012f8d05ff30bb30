// Inside/outside sweep: the winding number along every grid line (thesis §3.4.3).
// CPU twin: src/grid/cpu/sweep.rs. Prepended: shared/crossing.wgsl.
//
// One invocation per line: `starts[l] .. starts[l + 1]` are its crossings, sorted along it. The
// slot of the last crossing on each grid edge receives the run of constant winding that starts at
// the edge's upper corner; every other slot is marked RUN_CONTINUES.

@group(0) @binding(0) var<storage, read> crossings: array<GridCrossing>;
@group(0) @binding(1) var<storage, read> starts: array<u32>;
@group(0) @binding(2) var<storage, read_write> runs: array<WindingRun>;

const WORKGROUP_SIZE: u32 = 64u;

// Index of crossing k's grid edge along its own axis.
fn along(k: u32) -> i32 {
    return crossings[k].corner[crossings[k].flags & 3u];
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let l = (wg.y * groups.x + wg.x) * WORKGROUP_SIZE + lane;
    if l + 1u >= arrayLength(&starts) {
        return;
    }
    let end = starts[l + 1u];
    var winding = 0;
    for (var k = starts[l]; k < end; k += 1u) {
        winding += select(-1, 1, (crossings[k].flags & ENTER_BIT) != 0u);
        let here = along(k);
        let last_on_edge = k + 1u == end || along(k + 1u) != here;
        runs[k] = WindingRun(select(RUN_CONTINUES, here + 1, last_on_edge), winding);
    }
}
