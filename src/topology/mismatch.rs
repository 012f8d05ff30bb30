//! Where a re-sampled surface's topology came out unlike Θ's (paper §4.3): the components of the
//! result and of Θ's isosurface that do not pair one to one with equal Euler characteristics. A
//! shallow difference left out of the region can still change the topology; the next attempt
//! then counts every difference as deep, but first only in these components' cells rather than
//! everywhere — on a fluid's rippled surface, everywhere is most of the surface.

use rustc_hash::{FxHashMap, FxHashSet};

use super::keys::{Cell, GridEdge, NEIGHBOURS};
use super::subgrid::SMALL_CELLS;
use crate::grid::GridFrame;
use crate::mesh::IndexedMesh;

/// The cells (sorted, without repeats) of the vertices of every component of `result` and of Θ's
/// isosurface `iso` (its connectivity, one vertex on each grid edge of `edges`) that does not pair
/// with exactly one component of the other, lying in the same or neighbouring cells, of the same
/// Euler characteristic.
pub(crate) fn mismatched(
    frame: &GridFrame,
    result: &IndexedMesh,
    (iso, edges): (&IndexedMesh, &[GridEdge]),
    explained: &FxHashSet<Cell>,
) -> Vec<Cell> {
    let (ours, our_labels) = result.topology_with_labels();
    let (theirs, their_labels) = iso.topology_with_labels();
    let cells_of = |cells: &mut dyn Iterator<Item = Cell>, labels: &[u32]| {
        let mut at: FxHashMap<Cell, Vec<u32>> = FxHashMap::default();
        for (c, &l) in cells.zip(labels) {
            if l != u32::MAX {
                let list = at.entry(c).or_default();
                if !list.contains(&l) {
                    list.push(l);
                }
            }
        }
        at
    };
    let our_cells = cells_of(
        &mut result
            .positions
            .iter()
            .map(|p| frame.to_grid(*p).map(|x| x.floor() as i32)),
        &our_labels,
    );
    // A vertex of the isosurface lies on its grid edge, in the cells around the edge's corner.
    let their_cells = cells_of(&mut edges.iter().map(|e| e.corner), &their_labels);
    // The components of the other surface in or next to each component's cells.
    let partners = |own: &FxHashMap<Cell, Vec<u32>>,
                    other: &FxHashMap<Cell, Vec<u32>>,
                    count: usize|
     -> Vec<FxHashSet<u32>> {
        let mut near: Vec<FxHashSet<u32>> = vec![FxHashSet::default(); count];
        for (c, labels) in own {
            for d in NEIGHBOURS {
                let n = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                if let Some(found) = other.get(&n) {
                    for &l in labels {
                        near[l as usize].extend(found.iter().copied());
                    }
                }
            }
        }
        near
    };
    let mut our_partners = partners(&our_cells, &their_cells, ours.components.len());
    let mut their_partners = partners(&their_cells, &our_cells, theirs.components.len());
    // A difference the caller knows the cause of (a sheet thinner than a cell that both surfaces
    // have, which Θ cannot hold) leaves its components, and Θ's next to them, alone; so do
    // droplets, which the caller matches below the grid too, and which take no part in pairing.
    let (mut known, mut theirs_known) = (
        vec![false; ours.components.len()],
        vec![false; theirs.components.len()],
    );
    if !explained.is_empty() {
        let our_droplets = small(frame, result, &our_labels, ours.components.len());
        let droplets = small(frame, iso, &their_labels, theirs.components.len());
        known.clone_from(&our_droplets);
        for (c, labels) in &our_cells {
            if explained.contains(c) {
                for &l in labels {
                    known[l as usize] = true;
                }
            }
        }
        for near in &mut our_partners {
            near.retain(|&i| !droplets[i as usize]);
        }
        for (i, near) in their_partners.iter_mut().enumerate() {
            theirs_known[i] = droplets[i]
                || near
                    .iter()
                    .any(|&r| known[r as usize] && !our_droplets[r as usize]);
            near.retain(|&r| !our_droplets[r as usize]);
        }
    }
    let paired = |r: usize| -> Option<usize> {
        let &i = our_partners[r].iter().next()?;
        let i = i as usize;
        (our_partners[r].len() == 1
            && their_partners[i].len() == 1
            && ours.components[r].euler == theirs.components[i].euler)
            .then_some(i)
    };
    let mut ours_off = vec![true; ours.components.len()];
    let mut theirs_off = vec![true; theirs.components.len()];
    for (r, off) in ours_off.iter_mut().enumerate() {
        if let Some(i) = paired(r) {
            *off = false;
            theirs_off[i] = false;
        }
    }
    for (r, off) in ours_off.iter_mut().enumerate() {
        *off &= !known[r];
    }
    for (i, off) in theirs_off.iter_mut().enumerate() {
        *off &= !theirs_known[i];
    }
    let mut out: Vec<Cell> = our_cells
        .iter()
        .filter(|(_, labels)| labels.iter().any(|&l| ours_off[l as usize]))
        .chain(
            their_cells
                .iter()
                .filter(|(_, labels)| labels.iter().any(|&l| theirs_off[l as usize])),
        )
        .map(|(&c, _)| c)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Per component (`labels` numbering the vertices of `mesh`), whether its bounding box spans at
/// most [`SMALL_CELLS`] cells: a droplet, which the sub-grid match settles.
fn small(frame: &GridFrame, mesh: &IndexedMesh, labels: &[u32], count: usize) -> Vec<bool> {
    let mut boxes = vec![(glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN)); count];
    for (p, &l) in mesh.positions.iter().zip(labels) {
        if let Some(b) = boxes.get_mut(l as usize) {
            *b = (b.0.min(*p), b.1.max(*p));
        }
    }
    boxes
        .iter()
        .map(|(lo, hi)| (*hi - *lo).length() <= SMALL_CELLS * frame.spacing())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn frame() -> GridFrame {
        GridFrame::new(Vec3::ZERO, 0.25).unwrap()
    }

    /// Whether `result` and `iso` mismatch anywhere, and where: `iso`'s vertices are named by the
    /// grid edge along the x axis from the corner below them.
    fn compare(result: &IndexedMesh, iso: &IndexedMesh) -> Vec<Cell> {
        compare_explained(result, iso, &FxHashSet::default())
    }

    fn compare_explained(
        result: &IndexedMesh,
        iso: &IndexedMesh,
        explained: &FxHashSet<Cell>,
    ) -> Vec<Cell> {
        let edges: Vec<GridEdge> = iso
            .positions
            .iter()
            .map(|&p| GridEdge {
                corner: frame().to_grid(p).map(|x| x.floor() as i32),
                axis: 0,
            })
            .collect();
        mismatched(&frame(), result, (iso, &edges), explained)
    }

    fn join(a: &IndexedMesh, b: &IndexedMesh) -> IndexedMesh {
        let mut both = a.clone();
        let offset = both.positions.len() as u32;
        both.positions.extend(&b.positions);
        both.triangles
            .extend(b.triangles.iter().map(|t| t.map(|v| v + offset)));
        both
    }

    #[test]
    fn paired_components_are_not_mismatched() {
        let a = IndexedMesh::icosphere(Vec3::new(-2.0, 0.0, 0.0), 1.0, 3);
        let b = IndexedMesh::icosphere(Vec3::new(2.0, 0.0, 0.0), 1.0, 3);
        let shifted = IndexedMesh::icosphere(Vec3::new(2.05, 0.0, 0.0), 1.0, 2);
        assert!(compare(&join(&a, &b), &join(&a, &shifted)).is_empty());
    }

    #[test]
    fn only_the_components_that_differ_are_mismatched() {
        // The result keeps two balls apart where Θ has them touching as one; a third ball far
        // away is the same in both and is left out.
        let left = IndexedMesh::icosphere(Vec3::new(-0.9, 0.0, 0.0), 1.0, 3);
        let right = IndexedMesh::icosphere(Vec3::new(0.9, 0.0, 0.0), 1.0, 3);
        let far = IndexedMesh::icosphere(Vec3::new(6.0, 0.0, 0.0), 1.0, 3);
        let merged = IndexedMesh::icosphere(Vec3::ZERO, 1.9, 3);
        let wrong = compare(&join(&join(&left, &right), &far), &join(&merged, &far));
        let cell = |p: Vec3| frame().to_grid(p).map(|x| x.floor() as i32);
        assert!(wrong.binary_search(&cell(left.positions[0])).is_ok());
        assert!(wrong.binary_search(&cell(right.positions[0])).is_ok());
        assert!(
            far.positions
                .iter()
                .all(|&p| wrong.binary_search(&cell(p)).is_err())
        );
    }

    #[test]
    fn explained_components_and_droplets_are_left_to_the_caller() {
        // The result has a ball Θ lacks (a sheet Θ cannot hold, say) and a droplet next to a
        // ball both have: with the ball's cells explained, neither is a mismatch.
        let ball = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let extra = IndexedMesh::icosphere(Vec3::new(5.0, 0.0, 0.0), 1.0, 3);
        let droplet = IndexedMesh::icosphere(Vec3::new(1.2, 0.0, 0.0), 0.1, 1);
        let result = join(&join(&ball, &extra), &droplet);
        let cell = |p: Vec3| frame().to_grid(p).map(|x| x.floor() as i32);
        assert!(!compare(&result, &ball).is_empty());
        let explained: FxHashSet<Cell> = [cell(extra.positions[0])].into_iter().collect();
        assert!(compare_explained(&result, &ball, &explained).is_empty());
        // An unexplained ball is still a mismatch, droplet or not.
        let other: FxHashSet<Cell> = [cell(Vec3::new(-9.0, 0.0, 0.0))].into_iter().collect();
        let wrong = compare_explained(&result, &ball, &other);
        assert!(wrong.binary_search(&cell(extra.positions[0])).is_ok());
        assert!(wrong.binary_search(&cell(droplet.positions[0])).is_err());
    }
}
