// A point of the grid's fixed lattice: cell index and fraction in units of 2^-20 cell. Mirrored by
// `surftrack::kernels::shared::LatticePoint` (src/kernels/shared/lattice.rs); a test compares the two layouts.
// Members are arrays of scalars (4-byte aligned), so the host uploads `[LatticePoint]` as it is.
struct LatticePoint {
    cell: array<i32, 3>,
    frac: array<u32, 3>,
}

// Fractional bits of a lattice coordinate (`FRACTION_BITS` in src/kernels/shared/lattice.rs).
const FRACTION_BITS: u32 = 20u;
