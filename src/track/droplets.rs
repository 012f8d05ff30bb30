//! Droplets that the deformation graph does not move. A fluid cache sheds droplets of one
//! particle's blob (4–20 vertices, well below a grid cell) that fly a few edge lengths per frame:
//! on the SPH dam break a median 2.0–3.2 L between frames. The deformation graph (paper §4.2)
//! has no node that follows such a blob alone, and registration left the tracked droplets a
//! median 2.4–4.1 L from the nearest input droplet, farther than before it. The sub-grid match
//! then deleted every one of them and copied the input's in with fresh ids, so every id and
//! everything a user keeps per id (a seed, a velocity for motion blur) restarted on every droplet
//! every frame.
//!
//! So after registration each tracked droplet apart from the body (no vertex of a larger component
//! in its cells or next to them), and not already on the input (its centroid more than a cell
//! from it), moves by a translation onto the input droplet whose centroid lies nearest to its own,
//! within [`SMALL_CELLS`] cells: pairs are taken nearest first, each droplet of either side at most
//! once. The topology steps leave such droplets to the sub-grid match (`constrain_topology` with
//! `keep_shared_sheets`), which keeps a moved droplet where it reproduces its input droplet
//! within the distance bound, and replaces it as before where it does not.

use glam::Vec3;

use crate::compute::Backend;
use crate::grid::GridFrame;
use crate::mesh::{IndexedMesh, Mesh};
use crate::project::{Bvh, ProjectError, closest_points};
use crate::topology::droplets;
use crate::topology::subgrid::SMALL_CELLS;

/// The centroid of `vertices` of `mesh`.
fn centroid(mesh: &IndexedMesh, vertices: &[u32]) -> Vec3 {
    let sum: Vec3 = vertices.iter().map(|&v| mesh.positions[v as usize]).sum();
    sum / vertices.len() as f32
}

/// Moves the tracked droplets of `mesh` onto the droplets of `target` (whose tree is `bvh`) that
/// they follow (see the module comment), on the topology grid `frame`; returns how many moved.
pub(super) fn follow_droplets(
    backend: &Backend,
    mesh: &mut Mesh,
    (target, bvh): (&IndexedMesh, &Bvh),
    frame: &GridFrame,
) -> Result<usize, ProjectError> {
    let current = mesh.to_indexed();
    let ours = droplets(frame, &current, true);
    if ours.is_empty() {
        return Ok(0);
    }
    // A droplet already on the input is matched as it lies.
    let centroids: Vec<Vec3> = ours.iter().map(|d| centroid(&current, d)).collect();
    let on = closest_points(backend, bvh, &centroids, f32::INFINITY)?;
    let spacing = frame.spacing();
    let loose: Vec<bool> = centroids
        .iter()
        .zip(&on)
        .map(|(c, hit)| (hit.point - *c).length() > spacing)
        .collect();
    let theirs: Vec<Vec3> = droplets(frame, target, false)
        .iter()
        .map(|d| centroid(target, d))
        .collect();
    let reach = SMALL_CELLS * spacing;
    let mut pairs: Vec<(f32, usize, usize)> = Vec::new();
    for (i, c) in centroids.iter().enumerate().filter(|(i, _)| loose[*i]) {
        for (k, t) in theirs.iter().enumerate() {
            let gap = (*t - *c).length();
            if gap <= reach {
                pairs.push((gap, i, k));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let slots: Vec<_> = mesh.vertices().collect();
    let (mut moved, mut taken) = (vec![false; ours.len()], vec![false; theirs.len()]);
    for (_, i, k) in pairs {
        if moved[i] || taken[k] {
            continue;
        }
        (moved[i], taken[k]) = (true, true);
        let shift = theirs[k] - centroids[i];
        for &v in &ours[i] {
            let slot = slots[v as usize];
            mesh.set_position(slot, mesh.position(slot) + shift);
        }
    }
    Ok(moved.iter().filter(|&&m| m).count())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ball of radius 3 and droplets of radius 0.2 at `drops`, as one mesh.
    fn scene(drops: &[Vec3]) -> IndexedMesh {
        let mut mesh = IndexedMesh::icosphere(Vec3::ZERO, 3.0, 3);
        for &c in drops {
            let drop = IndexedMesh::icosphere(c, 0.2, 1);
            let base = mesh.positions.len() as u32;
            mesh.positions.extend(&drop.positions);
            mesh.triangles
                .extend(drop.triangles.iter().map(|t| t.map(|v| v + base)));
        }
        mesh
    }

    fn moved(tracked: &[Vec3], input: &[Vec3]) -> (usize, Mesh) {
        let frame = GridFrame::new(Vec3::splat(0.013), 1.0).unwrap();
        let mut mesh = Mesh::from_indexed(&scene(tracked)).unwrap();
        let target = scene(input);
        let bvh = Bvh::build(&target).unwrap();
        let n = follow_droplets(&Backend::Cpu, &mut mesh, (&target, &bvh), &frame).unwrap();
        (n, mesh)
    }

    fn centroid_near(mesh: &Mesh, c: Vec3) -> Vec3 {
        let near: Vec<Vec3> = mesh
            .vertices()
            .map(|v| mesh.position(v))
            .filter(|p| p.distance(c) < 0.5)
            .collect();
        assert!(!near.is_empty(), "nothing near {c}");
        near.iter().sum::<Vec3>() / near.len() as f32
    }

    /// A droplet 2.5 cells from its input droplet lands on it; the ball does not move; of two
    /// input droplets the nearer is taken.
    #[test]
    fn a_droplet_moves_onto_the_nearest_input_droplet() {
        let from = Vec3::new(8.0, 0.0, 0.0);
        let to = Vec3::new(8.0, 2.5, 0.0);
        let farther = Vec3::new(8.0, -3.2, 0.0);
        let (n, mesh) = moved(&[from], &[to, farther]);
        assert_eq!(n, 1);
        assert!(centroid_near(&mesh, to).distance(to) < 1e-4);
        let ball = IndexedMesh::icosphere(Vec3::ZERO, 3.0, 3);
        for (v, p) in mesh.vertices().zip(&ball.positions) {
            assert_eq!(mesh.position(v), *p);
        }
    }

    /// A droplet already on an input droplet stays; one with no input droplet within four cells
    /// stays; one next to the ball stays (it is not apart from the body); and two droplets never
    /// take the same input droplet.
    #[test]
    fn droplets_on_the_input_far_from_it_or_next_to_the_body_stay() {
        let on = Vec3::new(0.0, 8.0, 0.0);
        assert_eq!(moved(&[on], &[on + Vec3::new(0.1, 0.0, 0.0)]).0, 0);
        let lone = Vec3::new(0.0, -9.0, 0.0);
        assert_eq!(moved(&[lone], &[lone + Vec3::new(4.5, 0.0, 0.0)]).0, 0);
        let beside = Vec3::new(0.0, 0.0, 4.0);
        assert_eq!(moved(&[beside], &[beside + Vec3::new(0.0, 0.0, 2.5)]).0, 0);
        let (a, b) = (Vec3::new(9.0, 0.0, 0.0), Vec3::new(9.0, 1.5, 0.0));
        let (n, mesh) = moved(&[a, b], &[Vec3::new(9.0, 3.5, 0.0)]);
        assert_eq!(n, 1);
        assert!(centroid_near(&mesh, a).distance(a) < 1e-4);
    }
}
