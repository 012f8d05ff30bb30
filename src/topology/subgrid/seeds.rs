//! Where a graft's region starts (step 1 of the graft): the cells where the two surfaces differ
//! below the grid.
//!
//! Two kinds of difference seed it. A sample of either surface farther than the distance bound
//! from the other is a difference of shape, and its cell is a seed. A grid edge that one surface
//! crosses at least twice and the other a different number of times *may* be a difference of
//! topology: a sheet, tunnel or bridge thinner than a cell. But on a fluid's bumpy surface most
//! such edges are grazed by a ripple that one surface has and the other has moved a little: the
//! surfaces differ there in shape only, by far less than the bound, and re-sampling them costs
//! the coherence the tracker exists for (paper §4.3: only differences that change the topology
//! should re-sample the surface).
//!
//! An edge one surface crosses as a sheet where the other crosses the next parallel edge as many
//! times is no difference either: both have the sheet, a fraction of a cell apart (the topology
//! step keeps such shared sheets too, `TopologyOptions::keep_shared_sheets`).
//!
//! So the remaining edges are gathered into clusters of cells (the four cells around each edge, grown by
//! one, joined where they touch), and a cluster seeds the region only where replacing the tracked
//! surface by the input inside it changes the Euler characteristic: the graft keeps the tracked
//! triangles outside the region, `K`, copies the input's inside it, `C`, and joins them with
//! strips, annuli of characteristic 0, so the grafted surface has χ(K) + χ(C), while the tracked
//! one has χ(K) + χ(R) with `R` the tracked triangles it removes; the cluster changes χ by
//! χ(C) − χ(R). A cluster whose change is 0 holds ripples, or changes that cancel, and is left
//! alone. A cluster that changes χ is narrowed to the parts of it that carry the change
//! ([`split_changes`]): on a rippled sheet one hole that opened joins every ripple beside it in one
//! cluster. Every cluster stays at hand: when a graft of the narrowed parts misses the input's
//! topology, the region takes the whole clusters that change χ, and then all of them.

use glam::Vec3;
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};
use std::ops::Range;

use super::SubgridError;
use super::graft::submesh;
use crate::compute::Backend;
use crate::geometry::Components;
use crate::grid::{GridFrame, LatticeMesh, cross_axes, rasterize};
use crate::mesh::IndexedMesh;
use crate::topology::cell;
use crate::topology::classify::dilate;
use crate::topology::clusters::{Adjacent, EdgeNumbers, clusters, eulers, touching};
use crate::topology::keys::{Cell, NEIGHBOURS, PARALLEL_EDGES};
use crate::topology::nearest::Survivors;

/// The cells a graft's region starts from.
pub(super) struct Seeds {
    /// The cells of the far samples and of the parts of clusters that carry a change of the
    /// topology, grown by one.
    pub selected: Vec<Cell>,
    /// The cells of the far samples and of the whole clusters that change the topology, grown by
    /// one (the region's first fallback).
    pub changing: Vec<Cell>,
    /// The cells of the far samples and of every cluster, grown by one (the region's last
    /// fallback).
    pub all: Vec<Cell>,
}

