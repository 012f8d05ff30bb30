//! The workload of the parity tests and the projection benchmarks. Needs `metaballs.rs` as the
//! crate's `metaballs` module.

use glam::Vec3;
use surftrack::mesh::{IndexedMesh, NormalWeighting};

use crate::metaballs::metaballs;

/// The benchmark workload: a 100k-triangle synthetic target frame, and a tracked mesh of the same
/// scene a moment later, meshed independently (about 100k vertices), whose vertices with their
/// normals are the queries: 200k normal rays counting both directions.
pub fn workload() -> (IndexedMesh, Vec<Vec3>, Vec<Vec3>) {
    let target = metaballs(176, 0.0, 0.0);
    let source = metaballs(250, 0.3, 0.37);
    let normals = source.vertex_normals(NormalWeighting::Max);
    (target, source.positions, normals)
}
