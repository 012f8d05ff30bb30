//! Where a re-sampled surface's topology came out unlike Θ's (paper §4.3): the components of the
//! result and of Θ's isosurface that do not pair one to one with equal Euler characteristics. A
//! shallow difference left out of the region can still change the topology; the next attempt
//! then counts every difference as deep, but first only in these components' cells rather than
//! everywhere — on a fluid's rippled surface, everywhere is most of the surface.

use glam::Vec3;
use rustc_hash::{FxHashMap, FxHashSet};

use super::cell;
use super::field::Field;
use super::isosurface::isosurface_positions;
use super::keys::{Cell, GridEdge};
use super::subgrid::SMALL_CELLS;
use crate::geometry::Components;
use crate::grid::GridFrame;
use crate::mesh::{IndexedMesh, Topology};

/// Θ's isosurface as [`mismatched`] compares results with it: its components, the cells each
/// lies in and which are droplets. Θ is the same for every attempt of one step, so this is built
/// once per step rather than once per comparison.
pub(crate) struct Isosurface {
    topology: Topology,
    cells: Vec<(Cell, u32)>,
    droplets: Vec<bool>,
    blobs: Vec<bool>,
}

impl Isosurface {
    /// From Θ's isosurface as [`isosurface`](super::isosurface::isosurface) builds it: its
    /// connectivity, one vertex on each grid edge of `edges`, and no positions. Which components
    /// are droplets is a question of their size, so it is read at the vertices' places on Θ's zero
    /// set; at the unplaced positions (all at the origin) every component of Θ, the main body
    /// included, would count as a droplet and take no part in pairing.
    pub(crate) fn of_field(field: &Field, iso: &IndexedMesh, edges: &[GridEdge]) -> Self {
        Self::new(
            field.frame(),
            iso,
            &isosurface_positions(field, edges),
            edges,
        )
    }

    /// From the connectivity of Θ's isosurface `iso` and its vertices' `positions`, one on each
    /// grid edge of `edges`.
    pub(crate) fn new(
        frame: &GridFrame,
        iso: &IndexedMesh,
        positions: &[Vec3],
        edges: &[GridEdge],
    ) -> Self {
        let (topology, labels) = iso.topology_with_labels();
        // A vertex of the isosurface lies on its grid edge, in the cells around the edge's corner.
        let cells = cells_of(edges.iter().map(|e| e.corner), &labels);
        let count = topology.components.len();
        let spans = spans(positions, &labels, count);
        let droplets = within(frame, &spans, SMALL_CELLS);
        let blobs = within(frame, &spans, BLOB_CELLS);
        Self {
            topology,
            cells,
            droplets,
            blobs,
        }
    }
}

/// The pairs (cell, component) of points in `cells` numbered by `labels`, one label per point;
/// sorted, without repeats.
fn cells_of(cells: impl Iterator<Item = Cell>, labels: &[u32]) -> Vec<(Cell, u32)> {
    let mut at: Vec<(Cell, u32)> = cells
        .zip(labels)
        .filter(|&(_, &l)| l != u32::MAX)
        .map(|(c, &l)| (c, l))
        .collect();
    at.sort_unstable();
    at.dedup();
    at
}

