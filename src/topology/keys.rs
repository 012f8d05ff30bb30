//! Names for the grid's cells, faces, edges and corners, and the neighbourhoods between them, in the
//! numbering of [`crate::grid::cube`] so cell-local tables (face rule, case table) read them directly.

use crate::grid::cross_axes;
use crate::grid::cube::{CORNER_OFFSETS, EDGE_CORNERS};

/// A cell, named by its lowest corner.
pub(crate) type Cell = [i32; 3];

/// A grid corner.
pub(crate) type Corner = [i32; 3];

/// Offsets to the six grid edges parallel to one and a step away from it (along any axis; along
/// the edge's own axis that is the next edge on its line).
pub(crate) const PARALLEL_EDGES: [[i32; 3]; 6] = [
    [1, 0, 0],
    [-1, 0, 0],
    [0, 1, 0],
    [0, -1, 0],
    [0, 0, 1],
    [0, 0, -1],
];

/// The offsets of a cell's 26 neighbours (and itself).
pub(crate) const NEIGHBOURS: [[i32; 3]; 27] = {
    let mut out = [[0; 3]; 27];
    let mut i = 0;
    while i < 27 {
        out[i] = [i as i32 % 3 - 1, (i as i32 / 3) % 3 - 1, i as i32 / 9 - 1];
        i += 1;
    }
    out
};

/// `p + unit(axis) * k`.
pub(crate) fn step(p: [i32; 3], axis: usize, k: i32) -> [i32; 3] {
    let mut q = p;
    q[axis] += k;
    q
}

/// The grid edge from `corner` to `corner + unit(axis)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct GridEdge {
    pub corner: Corner,
    pub axis: u8,
}

impl GridEdge {
    pub fn new(corner: Corner, axis: usize) -> Self {
        Self {
            corner,
            axis: axis as u8,
        }
    }

    pub fn axis(&self) -> usize {
        usize::from(self.axis)
    }

    /// Lower and upper corner.
    pub fn ends(&self) -> [Corner; 2] {
        [self.corner, step(self.corner, self.axis(), 1)]
    }

    /// The four cells around the edge.
    pub fn cells(&self) -> [Cell; 4] {
        let (u, v) = cross_axes(self.axis());
        let c = self.corner;
        [
            step(step(c, u, -1), v, -1),
            step(c, v, -1),
            step(c, u, -1),
            c,
        ]
    }

    /// The four faces that share the edge.
    pub fn faces(&self) -> [GridFace; 4] {
        let (u, v) = cross_axes(self.axis());
        let c = self.corner;
        [
            GridFace::new(c, u),
            GridFace::new(step(c, v, -1), u),
            GridFace::new(c, v),
            GridFace::new(step(c, u, -1), v),
        ]
    }
}

/// The face of the grid on plane `cell[axis]` spanning `cell`'s extent along the two other axes: the
/// lower `axis` face of `cell`, the upper one of `cell - unit(axis)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct GridFace {
    pub cell: Cell,
    pub axis: u8,
}

impl GridFace {
    pub fn new(cell: Cell, axis: usize) -> Self {
        Self {
            cell,
            axis: axis as u8,
        }
    }

    pub fn axis(&self) -> usize {
        usize::from(self.axis)
    }

    /// Index of the face's plane along its axis.
    pub fn plane(&self) -> i32 {
        self.cell[self.axis()]
    }

    /// The cell below the face (along its axis) and the cell above it.
    pub fn cells(&self) -> [Cell; 2] {
        [step(self.cell, self.axis(), -1), self.cell]
    }

    /// The four edges bounding the face.
    pub fn edges(&self) -> [GridEdge; 4] {
        let (u, v) = cross_axes(self.axis());
        let c = self.cell;
        [
            GridEdge::new(c, u),
            GridEdge::new(step(c, u, 1), v),
            GridEdge::new(step(c, v, 1), u),
            GridEdge::new(c, v),
        ]
    }
}

/// Corner `c` (0..8) of `cell` in cube numbering.
pub(crate) fn cell_corner(cell: Cell, c: usize) -> Corner {
    std::array::from_fn(|a| cell[a] + CORNER_OFFSETS[c][a] as i32)
}

/// Edge `e` (0..12) of `cell` in cube numbering.
pub(crate) fn cell_edge(cell: Cell, e: usize) -> GridEdge {
    GridEdge::new(cell_corner(cell, EDGE_CORNERS[e][0]), e / 4)
}

/// Face `f` (0..6) of `cell` in cube numbering (−x, +x, −y, +y, −z, +z).
pub(crate) fn cell_face(cell: Cell, f: usize) -> GridFace {
    let axis = f / 2;
    GridFace::new(step(cell, axis, (f % 2) as i32), axis)
}

/// The cell across face `f` (0..6) of `cell`.
pub(crate) fn cell_neighbour(cell: Cell, f: usize) -> Cell {
    step(cell, f / 2, if f.is_multiple_of(2) { -1 } else { 1 })
}

/// The eight cells sharing `corner`.
pub(crate) fn corner_cells(corner: Corner) -> [Cell; 8] {
    std::array::from_fn(|c| cell_corner(corner, c).map(|x| x - 1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::cube::FACE_EDGES;

    #[test]
    fn edges_faces_and_cells_agree() {
        let cell = [3, -2, 5];
        for e in 0..12 {
            let edge = cell_edge(cell, e);
            assert!(edge.cells().contains(&cell), "edge {e}");
            let faces_of_cell: Vec<GridFace> = (0..6).map(|f| cell_face(cell, f)).collect();
            let shared = edge
                .faces()
                .iter()
                .filter(|f| faces_of_cell.contains(f))
                .count();
            assert_eq!(shared, 2, "edge {e} lies on two faces of its cell");
            for f in edge.faces() {
                assert!(f.edges().contains(&edge));
                assert!(f.cells().iter().all(|c| edge.cells().contains(c)));
            }
        }
        for (f, edges) in FACE_EDGES.iter().enumerate() {
            let face = cell_face(cell, f);
            assert!(face.cells().contains(&cell));
            assert!(face.cells().contains(&cell_neighbour(cell, f)));
            let mut mine: Vec<GridEdge> = edges.iter().map(|&e| cell_edge(cell, e)).collect();
            let mut theirs = face.edges().to_vec();
            mine.sort();
            theirs.sort();
            assert_eq!(mine, theirs, "face {f}");
        }
        let cells = corner_cells([0, 0, 0]);
        assert!(cells.contains(&[-1, -1, -1]) && cells.contains(&[0, 0, 0]));
    }
}
