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
//! alone. Every cluster stays at hand: when a graft of the selected ones still misses the input's
//! topology, the region takes them all.

use glam::Vec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::SubgridError;
use crate::compute::Backend;
use crate::geometry::Components;
use crate::grid::{GridFrame, LatticeMesh, cross_axes, rasterize};
use crate::mesh::IndexedMesh;
use crate::topology::classify::dilate;
use crate::topology::clusters::{clusters, euler, holders, touching};
use crate::topology::keys::{Cell, PARALLEL_EDGES};
use crate::topology::nearest::Survivors;

/// The cells a graft's region starts from.
pub(super) struct Seeds {
    /// The cells of the far samples and of the clusters that change the topology, grown by one.
    pub selected: Vec<Cell>,
    /// The cells of the far samples and of every cluster, grown by one (the region's fallback).
    pub all: Vec<Cell>,
}

/// The grid cell holding `p`.
pub(super) fn cell(frame: &GridFrame, p: Vec3) -> Cell {
    frame.to_grid(p).map(|x| x.floor() as i32)
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
    let grown: Vec<Vec<Cell>> = clusters(&around_edges)
        .iter()
        .map(|m| dilate(m, 1))
        .collect();
    let changes = euler_changes(frame, &grown, ours, input);
    let mut all = selected.clone();
    for (cells, change) in grown.into_iter().zip(changes) {
        if change != 0 {
            selected.extend(cells.iter().copied());
        }
        all.extend(cells);
    }
    for set in [&mut selected, &mut all] {
        set.sort_unstable();
        set.dedup();
    }
    Ok(Seeds { selected, all })
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

/// Per cluster, given by its cells grown by one, χ(C) − χ(R): the input's triangles with every
/// corner in the cluster's cells, and the tracked triangles with any corner in them (see the
/// module comment).
fn euler_changes(
    frame: &GridFrame,
    grown: &[Vec<Cell>],
    ours: &IndexedMesh,
    input: &IndexedMesh,
) -> Vec<i64> {
    let holders = holders(grown);
    let none: Vec<u32> = Vec::new();
    let clusters_at = |p: Vec3| holders.get(&cell(frame, p)).unwrap_or(&none);
    // Each side is gathered on its own core, and the clusters' characteristics in parallel.
    let (removed, copied) = rayon::join(
        || {
            touching(&ours.triangles, grown.len(), |v| {
                clusters_at(ours.positions[v as usize])
            })
        },
        || {
            let mut copied: Vec<Vec<u32>> = vec![Vec::new(); grown.len()];
            for (t, tri) in input.triangles.iter().enumerate() {
                let [a, b, c] = tri.map(|v| clusters_at(input.positions[v as usize]));
                for &k in a.iter().filter(|k| b.contains(k) && c.contains(k)) {
                    copied[k as usize].push(t as u32);
                }
            }
            copied
        },
    );
    removed
        .par_iter()
        .zip(&copied)
        .map(|(r, c)| euler(input, c) - euler(ours, r))
        .collect()
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