/// The seeds where `ours` (the tracked component or components, as a mesh of its own) and `input`
/// (the input's component) differ, with `far` the samples of either farther than the bound from
/// the other (see the module comment). With `shape_only` (one tracked component, of the input's
/// Euler characteristic) only the far samples seed the region: every cluster of differently
/// crossed edges is then a ripple, or one of several changes that cancel, and grafting some of
/// them would give the component another topology. Where `ours` has several components, the
/// input's edges whose ends lie nearest to different ones seed it too: there the input joins
/// what the tracked surface keeps apart, by a bridge that may be too thin for any grid edge to
/// cross.
pub(super) fn seeds(
    backend: &Backend,
    frame: &GridFrame,
    (ours, input): (&IndexedMesh, &IndexedMesh),
    far: &[Vec3],
    shape_only: bool,
) -> Result<Seeds, SubgridError> {
    let mut far_cells: Vec<Cell> = far.iter().map(|&p| cell(frame, p)).collect();
    if shape_only {
        far_cells.extend(bridges(frame, ours, input));
        let selected = dilate(&far_cells, 1);
        return Ok(Seeds {
            changing: selected.clone(),
            all: selected.clone(),
            selected,
        });
    }
    // The bridges and both surfaces' crossings are independent: they are found side by side.
    let (bridged, (our_counts, their_counts)) = rayon::join(
        || bridges(frame, ours, input),
        || {
            rayon::join(
                || crossing_counts(backend, frame, ours),
                || crossing_counts(backend, frame, input),
            )
        },
    );
    far_cells.extend(bridged);
    let mut selected = dilate(&far_cells, 1);
    let (our_counts, their_counts) = (our_counts?, their_counts?);
    let differs = |n: u32, m: u32| n != m && n.max(m) >= 2;
    // A sheet both surfaces have, crossing the next parallel edge in one of them, is no difference.
    let shifted = |key: &(Cell, usize), n: u32, other: &FxHashMap<(Cell, usize), u32>| {
        n >= 2
            && PARALLEL_EDGES.iter().any(|d| {
                let c = [key.0[0] + d[0], key.0[1] + d[1], key.0[2] + d[2]];
                other.get(&(c, key.1)).copied().unwrap_or(0) == n
            })
    };
    let edges = our_counts
        .iter()
        .filter(|(key, n)| {
            differs(**n, their_counts.get(key).copied().unwrap_or(0))
                && !shifted(key, **n, &their_counts)
        })
        .chain(their_counts.iter().filter(|(key, m)| {
            !our_counts.contains_key(key) && differs(0, **m) && !shifted(key, **m, &our_counts)
        }));
    let mut around_edges: Vec<Cell> = Vec::new();
    for ((corner, axis), _) in edges {
        let (b, c) = cross_axes(*axis);
        for (db, dc) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            let mut around = *corner;
            around[b] -= db;
            around[c] -= dc;
            around_edges.push(around);
        }
    }
    around_edges.sort_unstable();
    around_edges.dedup();
    let found = clusters(&around_edges);
    let grown: Vec<Vec<Cell>> = found.iter().map(|m| dilate(m, 1)).collect();
    // Only the triangles with a corner in a grown cluster count in any cluster's change.
    let around: FxHashSet<Cell> = grown.iter().flatten().copied().collect();
    let (ours, input) = rayon::join(
        || in_zone(frame, ours, &around),
        || in_zone(frame, input, &around),
    );
    let (ours, input) = (&ours, &input);
    let changes = euler_changes(
        &found,
        (&Placed::new(frame, ours), &Placed::new(frame, input)),
    );
    let (mut changing, mut all) = (selected.clone(), selected.clone());
    let mut changes_of = Vec::new();
    let mut zone: FxHashSet<Cell> = FxHashSet::default();
    for ((cells, change), bare) in grown.into_iter().zip(changes).zip(found) {
        if change != 0 {
            changing.extend(cells.iter().copied());
            zone.extend(cells.iter().copied());
            changes_of.push((bare, change));
        }
        all.extend(cells);
    }
    for part in split_changes(frame, changes_of, &zone, (ours, input)) {
        selected.extend(dilate(&part, 1));
    }
    for set in [&mut selected, &mut changing, &mut all] {
        set.sort_unstable();
        set.dedup();
    }
    Ok(Seeds {
        selected,
        changing,
        all,
    })
}

