//! Cutting the mesh along the boundary of the complex region (paper §4.3, thesis §3.4.5–3.4.6),
//! keeping what lies outside it.
//!
//! A triangle that meets a front face is split along the planes of the front faces it meets (and,
//! through each front edge it crosses, both planes of that edge, so the edge's crossing becomes a
//! vertex); each piece lies entirely inside or entirely outside the region, and the outside pieces
//! are kept. Where a split triangle's side is shared with a triangle that is not split, the points
//! on that side are inserted into the neighbour too. Every kept polygon is then triangulated without
//! new vertices ([`super::triangulate`]), so the cut leaves no T-junction, and the kept surface ends
//! exactly at the front faces' arcs, where the fill begins.

use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

use super::clip::{Line, Piece, clip_triangle, piece_cell};
use super::face_arcs::Arc;
use super::keys::{Cell, GridFace};
use super::mesh_grid::MeshGrid;
use super::points::Point;

/// A kept polygon of triangle `triangle`, with `lines[i]` the mask of the triangle's sides point
/// `i` lies on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Polygon {
    pub triangle: u32,
    pub points: Vec<Point>,
    pub lines: Vec<u8>,
}

/// The kept part of the mesh.
#[derive(Debug, Clone, Default)]
pub(crate) struct Cut {
    /// Triangles kept as they are.
    pub untouched: Vec<u32>,
    /// Kept polygons still to be triangulated, in triangle order.
    pub polygons: Vec<Polygon>,
    /// The planes at which each split mesh edge is cut, in order from its first vertex.
    pub splits: FxHashMap<u32, Vec<(u8, i32)>>,
}

/// What is kept of one triangle: the triangle itself, or polygons of it.
type Kept = (Option<u32>, Vec<Polygon>);

/// The cut for `region`, given its front faces and their arcs. Fails with the triangle whose split
/// contradicts the rasterizer's crossings.
pub(crate) fn cut(
    grid: &MeshGrid,
    region: &FxHashSet<Cell>,
    fronts: &[(GridFace, std::rc::Rc<Vec<Arc>>)],
) -> Result<Cut, u32> {
    let mut planes: Vec<(u32, u8, i32)> = Vec::new();
    for (face, arcs) in fronts {
        for arc in arcs.iter() {
            for &t in &arc.triangles {
                planes.push((t, face.axis, face.plane()));
            }
            for p in [arc.points[0], arc.points[arc.points.len() - 1]] {
                if let Point::Crossing { triangle, edge } = p {
                    for b in (0..3).filter(|&b| b != edge.axis()) {
                        planes.push((triangle, b as u8, edge.corner[b]));
                    }
                }
            }
        }
    }
    planes.sort_unstable();
    planes.dedup();
    let mut by_triangle: FxHashMap<u32, Vec<(u8, i32)>> = FxHashMap::default();
    for &(t, a, i) in &planes {
        by_triangle.entry(t).or_default().push((a, i));
    }
    let mut split: Vec<(u32, u8, i32)> = Vec::new();
    for (&t, ps) in &by_triangle {
        for e in grid.edges().of_triangle[t as usize] {
            let seg = &grid.segment(e);
            split.extend(
                ps.iter()
                    .filter(|&&(a, i)| seg.crosses(usize::from(a), i))
                    .map(|&(a, i)| (e, a, i)),
            );
        }
    }
    split.par_sort_unstable();
    split.dedup();
    let mut splits: FxHashMap<u32, Vec<(u8, i32)>> = FxHashMap::default();
    for group in split.chunk_by(|x, y| x.0 == y.0) {
        let e = group[0].0;
        let ordered = grid
            .pierces(e)
            .iter()
            .filter(|p| group.iter().any(|&(_, a, i)| (a, i) == (p.axis, p.plane)))
            .map(|p| (p.axis, p.plane))
            .collect();
        splits.insert(e, ordered);
    }
    let triangles = grid.mesh.triangles.len() as u32;
    let results: Vec<Result<Kept, u32>> = (0..triangles)
        .into_par_iter()
        .with_min_len(256)
        .map(|t| match by_triangle.get(&t) {
            Some(ps) => split_triangle(grid, region, &splits, t, ps).map(|p| (None, p)),
            None => keep_or_remove(grid, region, &splits, t),
        })
        .collect();
    let mut out = Cut {
        splits,
        ..Cut::default()
    };
    for r in results {
        let (untouched, polygons) = r?;
        out.untouched.extend(untouched);
        out.polygons.extend(polygons);
    }
    Ok(out)
}

