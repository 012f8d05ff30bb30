//! The first answer of `ConstrainTopology` to a topology left wrong (paper §4.3, the ladder in
//! `constrain`). A deep difference that is resolved can leave a component of another Euler
//! characteristic than Θ's: some shallow difference (a handle or tunnel the classification let
//! pass) changes the topology too. Taking every shallow difference of that component re-samples
//! all of it, and on a fluid's main body, rippled all over, that is most of the surface. Most
//! shallow differences are ripples, which replacing leaves χ as it is: so the next attempt first
//! takes only the clusters of shallow differences whose replacement by Θ's isosurface changes χ,
//! and all of them only if that fails.

use super::classify::dilate;
use super::clusters::{clusters, euler, holders, touching};
use super::keys::Cell;
use super::mesh_grid::MeshGrid;
use crate::grid::cases::cell_case;
use crate::mesh::IndexedMesh;

/// The cells of `seeds` whose cluster (26-connected, grown by one cell) changes the Euler
/// characteristic when the mesh's triangles with a corner in it are replaced by the triangles of
/// Θ's isosurface `iso` in it; `surface` lists the cells `iso` was made from, in its order.
/// Sorted.
pub(crate) fn changing(
    grid: &MeshGrid,
    (surface, iso): (&[(Cell, u8)], &IndexedMesh),
    seeds: &[Cell],
) -> Vec<Cell> {
    let mut seeds = seeds.to_vec();
    seeds.sort_unstable();
    seeds.dedup();
    let members = clusters(&seeds);
    let grown: Vec<Vec<Cell>> = members.iter().map(|m| dilate(m, 1)).collect();
    let holders = holders(&grown);
    let mesh = grid.mesh;
    let removed = touching(&mesh.triangles, members.len(), |v| {
        holders
            .get(&grid.vertex_cell(v))
            .map_or(&[][..], Vec::as_slice)
    });
    // The isosurface's triangles come cell by cell, in the order of `surface`.
    let mut filled: Vec<Vec<u32>> = vec![Vec::new(); members.len()];
    let mut first = 0u32;
    for &(cell, config) in surface {
        let count = cell_case(config).triangles.len() as u32;
        for &k in holders.get(&cell).into_iter().flatten() {
            filled[k as usize].extend(first..first + count);
        }
        first += count;
    }
    let mut out: Vec<Cell> = members
        .into_iter()
        .enumerate()
        .filter(|(k, _)| euler(iso, &filled[*k]) != euler(mesh, &removed[*k]))
        .flat_map(|(_, cells)| cells)
        .collect();
    out.sort_unstable();
    out
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::compute::Backend;
    use crate::grid::GridFrame;
    use crate::mesh::Mesh;
    use crate::topology::cell;
    use crate::topology::field::Field;
    use crate::topology::isosurface::isosurface;

    #[test]
    fn a_ripple_is_dropped_and_a_missing_ball_is_kept() {
        let frame = GridFrame::new(Vec3::new(0.013, -0.021, 0.007), 0.5).unwrap();
        let ours = IndexedMesh::icosphere(Vec3::ZERO, 2.0, 4);
        let ball = IndexedMesh::icosphere(Vec3::new(6.0, 0.0, 0.0), 1.0, 3);
        let both = ours.joined(&ball);
        // Θ has the ball the tracked mesh lacks, and the same sphere.
        let theta = Field::signed_distance(&Backend::Cpu, frame, &both).unwrap();
        let half = Mesh::from_indexed(&ours).unwrap();
        let grid = MeshGrid::new(&ours, &half, frame).unwrap();
        let surface = theta.surface();
        let (iso, _) = isosurface(&theta, &surface);
        // A patch of the sphere both share (a ripple's cells) and the cells of the ball.
        let ripple: Vec<Cell> = ours
            .positions
            .iter()
            .filter(|p| p.z > 1.8)
            .map(|&p| cell(&frame, p))
            .collect();
        let missing: Vec<Cell> = ball.positions.iter().map(|&p| cell(&frame, p)).collect();
        let seeds: Vec<Cell> = ripple.iter().chain(&missing).copied().collect();
        let kept = changing(&grid, (&surface, &iso), &seeds);
        assert!(missing.iter().all(|c| kept.binary_search(c).is_ok()));
        assert!(ripple.iter().all(|c| kept.binary_search(c).is_err()));
    }
}
