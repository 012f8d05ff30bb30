//! Classification (thesis §3.4.4, design note §2 steps 2–3): the cells where the mesh and Θ differ
//! deeply enough that the mesh must be re-sampled there.
//!
//! * **Self-intersection** — a grid edge along which the mesh's winding leaves {0, 1} (the surface
//!   overlaps or is inverted there): its four cells, always.
//! * **Corner mismatch** — the mesh and Θ disagree on whether a corner is inside: its eight cells,
//!   if the difference is *deep*. It is shallow when, within `depth` grid steps (L1), Θ holds the
//!   mesh's material and the mesh holds Θ's: both surfaces pass that close to the corner, so they
//!   differ by a wiggle thinner than a cell, which is not worth re-sampling (the paper's deep cells,
//!   after Wojtan et al.; TopoFixer's L1 test).
//! * **Multiply crossed edge** — the mesh crosses a grid edge more than once (a sheet, strand or gap
//!   thinner than a cell): its four cells, if deep, i.e. unless every material the mesh holds
//!   between its crossings appears in Θ within `depth` steps of the edge.
//! * **Sub-cell component** — a mesh component that crosses no grid edge is invisible to Θ's grid
//!   (no isosurface of Θ can have it): the cells of its vertices, always.
//! * With `faces` set, every face the mesh meets that could not be a front face (a closed loop on
//!   it, or arcs pairing its crossings unlike the face rule): both its cells.
//!
//! `depth = 0` makes every difference deep. The result is sorted and free of duplicates.

use rayon::prelude::*;
use rustc_hash::FxHashSet;

use super::face_arcs::face_arcs;
use super::field::Field;
use super::keys::{Cell, Corner, GridEdge, GridFace, PARALLEL_EDGES, corner_cells};
use super::mesh_grid::MeshGrid;
use super::region::pairs_follow_rule;
use crate::geometry::Components;
use crate::grid::{GridCrossing, GridLine};
use crate::mesh::IndexedMesh;

/// How strictly one attempt classifies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Strictness {
    /// L1 distance in grid steps within which a difference counts as shallow; 0: none does.
    pub depth: u32,
    /// Also seed the cells of faces that could not be front faces.
    pub faces: bool,
    /// Grow the seeds by this many cells in every direction.
    pub dilate: u32,
    /// A grid edge the mesh crosses as a sheet, without overlap, where Θ's own mesh crosses the
    /// same edge or one beside it more than once, is no difference (see
    /// `TopologyOptions::keep_shared_sheets`).
    pub keep_shared: bool,
}

/// Offsets within L1 distance `d` of the origin.
fn ball(d: u32) -> Vec<[i32; 3]> {
    let d = d as i32;
    let mut out = Vec::new();
    for x in -d..=d {
        for y in -d..=d {
            for z in -d..=d {
                if x.abs() + y.abs() + z.abs() <= d {
                    out.push([x, y, z]);
                }
            }
        }
    }
    out
}

fn offset(c: Corner, o: [i32; 3]) -> Corner {
    [c[0] + o[0], c[1] + o[1], c[2] + o[2]]
}

/// Seeds of the complex region for one attempt.
pub(crate) fn seeds(grid: &MeshGrid, field: &Field, strictness: &Strictness) -> Vec<Cell> {
    let near = ball(strictness.depth);
    let depth = strictness.depth;
    let per_line: Vec<(Vec<Cell>, Vec<Corner>)> = paired_lines(grid, field)
        .into_par_iter()
        .with_min_len(64)
        .map(|(line, m, t)| {
            let crossings = m.map_or(&[][..], |l| grid.crossings.of_line(l));
            let flips = t.map_or(&[][..], |l| field.signs().of_line(l));
            line_differences(field, line, crossings, flips, strictness, &near)
        })
        .collect();
    let mut seeds: Vec<Cell> = Vec::new();
    let mut mismatched: Vec<Corner> = Vec::new();
    for (s, c) in per_line {
        seeds.extend(s);
        mismatched.extend(c);
    }
    mismatched.par_sort_unstable();
    mismatched.dedup();
    seeds.par_extend(
        mismatched
            .par_iter()
            .filter(|&&c| {
                deep_corner(
                    grid,
                    field,
                    c,
                    !field.inside(c),
                    field.inside(c),
                    depth,
                    &near,
                )
            })
            .flat_map_iter(|&c| corner_cells(c)),
    );
    seeds.extend(sub_cell_components(grid));
    if strictness.faces {
        seeds.extend(complex_faces(grid, field));
    }
    seeds.par_sort_unstable();
    seeds.dedup();
    if strictness.dilate > 0 {
        seeds = dilate(&seeds, strictness.dilate);
    }
    seeds
}

