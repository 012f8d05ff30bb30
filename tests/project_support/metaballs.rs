//! The synthetic frames of the `project_*` tests and benchmarks: closed marching-cubes meshes
//! like a fluid cache's.

use glam::Vec3;
use surftrack::grid::{ScalarGrid, marching_cubes};
use surftrack::mesh::IndexedMesh;

/// Blended metaballs (three moving, one fixed) extracted by marching cubes on a `cells`³ grid:
/// a closed frame like a fluid cache's. `phase` moves the balls, `shift` the grid origin (in
/// cells), so two calls give two incoherent frames of the same scene.
pub fn metaballs(cells: usize, phase: f32, shift: f32) -> IndexedMesh {
    let balls = [
        (Vec3::new(-0.35 + 0.1 * phase.cos(), 0.05, 0.0), 0.42),
        (Vec3::new(0.35, -0.1 + 0.1 * phase.sin(), 0.1), 0.36),
        (Vec3::new(0.0, 0.4, -0.2 + 0.05 * phase), 0.3),
        (Vec3::new(0.1, -0.45, -0.3), 0.22),
    ];
    let size = 2.4f32;
    let spacing = size / cells as f32;
    let origin = Vec3::splat(-size / 2.0) + Vec3::splat(shift * spacing);
    let dims = [cells + 1; 3];
    let grid = ScalarGrid::from_fn(origin, spacing, dims, |p| {
        let sum: f32 = balls
            .iter()
            .map(|&(c, r)| r * r / (p - c).length_squared().max(1e-12))
            .sum();
        1.0 - sum
    })
    .expect("valid grid");
    marching_cubes(&grid, 0.0)
}
