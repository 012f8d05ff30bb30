//! `Φ(S)`: the grid module's narrow-band signed distance to a closed mesh (exact point-to-triangle
//! distances, sign from the sweep windings: inside where the winding is at least 1, so an
//! overlapping or inverted mesh gets the outer envelope of its inside, which is what
//! `ConstrainTopology(M, Φ(M))` merges to), and beyond the band the windings' sign.

use rustc_hash::FxHashMap;

use super::TopologyError;
use super::field::Field;
use crate::compute::Backend;
use crate::grid::{
    GridFrame, LatticeMesh, NarrowBand, Windings, edge_faces, footprint, rasterize,
    signed_distance, sweep,
};
use crate::mesh::IndexedMesh;

/// Half-width of the band `Φ` stores, in cells: both ends of every grid edge the surface crosses
/// get a true distance, which is all the crossings' positions need; farther corners need a sign
/// only.
pub const PHI_HALF_WIDTH: f32 = 1.0;

impl Field {
    /// `Φ(mesh)` on the grid `frame` (see the module docs), rasterized, swept and measured on
    /// `backend`.
    pub fn signed_distance(
        backend: &Backend,
        frame: GridFrame,
        mesh: &IndexedMesh,
    ) -> Result<Self, TopologyError> {
        let lattice = LatticeMesh::new(frame, mesh)?;
        let crossings = rasterize(backend, &lattice)?;
        let windings = sweep(backend, &crossings)?;
        let cells = footprint(&lattice, &crossings, &edge_faces(&lattice));
        let band = signed_distance(backend, &lattice, &cells, &windings, PHI_HALF_WIDTH)?;
        Ok(Field::from_narrow_band(frame, &band, windings).with_sheets(crossings.all()))
    }

    /// Θ from a narrow band of signed distances (world units) and, beyond it, the inside/outside
    /// classification of `windings` (inside where the winding along x is at least 1) at the band's
    /// half-width.
    pub fn from_narrow_band(frame: GridFrame, band: &NarrowBand, windings: Windings) -> Self {
        let near: FxHashMap<[i32; 3], f32> = band
            .corners()
            .iter()
            .copied()
            .zip(band.values().iter().copied())
            .collect();
        let far = band.half_width().max(1.0) * frame.spacing();
        Field::from_band(frame, near, windings, far)
    }
}