/// The grid lines on which the mesh has crossings or Θ's sign flips, with their numbers among the
/// mesh's crossing lines and among Θ's sign lines.
fn paired_lines(grid: &MeshGrid, field: &Field) -> Vec<(GridLine, Option<usize>, Option<usize>)> {
    let (m, t) = (grid.crossings.index().lines(), field.signs().lines());
    let (mut i, mut j) = (0, 0);
    let mut out = Vec::with_capacity(m.len().max(t.len()));
    while i < m.len() || j < t.len() {
        let order = match (m.get(i), t.get(j)) {
            (Some(a), Some(b)) => a.cmp(b),
            (Some(_), None) => std::cmp::Ordering::Less,
            _ => std::cmp::Ordering::Greater,
        };
        out.push(match order {
            std::cmp::Ordering::Less => (m[i], Some(i), None),
            std::cmp::Ordering::Greater => (t[j], None, Some(j)),
            std::cmp::Ordering::Equal => (m[i], Some(i), Some(j)),
        });
        i += usize::from(order != std::cmp::Ordering::Greater);
        j += usize::from(order != std::cmp::Ordering::Less);
    }
    out
}

/// The differences along one grid line: seeds from its crossed edges (self-intersection, deep
/// multiple crossings) and the corners where the mesh and Θ disagree, among the ends of the edges
/// the mesh crosses or Θ flips on. Both are read walking the line once: the mesh's winding is the
/// sum of the crossings before a corner, Θ's sign the parity of the flips up to it.
fn line_differences(
    field: &Field,
    line: GridLine,
    crossings: &[GridCrossing],
    flips: &[i32],
    strictness: &Strictness,
    near: &[[i32; 3]],
) -> (Vec<Cell>, Vec<Corner>) {
    let depth = strictness.depth;
    let mut seeds = Vec::new();
    let mut at: Vec<i32> = Vec::with_capacity(2 * crossings.len() + 2 * flips.len());
    for (group, sequence) in edge_windings(crossings) {
        let edge = GridEdge::new(group[0].corner, group[0].axis());
        at.extend([group[0].along(), group[0].along() + 1]);
        let shared = strictness.keep_shared && shared_sheet(field, &edge, &sequence);
        if sequence.iter().any(|w| !(0..=1).contains(w))
            || (group.len() >= 2 && !shared && deep_edge(field, &edge, &sequence, depth, near))
        {
            seeds.extend(edge.cells());
        }
    }
    for &f in flips {
        at.extend([f - 1, f]);
    }
    at.sort_unstable();
    at.dedup();
    let (mut c, mut f, mut winding) = (0, 0, 0);
    let mut mismatched = Vec::new();
    for k in at {
        while c < crossings.len() && crossings[c].along() < k {
            winding += crossings[c].sign();
            c += 1;
        }
        while f < flips.len() && flips[f] <= k {
            f += 1;
        }
        if (winding >= 1) != (f % 2 == 1) {
            mismatched.push(line.corner(k));
        }
    }
    (seeds, mismatched)
}

/// A corner mismatch is shallow when, nearby, Θ holds the mesh's material and the mesh holds Θ's.
fn deep_corner(
    grid: &MeshGrid,
    field: &Field,
    corner: Corner,
    mesh_inside: bool,
    theta_inside: bool,
    depth: u32,
    near: &[[i32; 3]],
) -> bool {
    if depth == 0 {
        return true;
    }
    let theta_has_mesh = near
        .iter()
        .any(|&o| field.inside(offset(corner, o)) == mesh_inside);
    let mesh_has_theta = near
        .iter()
        .any(|&o| grid.inside(offset(corner, o)) == theta_inside);
    !(theta_has_mesh && mesh_has_theta)
}

