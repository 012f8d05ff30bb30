//! Filling the complex region with Θ's isosurface and stitching it to the cut (paper §4.3, thesis
//! §3.4.7).
//!
//! Each complex cell's surface is bounded by closed loops on the cell's faces. On a front face the
//! loop follows the mesh's own arcs, through its cut points, so the fill meets the kept surface
//! point for point; on a face between two complex cells it follows the marching-cubes face rule on
//! Θ's signs, decided once for the face, so both cells agree (the hole of thesis §3.4.7 cannot
//! occur). Crossings of Θ are vertices on inner grid edges; on front edges the mesh's crossing is
//! used instead. Loops made only of edge crossings that are exactly the case table's loops take the
//! case table's triangles; any other loop is fanned from a centre vertex placed on Θ's zero set
//! inside the cell (one centre per loop, so two sheets in a cell are never pinched together).
//! Segments run as the face rule directs, so every fill triangle faces outward.

use rustc_hash::FxHashSet;

use super::field::Field;
use super::keys::{Cell, cell_corner, cell_edge, cell_face, cell_neighbour};
use super::mesh_grid::MeshGrid;
use super::points::Point;
use super::region::Checks;
use crate::grid::cases::cell_case;
use crate::grid::cube::{FACE_CORNERS, FACE_EDGES, face_segments};

/// The fill of the region: its triangles, and the loop around each centre vertex.
#[derive(Debug, Clone, Default)]
pub(crate) struct Fill {
    pub triangles: Vec<[Point; 3]>,
    pub centres: Vec<(Point, Vec<Point>)>,
}

/// The fill of every cell of `cells` (the region, sorted). Fails with a cell whose loops do not
/// close (never expected once the region has grown).
pub(crate) fn fill(
    grid: &MeshGrid,
    field: &Field,
    region: &FxHashSet<Cell>,
    cells: &[Cell],
    checks: &mut Checks,
) -> Result<Fill, Cell> {
    let mut out = Fill::default();
    for &cell in cells {
        fill_cell(grid, field, region, cell, checks, &mut out).ok_or(cell)?;
    }
    Ok(out)
}

fn fill_cell(
    grid: &MeshGrid,
    field: &Field,
    region: &FxHashSet<Cell>,
    cell: Cell,
    checks: &mut Checks,
    out: &mut Fill,
) -> Option<()> {
    let config = field.config(cell);
    if config == 0 || config == 255 {
        return Some(());
    }
    let edge_point = |e: usize| -> Option<Point> {
        let edge = cell_edge(cell, e);
        if edge.cells().iter().all(|c| region.contains(c)) {
            return Some(Point::Level(edge));
        }
        match grid.on_edge(edge) {
            [c] => Some(Point::Crossing {
                triangle: c.triangle,
                edge,
            }),
            _ => None,
        }
    };
    let mut links: Vec<(Point, Point)> = Vec::new();
    for f in 0..6 {
        let inside = FACE_CORNERS[f].map(|c| field.inside(cell_corner(cell, c)));
        let segments = face_segments(inside);
        if region.contains(&cell_neighbour(cell, f)) {
            for s in segments.as_slice() {
                links.push((
                    edge_point(FACE_EDGES[f][s.from])?,
                    edge_point(FACE_EDGES[f][s.to])?,
                ));
            }
            continue;
        }
        let arcs = checks.face(cell_face(cell, f))?;
        for s in segments.as_slice() {
            let from = cell_edge(cell, FACE_EDGES[f][s.from]);
            let to = cell_edge(cell, FACE_EDGES[f][s.to]);
            let arc = arcs
                .iter()
                .find(|a| a.ends == [from, to] || a.ends == [to, from])?;
            let forward = arc.ends[0] == from;
            let n = arc.points.len();
            for i in 0..n - 1 {
                links.push(if forward {
                    (arc.points[i], arc.points[i + 1])
                } else {
                    (arc.points[n - 1 - i], arc.points[n - 2 - i])
                });
            }
        }
    }
    links.sort_unstable();
    if links.windows(2).any(|w| w[0].0 == w[1].0) {
        return None;
    }
    let mut targets: Vec<Point> = links.iter().map(|l| l.1).collect();
    targets.sort_unstable();
    if targets.windows(2).any(|w| w[0] == w[1]) {
        return None;
    }
    let next = |p: &Point| -> Option<Point> {
        links
            .binary_search_by(|l| l.0.cmp(p))
            .ok()
            .map(|i| links[i].1)
    };
    let case = cell_case(config);
    let follows_case = links.len() == case.loops.iter().map(Vec::len).sum::<usize>()
        && case.loops.iter().all(|l| {
            (0..l.len()).all(|i| {
                let a = edge_point(usize::from(l[i]));
                let b = edge_point(usize::from(l[(i + 1) % l.len()]));
                a.is_some() && a.and_then(|a| next(&a)) == b
            })
        });
    if follows_case {
        for t in &case.triangles {
            let mut tri = [Point::Vertex(0); 3];
            for k in 0..3 {
                tri[k] = edge_point(usize::from(t[k]))?;
            }
            out.triangles.push(tri);
        }
        return Some(());
    }
    let mut seen: FxHashSet<Point> = FxHashSet::default();
    let mut index = 0u8;
    for &(start, _) in &links {
        if seen.contains(&start) {
            continue;
        }
        let mut cycle = vec![start];
        seen.insert(start);
        let mut at = next(&start)?;
        while at != start {
            if !seen.insert(at) {
                return None;
            }
            cycle.push(at);
            at = next(&at)?;
        }
        if cycle.len() < 3 {
            return None;
        }
        if cycle.len() == 3 {
            out.triangles.push([cycle[0], cycle[1], cycle[2]]);
        } else {
            let centre = Point::Centre { cell, index };
            index += 1;
            let n = cycle.len();
            for i in 0..n {
                out.triangles.push([cycle[i], cycle[(i + 1) % n], centre]);
            }
            out.centres.push((centre, cycle));
        }
    }
    Some(())
}