/// A triangle that meets no front face lies wholly inside or wholly outside the region; kept, it
/// takes the points its split neighbours put on its sides.
fn keep_or_remove(
    grid: &MeshGrid,
    region: &FxHashSet<Cell>,
    splits: &FxHashMap<u32, Vec<(u8, i32)>>,
    t: u32,
) -> Result<Kept, u32> {
    let tri = grid.mesh.triangles[t as usize];
    if region.contains(&grid.vertex_cell(tri[0])) {
        return Ok((None, Vec::new()));
    }
    let edges = grid.edges().of_triangle[t as usize];
    if edges.iter().all(|e| !splits.contains_key(e)) {
        return Ok((Some(t), Vec::new()));
    }
    let mut points = Vec::new();
    for k in 0..3 {
        let (from, to) = (Point::Vertex(tri[k]), Point::Vertex(tri[(k + 1) % 3]));
        points.push(from);
        points.extend(side_points(grid, splits, edges[k], &from, &to).ok_or(t)?);
    }
    Ok((None, vec![polygon(grid, t, points)]))
}

fn split_triangle(
    grid: &MeshGrid,
    region: &FxHashSet<Cell>,
    splits: &FxHashMap<u32, Vec<(u8, i32)>>,
    t: u32,
    planes: &[(u8, i32)],
) -> Result<Vec<Polygon>, u32> {
    let pieces = clip_triangle(grid, t, planes).map_err(|_| t)?;
    let mut kept = Vec::new();
    for piece in pieces {
        let cell = piece_cell(grid, &piece, planes).map_err(|_| t)?;
        if !region.contains(&cell) {
            kept.push(polygon(
                grid,
                t,
                with_side_points(grid, splits, t, &piece).ok_or(t)?,
            ));
        }
    }
    Ok(kept)
}

/// The piece's points with the split points of the triangle's sides inserted along them.
fn with_side_points(
    grid: &MeshGrid,
    splits: &FxHashMap<u32, Vec<(u8, i32)>>,
    t: u32,
    piece: &Piece,
) -> Option<Vec<Point>> {
    let n = piece.points.len();
    let mut points = Vec::with_capacity(n);
    for i in 0..n {
        let (from, to) = (piece.points[i], piece.points[(i + 1) % n]);
        points.push(from);
        if let Line::Side(k) = piece.lines[i] {
            let e = grid.edges().of_triangle[t as usize][usize::from(k)];
            points.extend(side_points(grid, splits, e, &from, &to)?);
        }
    }
    Some(points)
}

/// Split points of mesh edge `e` strictly between `from` and `to` (both on `e`), in that direction.
fn side_points(
    grid: &MeshGrid,
    splits: &FxHashMap<u32, Vec<(u8, i32)>>,
    e: u32,
    from: &Point,
    to: &Point,
) -> Option<Vec<Point>> {
    let Some(list) = splits.get(&e) else {
        return Some(Vec::new());
    };
    let [v0, v1] = grid.edges().verts[e as usize];
    let position = |p: &Point| -> Option<i64> {
        match *p {
            Point::Vertex(v) if v == v0 => Some(-1),
            Point::Vertex(v) if v == v1 => Some(list.len() as i64),
            Point::Pierce { edge, axis, plane } if edge == e => list
                .iter()
                .position(|&q| q == (axis, plane))
                .map(|i| i as i64),
            _ => None,
        }
    };
    let (a, b) = (position(from)?, position(to)?);
    let make = |i: i64| {
        let (axis, plane) = list[i as usize];
        Point::Pierce {
            edge: e,
            axis,
            plane,
        }
    };
    Some(if a < b {
        (a + 1..b).map(make).collect()
    } else {
        (b + 1..a).rev().map(make).collect()
    })
}

fn polygon(grid: &MeshGrid, t: u32, points: Vec<Point>) -> Polygon {
    let tri = grid.mesh.triangles[t as usize];
    let edges = grid.edges().of_triangle[t as usize];
    let lines = points
        .iter()
        .map(|p| match *p {
            Point::Vertex(v) => (0..3)
                .filter(|&k| tri[k] == v || tri[(k + 1) % 3] == v)
                .fold(0u8, |m, k| m | (1 << k)),
            Point::Pierce { edge, .. } => (0..3)
                .filter(|&k| edges[k] == edge)
                .fold(0u8, |m, k| m | (1 << k)),
            _ => 0,
        })
        .collect();
    Polygon {
        triangle: t,
        points,
        lines,
    }
}
