//! The points the new surface is made of, named by how they arise rather than by position, so the
//! cut, the fill and the neighbouring cells refer to one point by one name (thesis §3.4.6: "decide
//! once"), and positions are computed once, afterwards.

use super::keys::{Cell, GridEdge};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum Point {
    /// A vertex of the input mesh.
    Vertex(u32),
    /// Where mesh edge `edge` pierces plane `plane` of `axis` (a "type 2" cut vertex, thesis §3.4.5).
    Pierce { edge: u32, axis: u8, plane: i32 },
    /// Where triangle `triangle` crosses grid edge `edge` (a "type 1" cut vertex).
    Crossing { triangle: u32, edge: GridEdge },
    /// Where Θ's zero set crosses a grid edge inside the complex region.
    Level(GridEdge),
    /// The centre of loop `index` of a filled cell.
    Centre { cell: Cell, index: u8 },
}

impl Point {
    /// A point of the fill: on Θ's surface, strictly inside the complex region.
    pub fn is_fill(&self) -> bool {
        matches!(self, Point::Level(_) | Point::Centre { .. })
    }
}
