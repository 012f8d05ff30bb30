//! Mirror of `kernels/shared/lattice.wgsl`: a point of the grid's fixed lattice, and the limits of
//! the lattice that the exact predicates on both backends rely on.

use glam::Vec3;

/// Fractional bits of a lattice coordinate: a cell is `2^FRACTION_BITS` lattice units wide.
pub const FRACTION_BITS: u32 = 20;

/// Lattice units per cell.
pub const CELL_UNITS: i64 = 1 << FRACTION_BITS;

/// Largest extent of one triangle along any axis, in cells. Within one triangle the predicates work
/// on offsets from the triangle's lowest cell, which then fit in 31 bits: products of two offsets
/// fit in `i64` and the orientation of a corner against the triangle's plane fits in `i128`.
pub const MAX_TRIANGLE_SPAN: i64 = (1i64 << (31 - FRACTION_BITS)) - 1;

/// Largest cell index in absolute value. Cell indices and their differences are then exact in f32,
/// which the distance computation relies on, and a cell one step beyond any vertex's still packs
/// into 21 bits per axis (`grid::cell_key`).
pub const MAX_CELL_INDEX: i32 = (1 << 20) - 2;

gpu_struct! {
    mirrors LATTICE;
    /// A point of the fixed lattice: cell index (floor of the grid coordinate) and fraction within the
    /// cell in units of `2^-FRACTION_BITS` (always below `CELL_UNITS`).
    ///
    /// The cell is the one the point lies in under the grid's symbolic perturbation (the mesh shifted by
    /// `(ε, ε², ε³)`, see `grid/predicates.rs`): a point exactly on the plane `x = i` belongs to cell `i`,
    /// as `floor` says. Mirrors `struct LatticePoint` in `kernels/shared/lattice.wgsl`.
    #[derive(Eq, Hash, PartialOrd, Ord)]
    pub struct LatticePoint {
        pub cell: [i32; 3],
        pub frac: [u32; 3],
    }
}

impl LatticePoint {
    /// Coordinate along `axis` in lattice units.
    pub fn units(&self, axis: usize) -> i64 {
        i64::from(self.cell[axis]) * CELL_UNITS + i64::from(self.frac[axis])
    }

    /// Offset from the corner `corner`, in cells, rounded once to f32 (the same operations as the
    /// distance kernel, so both read identical bits).
    pub fn offset_from(&self, corner: [i32; 3]) -> Vec3 {
        let scale = 1.0 / CELL_UNITS as f32;
        Vec3::from_array(std::array::from_fn(|a| {
            (self.cell[a] - corner[a]) as f32 + self.frac[a] as f32 * scale
        }))
    }
}
