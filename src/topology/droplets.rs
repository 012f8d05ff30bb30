//! Droplets: components of a mesh within [`SMALL_CELLS`] cells of the topology grid, which the
//! grid cannot resolve and the sub-grid match settles (`subgrid`). Both the topology step, which
//! leaves them to that match, and the tracker, which moves them onto the input's droplets (they
//! fly faster than the deformation graph follows), find them here.

use glam::Vec3;
use rustc_hash::{FxHashMap, FxHashSet};

use super::keys::{Cell, NEIGHBOURS};
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
    for v in 0..mesh.positions.len() as u32 {
        let root = components.find(v);
        let k = *number.entry(root).or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[k].push(v);
    }
    let small = SMALL_CELLS * frame.spacing();
    let is_droplet: Vec<bool> = members
        .iter()
        .map(|vertices| {
            let (lo, hi) = vertices.iter().map(|&v| mesh.positions[v as usize]).fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(lo, hi), p| (lo.min(p), hi.max(p)),
            );
            (hi - lo).length() <= small
        })
        .collect();
    let mut body: FxHashSet<Cell> = FxHashSet::default();
    if apart {
        for (vertices, _) in members.iter().zip(&is_droplet).filter(|(_, d)| !**d) {
            for &v in vertices {
                body.insert(cell(frame, mesh.positions[v as usize]));
            }
        }
    }
    members
        .into_iter()
        .zip(is_droplet)
        .filter(|(vertices, droplet)| {
            *droplet
                && (!apart
                    || vertices
                        .iter()
                        .flat_map(|&v| around(cell(frame, mesh.positions[v as usize])))
                        .all(|c| !body.contains(&c)))
        })
        .map(|(vertices, _)| vertices)
        .collect()
}

/// The grid cell holding `p`.
pub(crate) fn cell(frame: &GridFrame, p: Vec3) -> Cell {
    frame.to_grid(p).map(|x| x.floor() as i32)
}

/// `c` and the 26 cells around it.
pub(crate) fn around(c: Cell) -> impl Iterator<Item = Cell> {
    NEIGHBOURS
        .iter()
        .map(move |d| [c[0] + d[0], c[1] + d[1], c[2] + d[2]])
}
