//! Droplets: components of a mesh within [`SMALL_CELLS`] cells of the topology grid, which the
//! grid cannot resolve and the sub-grid match settles (`subgrid`). Both the topology step, which
//! leaves them to that match, and the tracker, which moves them onto the input's droplets (they
//! fly faster than the deformation graph follows), find them here.

use glam::Vec3;
use rustc_hash::{FxHashMap, FxHashSet};

use super::classify::dilate;
use super::keys::Cell;
use super::mismatch::{spans, within};
use super::subgrid::SMALL_CELLS;
use crate::geometry::Components;
use crate::grid::GridFrame;
use crate::mesh::IndexedMesh;

/// The droplets of `mesh` (components whose bounding-box diagonal is at most [`SMALL_CELLS`] cells
/// of `frame`), each as its vertices, in order of their least vertex. With `apart`, only those
/// with no vertex of a larger component in their cells or the 26 cells around them: such a
/// droplet is in no self-intersection with the body that ConstrainTopology on Φ(M) would merge
/// (paper §4.3).
pub(crate) fn droplets(frame: &GridFrame, mesh: &IndexedMesh, apart: bool) -> Vec<Vec<u32>> {
    let mut components = Components::new(mesh.positions.len(), &mesh.triangles);
    let mut number: FxHashMap<u32, usize> = FxHashMap::default();
    let mut members: Vec<Vec<u32>> = Vec::new();
    let mut labels: Vec<u32> = Vec::with_capacity(mesh.positions.len());
    for v in 0..mesh.positions.len() as u32 {
        let root = components.find(v);
        let k = *number.entry(root).or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[k].push(v);
        labels.push(k as u32);
    }
    let spans = spans(&mesh.positions, &labels, members.len());
    let is_droplet = within(frame, &spans, SMALL_CELLS);
    let body: FxHashSet<Cell> = if apart {
        mesh.positions
            .iter()
            .zip(&labels)
            .filter(|(_, l)| !is_droplet[**l as usize])
            .map(|(&p, _)| cell(frame, p))
            .collect()
    } else {
        FxHashSet::default()
    };
    members
        .into_iter()
        .zip(is_droplet)
        .filter(|(vertices, droplet)| {
            let cells = || -> Vec<Cell> {
                vertices
                    .iter()
                    .map(|&v| cell(frame, mesh.positions[v as usize]))
                    .collect()
            };
            *droplet && (!apart || dilate(&cells(), 1).iter().all(|c| !body.contains(c)))
        })
        .map(|(vertices, _)| vertices)
        .collect()
}

/// The grid cell holding `p`.
pub(crate) fn cell(frame: &GridFrame, p: Vec3) -> Cell {
    frame.to_grid(p).map(|x| x.floor() as i32)
}