/// The pairs (component of `ours`, component of `theirs`) with cells in or next to each other's,
/// sorted, without repeats. Cells sort by x, then y, then z, so for each of the nine x and y
/// offsets the neighbours of a cell are one contiguous range (three values of z) in `theirs`,
/// and the ranges of cells in sorted order move forward: nine passes over the two lists, without
/// a lookup per cell.
fn near_pairs(ours: &[(Cell, u32)], theirs: &[(Cell, u32)]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    for dx in -1..=1 {
        for dy in -1..=1 {
            let mut from = 0;
            for &([x, y, z], r) in ours {
                let (lo, hi) = ([x + dx, y + dy, z - 1], [x + dx, y + dy, z + 1]);
                while from < theirs.len() && theirs[from].0 < lo {
                    from += 1;
                }
                pairs.extend(
                    theirs[from..]
                        .iter()
                        .take_while(|t| t.0 <= hi)
                        .map(|&(_, t)| (r, t)),
                );
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Components whose bounding-box diagonal is at most this many cells count as blobs: a group of
/// them that pairs badly is left to the sub-grid match (see [`mismatched`]).
const BLOB_CELLS: f32 = 4.0 * SMALL_CELLS;

/// The unpaired components of one group joined by nearness: their Euler characteristics, per
/// side, and whether all are blobs.
struct Group {
    ours: Vec<i64>,
    theirs: Vec<i64>,
    blobs: bool,
}

impl Default for Group {
    fn default() -> Self {
        Self {
            ours: Vec::new(),
            theirs: Vec::new(),
            blobs: true,
        }
    }
}

/// The cells (sorted, without repeats) of the vertices of every component of `result` and of Θ's
/// isosurface `iso` that does not pair with exactly one component of the other, lying in the same
/// or neighbouring cells, of the same Euler characteristic. With `explained` cells (a caller that
/// matches the input below the grid afterwards), those the caller settles are left out: the
/// components holding an explained cell, droplets, and groups of unpaired components joined by
/// nearness that hold the same components on both sides or only blobs.
pub(crate) fn mismatched(
    frame: &GridFrame,
    result: &IndexedMesh,
    iso: &Isosurface,
    explained: &FxHashSet<Cell>,
) -> Vec<Cell> {
    let (ours, our_labels) = result.topology_with_labels();
    let (theirs, their_cells) = (&iso.topology, &iso.cells);
    let our_cells = cells_of(
        result.positions.iter().map(|p| cell(frame, *p)),
        &our_labels,
    );
    // The components of the other surface in or next to each component's cells.
    let mut our_partners: Vec<Vec<u32>> = vec![Vec::new(); ours.components.len()];
    let mut their_partners: Vec<Vec<u32>> = vec![Vec::new(); theirs.components.len()];
    for (r, i) in near_pairs(&our_cells, their_cells) {
        our_partners[r as usize].push(i);
        their_partners[i as usize].push(r);
    }
    // A difference the caller knows the cause of (a sheet thinner than a cell that both surfaces
    // have, which Θ cannot hold) leaves its components, and Θ's next to them, alone; so do
    // droplets, which the caller matches below the grid too, and which take no part in pairing.
    let (mut known, mut theirs_known) = (
        vec![false; ours.components.len()],
        vec![false; theirs.components.len()],
    );
    // The span of each component, read once for the droplets and blobs below.
    let count = ours.components.len();
    let our_spans = if explained.is_empty() {
        Vec::new()
    } else {
        spans(&result.positions, &our_labels, count)
    };
    if !explained.is_empty() {
        let our_droplets = within(frame, &our_spans, SMALL_CELLS);
        let droplets = &iso.droplets;
        known.clone_from(&our_droplets);
        for (c, l) in &our_cells {
            if explained.contains(c) {
                known[*l as usize] = true;
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
        // A component of the result whose every neighbour in Θ is left alone is left alone too:
        // a blob next to an explained body, which a component of Θ next to that body matches, has
        // no other partner to pair with, and counting it as wrong sent the next attempt over every
        // shallow difference of the surface (dam-break frame 23: 7,951 cells instead of 2,944).
        for (r, near) in our_partners.iter().enumerate() {
            if !near.is_empty() && near.iter().all(|&i| theirs_known[i as usize]) {
                known[r] = true;
            }
        }
    }
    let paired = |r: usize| -> Option<usize> {
        let i = match our_partners[r][..] {
            [i] => i as usize,
            _ => return None,
        };
        (their_partners[i].len() == 1 && ours.components[r].euler == theirs.components[i].euler)
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
    if !explained.is_empty() {
        // Blobs within a cell of each other pair with several of the other surface's at once.
        // A group of unpaired components joined by nearness is left to the sub-grid match too
        // where its two sides hold as many components of the same Euler characteristics, or
        // where every member is a blob (within [`BLOB_CELLS`] cells): the sub-grid match pairs
        // them by where their vertices lie and re-samples at most the blobs, while the next
        // attempt here would count every difference of the surface as deep (DFSPH frame 23: two
        // blobs of 38 and 61 cells beside Θ's one sent the step over 12,134 cells, after three
        // attempts).
        let our_blobs = within(frame, &our_spans, BLOB_CELLS);
        let mut groups = Components::new(count + theirs.components.len(), &[]);
        for (r, near) in our_partners.iter().enumerate() {
            for &i in near {
                if ours_off[r] && theirs_off[i as usize] {
                    groups.join(r as u32, (count + i as usize) as u32);
                }
            }
        }
        let mut sides: FxHashMap<u32, Group> = FxHashMap::default();
        for (r, _) in ours_off.iter().enumerate().filter(|(_, off)| **off) {
            let group = sides.entry(groups.find(r as u32)).or_default();
            group.ours.push(ours.components[r].euler);
            group.blobs &= our_blobs[r];
        }
        for (i, _) in theirs_off.iter().enumerate().filter(|(_, off)| **off) {
            let group = sides.entry(groups.find((count + i) as u32)).or_default();
            group.theirs.push(theirs.components[i].euler);
            group.blobs &= iso.blobs[i];
        }
        let alike: FxHashSet<u32> = sides
            .into_iter()
            .filter_map(|(g, mut group)| {
                group.ours.sort_unstable();
                group.theirs.sort_unstable();
                (group.blobs || group.ours == group.theirs).then_some(g)
            })
            .collect();
        for (r, off) in ours_off.iter_mut().enumerate() {
            *off &= !alike.contains(&groups.find(r as u32));
        }
        for (i, off) in theirs_off.iter_mut().enumerate() {
            *off &= !alike.contains(&groups.find((count + i) as u32));
        }
    }
    let mut out: Vec<Cell> = our_cells
        .iter()
        .filter(|&&(_, l)| ours_off[l as usize])
        .chain(their_cells.iter().filter(|&&(_, l)| theirs_off[l as usize]))
        .map(|&(c, _)| c)
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Per component (`labels` numbering the vertices at `positions`), the length of its bounding
/// box's diagonal.
pub(super) fn spans(positions: &[Vec3], labels: &[u32], count: usize) -> Vec<f32> {
    let mut boxes = vec![(Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)); count];
    for (p, &l) in positions.iter().zip(labels) {
        if let Some(b) = boxes.get_mut(l as usize) {
            *b = (b.0.min(*p), b.1.max(*p));
        }
    }
    boxes.iter().map(|(lo, hi)| (*hi - *lo).length()).collect()
}

/// Per component of `spans`, whether it spans at most `cells` cells of `frame`: [`SMALL_CELLS`]
/// for a droplet, which the sub-grid match settles.
pub(super) fn within(frame: &GridFrame, spans: &[f32], cells: f32) -> Vec<bool> {
    spans
        .iter()
        .map(|&s| s <= cells * frame.spacing())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

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
                corner: cell(&frame(), p),
                axis: 0,
            })
            .collect();
        mismatched(
            &frame(),
            result,
            &Isosurface::new(&frame(), iso, &iso.positions, &edges),
            explained,
        )
    }

    #[test]
    fn near_pairs_are_every_pair_of_cells_at_most_one_step_apart() {
        // Scattered cells, some repeated, of several components.
        let list = |seed: i32, count: u32| -> Vec<(Cell, u32)> {
            let points = (0..60).map(|k: i32| {
                let h = (k * 7919 + seed * 104729).rem_euclid(1000);
                [h % 10, (h / 10) % 10, (h / 100) % 10]
            });
            let labels: Vec<u32> = (0..60).map(|k| (k * 13 + seed as u32) % count).collect();
            cells_of(points, &labels)
        };
        let (ours, theirs) = (list(1, 12), list(2, 15));
        let mut brute: Vec<(u32, u32)> = Vec::new();
        for &(c, r) in &ours {
            for &(n, t) in &theirs {
                if (0..3).all(|a| (c[a] - n[a]).abs() <= 1) {
                    brute.push((r, t));
                }
            }
        }
        brute.sort_unstable();
        brute.dedup();
        assert!(!brute.is_empty() && brute.len() < 12 * 15);
        assert_eq!(near_pairs(&ours, &theirs), brute);
    }

    #[test]
    fn paired_components_are_not_mismatched() {
        let a = IndexedMesh::icosphere(Vec3::new(-2.0, 0.0, 0.0), 1.0, 3);
        let b = IndexedMesh::icosphere(Vec3::new(2.0, 0.0, 0.0), 1.0, 3);
        let shifted = IndexedMesh::icosphere(Vec3::new(2.05, 0.0, 0.0), 1.0, 2);
        assert!(compare(&a.joined(&b), &a.joined(&shifted)).is_empty());
    }

    #[test]
    fn only_the_components_that_differ_are_mismatched() {
        // The result keeps two balls apart where Θ has them touching as one; a third ball far
        // away is the same in both and is left out.
        let left = IndexedMesh::icosphere(Vec3::new(-0.9, 0.0, 0.0), 1.0, 3);
        let right = IndexedMesh::icosphere(Vec3::new(0.9, 0.0, 0.0), 1.0, 3);
        let far = IndexedMesh::icosphere(Vec3::new(6.0, 0.0, 0.0), 1.0, 3);
        let merged = IndexedMesh::icosphere(Vec3::ZERO, 1.9, 3);
        let wrong = compare(&left.joined(&right).joined(&far), &merged.joined(&far));
        let cell_of = |p: Vec3| cell(&frame(), p);
        assert!(wrong.binary_search(&cell_of(left.positions[0])).is_ok());
        assert!(wrong.binary_search(&cell_of(right.positions[0])).is_ok());
        assert!(
            far.positions
                .iter()
                .all(|&p| wrong.binary_search(&cell_of(p)).is_err())
        );
    }

    #[test]
    fn droplets_of_an_unplaced_isosurface_are_told_by_their_size() {
        // A body 4.8 cells across and a droplet 2 cells across (grid 0.25): the body is no droplet
        // although the isosurface comes without positions.
        let frame = frame();
        let field = Field::from_fn(frame, [-8; 3], [12; 3], |p| {
            (p.length() - 0.6).min((p - Vec3::new(1.8, 0.0, 0.0)).length() - 0.25)
        })
        .unwrap();
        let (iso, edges) = super::super::isosurface::isosurface(&field, &field.surface());
        assert!(iso.positions.iter().all(|p| *p == Vec3::ZERO));
        let compared = Isosurface::of_field(&field, &iso, &edges);
        assert_eq!(compared.topology.components.len(), 2);
        let mut droplets = compared.droplets.clone();
        droplets.sort_unstable();
        assert_eq!(droplets, vec![false, true]);
    }

    #[test]
    fn a_blob_next_to_an_explained_body_is_left_alone_with_it() {
        // A body whose cells are explained, a blob (not a droplet: 1.2 across, grid 0.25) within a
        // cell of it in both surfaces, and a body far away (larger than a blob) that Θ has and
        // the result lacks.
        let body = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let blob = IndexedMesh::icosphere(Vec3::new(1.75, 0.0, 0.0), 0.6, 3);
        let far = IndexedMesh::icosphere(Vec3::new(9.0, 0.0, 0.0), 2.5, 3);
        let result = body.joined(&blob);
        let theta = body.joined(&blob).joined(&far);
        let cell_of = |p: Vec3| cell(&frame(), p);
        let explained: FxHashSet<Cell> = [cell_of(body.positions[0])].into_iter().collect();
        // The blob's only partner besides the body's is left alone with the body; the far body
        // Θ has alone is still a mismatch, and the near blob is not.
        let wrong = compare_explained(&result, &theta, &explained);
        assert!(wrong.binary_search(&cell_of(far.positions[0])).is_ok());
        assert!(
            blob.positions
                .iter()
                .all(|&p| wrong.binary_search(&cell_of(p)).is_err())
        );
    }

    #[test]
    fn explained_components_and_droplets_are_left_to_the_caller() {
        // The result has a ball Θ lacks (a sheet Θ cannot hold, say; larger than a blob) and a
        // droplet next to a ball both have: with the ball's cells explained, neither is a
        // mismatch.
        let ball = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let extra = IndexedMesh::icosphere(Vec3::new(8.0, 0.0, 0.0), 2.5, 3);
        let droplet = IndexedMesh::icosphere(Vec3::new(1.2, 0.0, 0.0), 0.1, 1);
        let result = ball.joined(&extra).joined(&droplet);
        let cell_of = |p: Vec3| cell(&frame(), p);
        assert!(!compare(&result, &ball).is_empty());
        let explained: FxHashSet<Cell> = [cell_of(extra.positions[0])].into_iter().collect();
        assert!(compare_explained(&result, &ball, &explained).is_empty());
        // An unexplained ball is still a mismatch, droplet or not.
        let other: FxHashSet<Cell> = [cell_of(Vec3::new(-9.0, 0.0, 0.0))].into_iter().collect();
        let wrong = compare_explained(&result, &ball, &other);
        assert!(wrong.binary_search(&cell_of(extra.positions[0])).is_ok());
        assert!(wrong.binary_search(&cell_of(droplet.positions[0])).is_err());
    }

    /// Two blobs of the result within a cell of each other beside one blob of Θ pair with no
    /// one: as a group of blobs they are left to the sub-grid match; the same scaled past the
    /// size of a blob is a mismatch.
    #[test]
    fn a_group_of_blobs_that_pairs_badly_is_left_to_the_caller() {
        let cell_of = |p: Vec3| cell(&frame(), p);
        let explained: FxHashSet<Cell> =
            [cell_of(Vec3::new(-40.0, 0.0, 0.0))].into_iter().collect();
        let surfaces = |scale: f32| {
            let a = IndexedMesh::icosphere(Vec3::ZERO, 0.4 * scale, 3);
            let b = IndexedMesh::icosphere(Vec3::new(0.95 * scale, 0.0, 0.0), 0.4 * scale, 3);
            let theta = IndexedMesh::icosphere(Vec3::new(0.5 * scale, 0.0, 0.0), 0.6 * scale, 3);
            (a.joined(&b), theta)
        };
        let (result, theta) = surfaces(1.0);
        assert!(compare_explained(&result, &theta, &explained).is_empty());
        // Unexplained, every difference counts.
        assert!(!compare(&result, &theta).is_empty());
        let (result, theta) = surfaces(4.0);
        assert!(!compare_explained(&result, &theta, &explained).is_empty());
    }

    /// Blobs that pair badly but hold the same components on both sides, some larger than a
    /// blob, are left alone; one more on either side is not.
    #[test]
    fn a_group_with_the_same_components_on_both_sides_is_left_to_the_caller() {
        let cell_of = |p: Vec3| cell(&frame(), p);
        let explained: FxHashSet<Cell> =
            [cell_of(Vec3::new(-40.0, 0.0, 0.0))].into_iter().collect();
        // Two large balls a little apart in the result, and two in Θ shifted along the line by
        // half the gap, so each of Θ's lies next to both of the result's.
        let ball = |x: f32| IndexedMesh::icosphere(Vec3::new(x, 0.0, 0.0), 2.5, 3);
        let result = ball(0.0).joined(&ball(5.2));
        let theta = ball(0.1).joined(&ball(5.1));
        assert!(compare_explained(&result, &theta, &explained).is_empty());
        let more = result.joined(&ball(10.4));
        assert!(!compare_explained(&more, &theta, &explained).is_empty());
    }
}
