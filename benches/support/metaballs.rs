//! The grid benchmark's surface, shared by `benches/grid.rs` and `examples/band_reference.rs` so
//! that the reference comparison times exactly the benchmarked case.

use glam::Vec3;
use surftrack::grid::{GridFrame, ScalarGrid, marching_cubes};
use surftrack::mesh::IndexedMesh;

/// Cells across the box.
pub const N: usize = 128;

/// Three blended Gaussian blobs extracted by marching cubes on the benchmark grid itself, and
/// that grid: about 100 k triangles whose vertices lie on grid edges.
pub fn metaballs() -> (IndexedMesh, GridFrame) {
    let centers = [
        Vec3::new(-0.4, -0.2, 0.0),
        Vec3::new(0.45, 0.05, 0.1),
        Vec3::new(0.0, 0.45, -0.3),
    ];
    let width = 0.57f32;
    let spacing = 2.0 / N as f32;
    let origin = Vec3::splat(-1.0);
    let grid = ScalarGrid::from_fn(origin, spacing, [N + 1; 3], |p| {
        let sum: f32 = centers
            .iter()
            .map(|c| (-(p - *c).length_squared() / (width * width)).exp())
            .sum();
        0.5 - sum
    })
    .expect("benchmark grid shape is valid");
    let frame = GridFrame::new(origin, spacing).expect("benchmark frame is valid");
    (marching_cubes(&grid, 0.0), frame)
}
