//! Splitting one triangle along grid planes into convex pieces, exactly (thesis §3.4.6).
//!
//! A piece is a polygon of named [`Point`]s. Each split decides the side of every point from the
//! exact predicates the rasterizer uses and creates, where a side crosses the plane, the point whose
//! name says what it is: a mesh edge crossing the plane is a pierce point, a line of the triangle on
//! an earlier plane crossing it is the rasterizer's own crossing of the triangle with that grid line.
//! Neighbouring pieces, and the cells across the cut, therefore share points by name, never by a
//! rounded coordinate: the cut cannot leave a gap or a T-junction.

use super::keys::Cell;
use super::mesh_grid::MeshGrid;
use super::points::Point;
use super::segment::vertex_above;

/// What a polygon side runs along: side `k` of the triangle (from corner `k` to `k + 1`) or the
/// triangle's intersection with a grid plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Line {
    Side(u8),
    Plane(u8, i32),
}

/// A convex piece of a triangle: `lines[i]` runs from `points[i]` to `points[i + 1]`; `above[p]`
/// says on which side of the `p`-th splitting plane the piece lies.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Piece {
    pub points: Vec<Point>,
    pub lines: Vec<Line>,
    pub above: Vec<bool>,
}

/// Why a split could not be made: the predicates disagree with the rasterizer's crossings (never
/// expected; the caller treats the triangle as lying in the complex region).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Inconsistent;

/// Splits triangle `t` by every plane of `planes` (axis, index) in turn.
pub(crate) fn clip_triangle(
    grid: &MeshGrid,
    t: u32,
    planes: &[(u8, i32)],
) -> Result<Vec<Piece>, Inconsistent> {
    let tri = grid.mesh.triangles[t as usize];
    let mut pieces = vec![Piece {
        points: tri.map(Point::Vertex).to_vec(),
        lines: vec![Line::Side(0), Line::Side(1), Line::Side(2)],
        above: Vec::with_capacity(planes.len()),
    }];
    for &(axis, plane) in planes {
        let mut next = Vec::with_capacity(pieces.len() + 1);
        for piece in pieces {
            split(grid, t, piece, usize::from(axis), plane, &mut next)?;
        }
        pieces = next;
    }
    Ok(pieces)
}

/// Side of a point against plane `plane` of `axis`; points lying on the plane cannot occur, since
/// each plane splits once and every point made on a plane is made by that split.
fn above(grid: &MeshGrid, p: &Point, axis: usize, plane: i32) -> Result<bool, Inconsistent> {
    match *p {
        Point::Vertex(v) => Ok(vertex_above(
            &grid.lattice.points()[v as usize],
            axis,
            plane,
        )),
        Point::Pierce {
            edge,
            axis: a,
            plane: i,
        } => {
            let a = usize::from(a);
            if a == axis {
                if i == plane {
                    Err(Inconsistent)
                } else {
                    Ok(i > plane)
                }
            } else {
                Ok(grid.segment(edge).above((a, i), (axis, plane)))
            }
        }
        Point::Crossing { edge, .. } => {
            if edge.axis() == axis {
                Ok(edge.corner[axis] >= plane)
            } else if edge.corner[axis] == plane {
                Err(Inconsistent)
            } else {
                Ok(edge.corner[axis] > plane)
            }
        }
        Point::Level(_) | Point::Centre { .. } => Err(Inconsistent),
    }
}

/// The point where `line` of triangle `t` crosses plane `plane` of `axis`.
fn intersection(
    grid: &MeshGrid,
    t: u32,
    line: Line,
    axis: usize,
    plane: i32,
) -> Result<Point, Inconsistent> {
    match line {
        Line::Side(k) => Ok(Point::Pierce {
            edge: grid.edges().of_triangle[t as usize][usize::from(k)],
            axis: axis as u8,
            plane,
        }),
        Line::Plane(a, i) => {
            let a = usize::from(a);
            let along = 3 - a - axis;
            grid.triangle_line_crossing(t, along, [(a, i), (axis, plane)])
                .map(|edge| Point::Crossing { triangle: t, edge })
                .ok_or(Inconsistent)
        }
    }
}

fn split(
    grid: &MeshGrid,
    t: u32,
    piece: Piece,
    axis: usize,
    plane: i32,
    out: &mut Vec<Piece>,
) -> Result<(), Inconsistent> {
    let sides = piece
        .points
        .iter()
        .map(|p| above(grid, p, axis, plane))
        .collect::<Result<Vec<bool>, _>>()?;
    if sides.iter().all(|&s| s == sides[0]) {
        let mut piece = piece;
        piece.above.push(sides[0]);
        out.push(piece);
        return Ok(());
    }
    let mut parts: [(Vec<Point>, Vec<Line>); 2] = Default::default();
    let n = piece.points.len();
    for i in 0..n {
        let (p, line) = (piece.points[i], piece.lines[i]);
        let (sp, sq) = (sides[i], sides[(i + 1) % n]);
        let here = usize::from(sp);
        parts[here].0.push(p);
        parts[here].1.push(line);
        if sp != sq {
            let x = intersection(grid, t, line, axis, plane)?;
            parts[here].0.push(x);
            parts[here].1.push(Line::Plane(axis as u8, plane));
            let there = usize::from(sq);
            parts[there].0.push(x);
            parts[there].1.push(line);
        }
    }
    for (side, (points, lines)) in parts.into_iter().enumerate() {
        if points.len() < 3 {
            return Err(Inconsistent);
        }
        let mut above = piece.above.clone();
        above.push(side == 1);
        out.push(Piece {
            points,
            lines,
            above,
        });
    }
    Ok(())
}

/// A cell the piece lies in (every cell it meets is on the same side of every splitting plane, so
/// any of them decides whether the piece is in the complex region), read at its first point.
pub(crate) fn piece_cell(
    grid: &MeshGrid,
    piece: &Piece,
    planes: &[(u8, i32)],
) -> Result<Cell, Inconsistent> {
    let side_of = |axis: usize, plane: i32| {
        planes
            .iter()
            .position(|&(a, i)| usize::from(a) == axis && i == plane)
            .map(|p| piece.above[p])
            .ok_or(Inconsistent)
    };
    match piece.points[0] {
        Point::Vertex(v) => Ok(grid.vertex_cell(v)),
        Point::Pierce { edge, axis, plane } => {
            let axis = usize::from(axis);
            let mut cell = grid.segment(edge).face(axis, plane);
            if !side_of(axis, plane)? {
                cell[axis] -= 1;
            }
            Ok(cell)
        }
        Point::Crossing { edge, .. } => {
            let mut cell = edge.corner;
            for b in (0..3).filter(|&b| b != edge.axis()) {
                if !side_of(b, edge.corner[b])? {
                    cell[b] -= 1;
                }
            }
            Ok(cell)
        }
        Point::Level(_) | Point::Centre { .. } => Err(Inconsistent),
    }
}
