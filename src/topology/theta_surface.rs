//! Θ's isosurface as `ConstrainTopology` reads it: the cells it crosses, its connectivity, its
//! topology, and, to compare components, its vertices placed on Θ's zero set.
//!
//! All of it depends on Θ alone. For Φ(T) that is the target frame alone, so the tracker extracts
//! it while registration runs on the other core (dam-break frames 20–31: 3 ms for the
//! connectivity and topology, 9 ms for the placed comparison, a Φ(T) call each frame).

use std::sync::OnceLock;

use super::field::Field;
use super::isosurface::{isosurface, signature};
use super::keys::{Cell, GridEdge};
use super::mismatch::Isosurface;
use crate::mesh::IndexedMesh;

/// Θ's isosurface, extracted once for every attempt of a `ConstrainTopology` call on Θ.
pub struct ThetaSurface {
    /// The cells Θ's zero set crosses, with their corner configurations.
    pub(crate) cells: Vec<(Cell, u8)>,
    /// Its connectivity, one vertex on each grid edge of `edges` (unplaced).
    pub(crate) mesh: IndexedMesh,
    pub(crate) edges: Vec<GridEdge>,
    /// The components' Euler characteristics the result must have.
    pub(crate) signature: Vec<i64>,
    /// The components placed on Θ's zero set, for comparing a result's with them: built on first
    /// use, since most calls never compare.
    compared: OnceLock<Isosurface>,
}

impl ThetaSurface {
    /// Θ's isosurface, its topology not yet compared.
    pub fn of(theta: &Field) -> Self {
        let cells = theta.surface();
        let (mesh, edges) = isosurface(theta, &cells);
        let signature = signature(&mesh);
        Self {
            cells,
            mesh,
            edges,
            signature,
            compared: OnceLock::new(),
        }
    }

    /// Θ's isosurface ready to compare components with, `theta` being the field it came from.
    pub(crate) fn compared(&self, theta: &Field) -> &Isosurface {
        self.compared
            .get_or_init(|| Isosurface::of_field(theta, &self.mesh, &self.edges))
    }

    /// [`ThetaSurface::of`], its components placed for comparing as well.
    pub fn compared_of(theta: &Field) -> Self {
        let surface = Self::of(theta);
        surface.compared(theta);
        surface
    }
}
