//! Two-sided distance between a tracked frame and its input frame, measured on samples of both
//! surfaces: every vertex, every edge midpoint and every triangle centroid.

use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::project::{Bvh, ProjectError, closest_points};
use glam::Vec3;
use serde::Serialize;

/// Distances between two surfaces, in world units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SurfaceDistances {
    /// Largest distance from a sample of the tracked surface to the input surface.
    pub tracked_to_input: f32,
    /// Largest distance from a sample of the input surface to the tracked surface.
    pub input_to_tracked: f32,
    /// Mean distance over the samples of both surfaces.
    pub mean: f32,
}

impl SurfaceDistances {
    /// The two-sided Hausdorff distance (as far as the samples see it).
    pub fn hausdorff(&self) -> f32 {
        self.tracked_to_input.max(self.input_to_tracked)
    }
}

/// Points spread over a mesh: vertices, one midpoint per edge (each edge once, from the triangle
/// that lists it with ascending ends) and centroids. Midway between vertices is where two
/// triangulations of one surface part most, so this sees more than the vertices alone would.
pub fn surface_samples(mesh: &IndexedMesh) -> Vec<Vec3> {
    labelled_surface_samples(mesh, &[]).0
}

/// [`surface_samples`], each with the label of the vertex it is, or of the first corner of the
/// triangle it lies in (`u32::MAX` where `labels` has none): with component labels, which
/// component each sample measures.
pub fn labelled_surface_samples(mesh: &IndexedMesh, labels: &[u32]) -> (Vec<Vec3>, Vec<u32>) {
    let p = |v: u32| mesh.positions[v as usize];
    let label = |v: u32| labels.get(v as usize).copied().unwrap_or(u32::MAX);
    let mut samples = mesh.positions.clone();
    let mut owners: Vec<u32> = (0..mesh.positions.len() as u32).map(label).collect();
    for tri in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a < b {
                samples.push((p(a) + p(b)) * 0.5);
                owners.push(label(tri[0]));
            }
        }
    }
    for t in &mesh.triangles {
        samples.push((p(t[0]) + p(t[1]) + p(t[2])) / 3.0);
        owners.push(label(t[0]));
    }
    (samples, owners)
}

/// Largest and summed distance of `points` to the surface in `bvh`.
fn one_side(
    backend: &Backend,
    bvh: &Bvh,
    points: &[Vec3],
) -> Result<(f32, f64, usize), ProjectError> {
    let found = closest_points(backend, bvh, points, f32::INFINITY)?;
    let (mut max, mut sum) = (0.0f32, 0.0f64);
    for hit in found.iter().filter(|h| h.hit_triangle().is_some()) {
        let d = hit.distance.abs();
        max = max.max(d);
        sum += f64::from(d);
    }
    Ok((max, sum, found.len()))
}

/// Distances between `tracked` and `input` (both need triangles and finite positions).
pub fn surface_distances(
    backend: &Backend,
    tracked: &IndexedMesh,
    input: &IndexedMesh,
) -> Result<SurfaceDistances, ProjectError> {
    let (to_input, sum_a, n_a) = one_side(
        backend,
        &Bvh::build_unsigned(input)?,
        &surface_samples(tracked),
    )?;
    let (to_tracked, sum_b, n_b) = one_side(
        backend,
        &Bvh::build_unsigned(tracked)?,
        &surface_samples(input),
    )?;
    let n = (n_a + n_b).max(1);
    Ok(SurfaceDistances {
        tracked_to_input: to_input,
        input_to_tracked: to_tracked,
        mean: ((sum_a + sum_b) / n as f64) as f32,
    })
}