/// The parts of the clusters `changing` (each its cells around differently crossed edges, not
/// grown, with the change of χ that replacing it makes) that carry their change. On a fluid's
/// rippled sheet the differently crossed edges touch one another across the sheet, and a cluster
/// holding one hole that opened holds every ripple beside it: selecting all of it re-samples the
/// sheet (dam-break frame 30: one re-sampled patch of 4,129 vertices, three in four of them
/// re-sampled again the next frame). So each cluster is cut in two by a grid plane, each side
/// split into the clusters it falls into, and where the parts' changes add up to the whole's,
/// the parts that change χ are kept and cut again. A plane through the change itself makes the
/// parts' grown cells count it twice or not at all, so several planes are tried ([`cuts`]) and,
/// of those whose parts add up, the one keeping the fewest cells is taken; where none adds up, or
/// the cluster is one cell wide, the cluster is kept whole. The graft checks the topology it
/// gives and falls back on the whole clusters, so a cut that misleads costs re-sampling, never
/// correctness. `zone` holds the clusters' cells grown by one: every part, grown by one, lies
/// there, so only the triangles with a corner in it count in any part's change, and each round
/// measures those alone.
fn split_changes(
    frame: &GridFrame,
    mut changing: Vec<(Vec<Cell>, i64)>,
    zone: &FxHashSet<Cell>,
    (ours, input): (&IndexedMesh, &IndexedMesh),
) -> Vec<Vec<Cell>> {
    let (ours, input) = rayon::join(
        || in_zone(frame, ours, zone),
        || in_zone(frame, input, zone),
    );
    let placed = (&Placed::new(frame, &ours), &Placed::new(frame, &input));
    let mut kept: Vec<Vec<Cell>> = Vec::new();
    while !changing.is_empty() {
        // Every cut of every cluster of this round is measured in one pass: per cluster, per
        // cut, the range of its parts.
        let mut parts: Vec<Vec<Cell>> = Vec::new();
        let mut tried: Vec<Vec<Range<usize>>> = Vec::with_capacity(changing.len());
        for (cells, _) in &changing {
            let touching = Adjacent::of(cells);
            tried.push(
                cuts(cells)
                    .into_iter()
                    .map(|(axis, plane)| {
                        let start = parts.len();
                        for low in [true, false] {
                            parts.extend(touching.clusters(|c| (c[axis] < plane) == low));
                        }
                        start..parts.len()
                    })
                    .collect(),
            );
        }
        let changes = euler_changes(&parts, placed);
        let mut next = Vec::new();
        for ((cells, change), ranges) in changing.into_iter().zip(tried) {
            let carrying = |range: &Range<usize>| range.clone().filter(|&k| changes[k] != 0);
            let best = ranges
                .into_iter()
                .filter(|range| changes[range.clone()].iter().sum::<i64>() == change)
                .min_by_key(|range| carrying(range).map(|k| parts[k].len()).sum::<usize>());
            match best {
                Some(range) => {
                    for k in carrying(&range).collect::<Vec<_>>() {
                        next.push((std::mem::take(&mut parts[k]), changes[k]));
                    }
                }
                None => kept.push(cells),
            }
        }
        changing = next;
    }
    kept
}

/// The triangles of `mesh` with a corner in a cell of `zone`, as a mesh of their own: the only
/// ones that count in the change of χ of a cluster that lies in `zone` once grown by one.
fn in_zone(frame: &GridFrame, mesh: &IndexedMesh, zone: &FxHashSet<Cell>) -> IndexedMesh {
    let inside: Vec<bool> = mesh
        .positions
        .par_iter()
        .map(|&p| zone.contains(&cell(frame, p)))
        .collect();
    let touching: Vec<u32> = (0..mesh.triangles.len() as u32)
        .into_par_iter()
        .filter(|&t| {
            mesh.triangles[t as usize]
                .iter()
                .any(|&v| inside[v as usize])
        })
        .collect();
    submesh(mesh, &touching)
}

/// The ways [`split_changes`] tries to cut `cells` in two, as (axis, plane): the cells below the
/// plane on one side, the others on the other; along each axis on which they are more than one
/// cell wide, the planes at a half, a quarter and three quarters of their extent, the widest axis
/// first. None where they are one cell wide in every direction.
fn cuts(cells: &[Cell]) -> Vec<(usize, i32)> {
    let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
    for c in cells {
        for a in 0..3 {
            lo[a] = lo[a].min(c[a]);
            hi[a] = hi[a].max(c[a]);
        }
    }
    let mut axes = [0, 1, 2];
    axes.sort_by_key(|&a| std::cmp::Reverse((hi[a] - lo[a], a)));
    let mut out = Vec::new();
    for axis in axes {
        let width = hi[axis] - lo[axis] + 1;
        let mut planes: Vec<i32> = [width / 2, width / 4, 3 * width / 4]
            .iter()
            .map(|&k| lo[axis] + k)
            .filter(|&p| lo[axis] < p && p <= hi[axis])
            .collect();
        planes.dedup();
        out.extend(planes.into_iter().map(|plane| (axis, plane)));
    }
    out
}

