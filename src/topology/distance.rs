//! `Φ(S)`: the grid module's narrow-band signed distance to a closed mesh (exact point-to-triangle
//! distances, sign from the sweep windings: inside where the winding is at least 1, so an
//! overlapping or inverted mesh gets the outer envelope of its inside, which is what
//! `ConstrainTopology(M, Φ(M))` merges to), and beyond the band the windings' sign.

use rustc_hash::FxHashMap;

use super::TopologyError;
use super::field::Field;
use super::mesh_grid::MeshRaster;
use crate::compute::Backend;
use crate::grid::{GridFrame, NarrowBand, Windings, edge_faces, footprint, signed_distance};
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
        Self::of_raster(backend, &MeshRaster::new(backend, frame, mesh)?)
    }

    /// `Φ` of the mesh rasterized as `raster`, measured on `backend`.
    pub fn of_raster(backend: &Backend, raster: &MeshRaster) -> Result<Self, TopologyError> {
        let lattice = &raster.lattice;
        let cells = footprint(lattice, &raster.crossings, &edge_faces(lattice));
        let band = signed_distance(backend, lattice, &cells, &raster.windings, PHI_HALF_WIDTH)?;
        Ok(
            Field::from_narrow_band(*lattice.frame(), &band, raster.windings.clone())
                .with_sheets(raster.crossings.all()),
        )
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