/// A multiply crossed edge is shallow when every material between its crossings appears in Θ near
/// the edge. `windings` lists the winding before, between and after the crossings.
fn deep_edge(
    field: &Field,
    edge: &GridEdge,
    windings: &[i32],
    depth: u32,
    near: &[[i32; 3]],
) -> bool {
    if depth == 0 {
        return true;
    }
    let interior = &windings[1..windings.len() - 1];
    let ends = edge.ends();
    let present = |inside: bool| {
        ends.iter()
            .any(|&e| near.iter().any(|&o| field.inside(offset(e, o)) == inside))
    };
    let needs_inside = interior.contains(&1);
    let needs_outside = interior.contains(&0);
    (needs_inside && !present(true)) || (needs_outside && !present(false))
}

/// The crossings of one grid line grouped by the grid edge they lie on, each group with the mesh's
/// winding before, between and after its crossings.
fn edge_windings(
    crossings: &[GridCrossing],
) -> impl Iterator<Item = (&[GridCrossing], Vec<i32>)> + '_ {
    let mut winding = 0;
    crossings
        .chunk_by(|x, y| x.along() == y.along())
        .map(move |group| {
            let mut sequence = Vec::with_capacity(group.len() + 1);
            sequence.push(winding);
            for c in group {
                winding += c.sign();
                sequence.push(winding);
            }
            (group, sequence)
        })
}

/// Whether the mesh crosses `edge` (with `windings` before, between and after its crossings) as a
/// sheet thinner than a cell that Θ's own mesh has too: none of the crossings is an overlap, and
/// Θ's mesh crosses this edge, or one beside it (parallel, one step away), more than once.
fn shared_sheet(field: &Field, edge: &GridEdge, windings: &[i32]) -> bool {
    windings.len() > 2
        && windings.iter().all(|w| (0..=1).contains(w))
        && std::iter::once([0; 3])
            .chain(PARALLEL_EDGES)
            .any(|o| field.sheet_on(&GridEdge::new(offset(edge.corner, o), edge.axis())))
}

/// The cells around every grid edge that the mesh crosses as a sheet Θ's own mesh has too (see
/// `TopologyOptions::keep_shared_sheets`).
pub(crate) fn shared_sheet_cells(grid: &MeshGrid, field: &Field) -> FxHashSet<Cell> {
    let mut cells = FxHashSet::default();
    for l in 0..grid.crossings.index().len() {
        for (group, windings) in edge_windings(grid.crossings.of_line(l)) {
            let edge = GridEdge::new(group[0].corner, group[0].axis());
            if shared_sheet(field, &edge, &windings) {
                cells.extend(edge.cells());
            }
        }
    }
    cells
}

/// Cells of the vertices of every mesh component that crosses no grid edge.
fn sub_cell_components(grid: &MeshGrid) -> Vec<Cell> {
    let mesh: &IndexedMesh = grid.mesh;
    let n = mesh.positions.len();
    let mut components = Components::new(n, &mesh.triangles);
    let mut crossed = vec![false; n];
    for c in grid.crossings.all() {
        let root = components.find(mesh.triangles[c.triangle as usize][0]);
        crossed[root as usize] = true;
    }
    let mut cells: Vec<Cell> = (0..n as u32)
        .filter(|&v| !crossed[components.find(v) as usize])
        .map(|v| grid.vertex_cell(v))
        .collect();
    cells.sort_unstable();
    cells.dedup();
    cells
}

/// Both cells of every face the mesh meets that could not be a front face.
fn complex_faces(grid: &MeshGrid, field: &Field) -> Vec<Cell> {
    let mut faces: Vec<GridFace> = grid.pierced_faces().collect();
    faces.extend(
        grid.crossings
            .all()
            .iter()
            .flat_map(|c| GridEdge::new(c.corner, c.axis()).faces()),
    );
    faces.par_sort_unstable();
    faces.dedup();
    faces
        .par_iter()
        .filter(|face| {
            face_arcs(grid, face).is_none_or(|arcs| !pairs_follow_rule(field, face, &arcs))
        })
        .flat_map_iter(|face| face.cells())
        .collect()
}

/// Every cell within `k` cells (in each coordinate) of a seed, sorted.
pub(crate) fn dilate(seeds: &[Cell], k: u32) -> Vec<Cell> {
    let k = k as i32;
    let mut out: Vec<Cell> = seeds
        .par_iter()
        .flat_map_iter(|&c| {
            (-k..=k).flat_map(move |x| {
                (-k..=k).flat_map(move |y| (-k..=k).map(move |z| [c[0] + x, c[1] + y, c[2] + z]))
            })
        })
        .collect();
    out.par_sort_unstable();
    out.dedup();
    out
}