/// The cells of the input's edges whose ends lie nearest to different components of `ours`
/// (none when `ours` is one component).
fn bridges(frame: &GridFrame, ours: &IndexedMesh, input: &IndexedMesh) -> Vec<Cell> {
    let mut components = Components::new(ours.positions.len(), &ours.triangles);
    let label: Vec<u32> = (0..ours.positions.len() as u32)
        .map(|v| components.find(v))
        .collect();
    if label.iter().all(|&l| l == label[0]) {
        return Vec::new();
    }
    let near = Survivors::new(
        ours.positions
            .iter()
            .enumerate()
            .map(|(v, &p)| (v as u32, p)),
        frame.spacing(),
    );
    let owner: Vec<Option<u32>> = near
        .nearest_each(input.positions.par_iter().copied())
        .into_iter()
        .map(|v| v.map(|v| label[v as usize]))
        .collect();
    let mut cells = Vec::new();
    for t in &input.triangles {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            if owner[a] != owner[b] {
                cells.push(cell(frame, input.positions[a]));
                cells.push(cell(frame, input.positions[b]));
            }
        }
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

/// How many times the surface crosses each grid edge it crosses, keyed by (lower corner, axis).
fn crossing_counts(
    backend: &Backend,
    frame: &GridFrame,
    surface: &IndexedMesh,
) -> Result<FxHashMap<(Cell, usize), u32>, SubgridError> {
    let lattice = LatticeMesh::new(*frame, surface)?;
    let mut counts = FxHashMap::default();
    for crossing in rasterize(backend, &lattice)?.all() {
        *counts
            .entry((crossing.corner, crossing.axis()))
            .or_insert(0) += 1;
    }
    Ok(counts)
}

/// A mesh with the cell of each vertex: the distinct cells its vertices lie in (sorted), and the
/// index among them of each vertex's.
struct Placed<'a> {
    mesh: &'a IndexedMesh,
    cells: Vec<Cell>,
    of: Vec<u32>,
    /// The mesh's edges, numbered for counting the characteristics of many patches at once
    /// (`eulers`).
    edges: EdgeNumbers,
}

impl<'a> Placed<'a> {
    fn new(frame: &GridFrame, mesh: &'a IndexedMesh) -> Self {
        let ((cells, of), edges) = rayon::join(
            || {
                let at: Vec<Cell> = mesh.positions.par_iter().map(|&p| cell(frame, p)).collect();
                let mut cells = at.clone();
                cells.par_sort_unstable();
                cells.dedup();
                let of = at
                    .par_iter()
                    .map(|c| cells.partition_point(|x| x < c) as u32)
                    .collect();
                (cells, of)
            },
            || EdgeNumbers::of(mesh),
        );
        Placed {
            mesh,
            cells,
            of,
            edges,
        }
    }

    /// Per distinct cell, the clusters holding it once grown by one: those with a cell among
    /// its 27 neighbours (itself included), in increasing order. A vertex's clusters are read
    /// from its cell's, so no cluster is ever dilated. Where the clusters' cells are far fewer
    /// than the mesh's (the seeds' clusters), each hands its neighbours among the mesh's cells
    /// its cluster; otherwise (a split round's parts, every cut of every cluster) each of the
    /// mesh's cells looks its neighbours up among the clusters'.
    fn holders(&self, clusters: &[Vec<Cell>]) -> Vec<Vec<u32>> {
        let listed: usize = clusters.iter().map(Vec::len).sum();
        if 2 * listed <= self.cells.len() {
            let mut held: Vec<Vec<u32>> = vec![Vec::new(); self.cells.len()];
            for (k, cells) in clusters.iter().enumerate() {
                for c in cells {
                    for d in &NEIGHBOURS {
                        let n = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                        if let Ok(i) = self.cells.binary_search(&n)
                            && held[i].last() != Some(&(k as u32))
                        {
                            held[i].push(k as u32);
                        }
                    }
                }
            }
            return held;
        }
        let mut at: FxHashMap<Cell, Vec<u32>> = FxHashMap::default();
        for (k, cells) in clusters.iter().enumerate() {
            for &c in cells {
                at.entry(c).or_default().push(k as u32);
            }
        }
        self.cells
            .par_iter()
            .map(|c| {
                let mut held: Vec<u32> = NEIGHBOURS
                    .iter()
                    .filter_map(|d| at.get(&[c[0] + d[0], c[1] + d[1], c[2] + d[2]]))
                    .flatten()
                    .copied()
                    .collect();
                held.sort_unstable();
                held.dedup();
                held
            })
            .collect()
    }
}

/// Per cluster (its cells, not grown), χ(C) − χ(R) over the cluster grown by one: the input's
/// triangles with every corner in the grown cells, and the tracked triangles with any corner in
/// them (see the module comment).
fn euler_changes(clusters: &[Vec<Cell>], (ours, input): (&Placed, &Placed)) -> Vec<i64> {
    // Each side is gathered on its own core, and the clusters' characteristics in parallel.
    let (removed, copied) = rayon::join(
        || {
            let holders = ours.holders(clusters);
            touching(&ours.mesh.triangles, clusters.len(), |v| {
                &holders[ours.of[v as usize] as usize]
            })
        },
        || {
            let holders = input.holders(clusters);
            let at = |v: u32| &holders[input.of[v as usize] as usize];
            let mut copied: Vec<Vec<u32>> = vec![Vec::new(); clusters.len()];
            for (t, tri) in input.mesh.triangles.iter().enumerate() {
                let [a, b, c] = tri.map(at);
                for &k in a.iter().filter(|k| b.contains(k) && c.contains(k)) {
                    copied[k as usize].push(t as u32);
                }
            }
            copied
        },
    );
    let (copied, removed) = rayon::join(
        || eulers(input.mesh, &input.edges, &copied),
        || eulers(ours.mesh, &ours.edges, &removed),
    );
    copied.iter().zip(&removed).map(|(c, r)| c - r).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{ScalarGrid, marching_cubes};

    /// Sheets 0.24 cells thick at heights `centres` (in cells, on a grid of unit spacing), 8 cells
    /// wide: each lies between two planes of corners, so every vertical grid edge under it is
    /// crossed twice.
    fn sheets(centres: &[f32]) -> IndexedMesh {
        let centres = centres.to_vec();
        let f = move |p: Vec3| {
            centres
                .iter()
                .map(|&c| {
                    let d = (p - Vec3::new(0.0, 0.0, c)).abs() - Vec3::new(4.0, 4.0, 0.12);
                    d.max(Vec3::ZERO).length() + d.max_element().min(0.0)
                })
                .fold(f32::INFINITY, f32::min)
        };
        let h = 0.1;
        let origin = Vec3::new(-6.0, -6.0, -3.0) + Vec3::new(0.031, 0.017, 0.043);
        marching_cubes(
            &ScalarGrid::from_fn(origin, h, [120, 120, 80], f).unwrap(),
            0.0,
        )
    }

    /// A slab 40 × 6 × 2 cells (on a grid of unit spacing), with a tunnel of radius 1.2 through
    /// its thickness at x = HOLE where `tunnel`.
    const HOLE: f32 = 9.5;

    fn slab(tunnel: bool) -> IndexedMesh {
        let f = move |p: Vec3| {
            let d = p.abs() - Vec3::new(20.0, 3.0, 1.0);
            let slab = d.max(Vec3::ZERO).length() + d.max_element().min(0.0);
            let hole = 1.2 - Vec3::new(p.x - HOLE, p.y, 0.0).length();
            if tunnel { slab.max(hole) } else { slab }
        };
        let origin = Vec3::new(-22.0, -5.0, -3.0) + Vec3::new(0.031, 0.017, 0.043);
        marching_cubes(
            &ScalarGrid::from_fn(origin, 0.25, [176, 40, 24], f).unwrap(),
            0.0,
        )
    }

    #[test]
    fn a_cluster_that_changes_the_topology_narrows_to_where_it_does() {
        let frame = GridFrame::new(Vec3::new(0.013, -0.021, 0.007), 1.0).unwrap();
        let (ours, input) = (slab(false), slab(true));
        // One cluster over both surfaces whole: the tunnel changes χ from 2 to 0.
        let mut cluster: Vec<Cell> = ours
            .positions
            .iter()
            .chain(&input.positions)
            .map(|&p| cell(&frame, p))
            .collect();
        cluster.sort_unstable();
        cluster.dedup();
        let placed = (&Placed::new(&frame, &ours), &Placed::new(&frame, &input));
        let whole = euler_changes(std::slice::from_ref(&cluster), placed);
        assert_eq!(whole, vec![-2]);
        let zone: FxHashSet<Cell> = dilate(&cluster, 1).into_iter().collect();
        let parts = split_changes(&frame, vec![(cluster.clone(), -2)], &zone, (&ours, &input));
        // The parts still carry the change, and lie around the tunnel only.
        assert_eq!(euler_changes(&parts, placed).iter().sum::<i64>(), -2);
        let cells: usize = parts.iter().map(Vec::len).sum();
        assert!(4 * cells <= cluster.len(), "{cells} of {}", cluster.len());
        assert!(parts.iter().flatten().all(|c| c[0] >= 3), "{parts:?}");
        // Where nothing changes χ on one side of every cut, nothing is kept there either; a
        // cluster one cell wide stays whole.
        let single = vec![cluster[0]];
        assert_eq!(
            split_changes(&frame, vec![(single.clone(), 1)], &zone, (&ours, &input)),
            vec![single]
        );
    }

    /// Every cut's sides fall into the clusters that `clusters` finds for them anew.
    #[test]
    fn the_sides_of_a_cut_cluster_as_clusters_finds_them() {
        // The groups of touching cells found by comparing every pair, sorted and numbered by
        // their first cell: what `clusters` must give, found without it.
        let compared = |cells: &[Cell]| -> Vec<Vec<Cell>> {
            let touch = |a: &Cell, b: &Cell| (0..3).all(|k| (a[k] - b[k]).abs() <= 1);
            let mut label: Vec<Option<usize>> = vec![None; cells.len()];
            let mut groups: Vec<Vec<Cell>> = Vec::new();
            for start in 0..cells.len() {
                if label[start].is_some() {
                    continue;
                }
                label[start] = Some(groups.len());
                let mut stack = vec![start];
                while let Some(i) = stack.pop() {
                    for j in 0..cells.len() {
                        if label[j].is_none() && touch(&cells[i], &cells[j]) {
                            label[j] = Some(groups.len());
                            stack.push(j);
                        }
                    }
                }
                groups.push(Vec::new());
            }
            for (c, k) in cells.iter().zip(label) {
                groups[k.unwrap_or(0)].push(*c);
            }
            groups
        };
        // A ring, a bar through it and scattered cells: cuts split them into several pieces.
        let mut cells: Vec<Cell> = Vec::new();
        for k in 0..40 {
            let a = k as f32 * std::f32::consts::TAU / 40.0;
            cells.push([(8.0 * a.cos()) as i32, (8.0 * a.sin()) as i32, 0]);
        }
        cells.extend((-10..10).map(|x| [x, 0, x / 4]));
        cells.extend([[20, 20, 20], [21, 21, 21], [25, 20, 20]]);
        cells.sort_unstable();
        cells.dedup();
        let touching = Adjacent::of(&cells);
        let planes = cuts(&cells);
        assert!(planes.len() >= 6);
        for (axis, plane) in planes {
            for low in [true, false] {
                let side = |c: &Cell| (c[axis] < plane) == low;
                let subset: Vec<Cell> = cells.iter().copied().filter(side).collect();
                assert_eq!(touching.clusters(side), compared(&subset));
                assert_eq!(clusters(&subset), compared(&subset));
            }
        }
        assert_eq!(touching.clusters(|_| true), compared(&cells));
        assert_eq!(clusters(&cells), compared(&cells));
    }

    #[test]
    fn a_sheet_one_edge_apart_is_no_difference_but_a_second_sheet_is() {
        let frame = GridFrame::new(Vec3::new(0.013, -0.021, 0.007), 1.0).unwrap();
        let ours = sheets(&[0.5]);
        // The same sheet one cell higher crosses the next vertical edges, as often.
        let shifted = seeds(&Backend::Cpu, &frame, (&ours, &sheets(&[1.5])), &[], false).unwrap();
        assert!(shifted.all.is_empty(), "{} cells", shifted.all.len());
        // A second sheet below the first crosses its edges twice more.
        let doubled = sheets(&[0.3, 0.7]);
        let seeded = seeds(&Backend::Cpu, &frame, (&ours, &doubled), &[], false).unwrap();
        assert!(!seeded.all.is_empty());
    }
}
