use std::time::Duration;

/// How the surface was replaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Resampling {
    /// The mesh already had Θ's topology with no deep difference: nothing changed.
    #[default]
    None,
    /// Cells around the differences were re-sampled; `attempt` counts from 0 (the classification
    /// with the configured depth), later attempts being stricter or wider.
    Local { attempt: usize },
    /// Every local attempt failed and the whole surface was replaced by Θ's isosurface.
    Whole,
}

/// What one call of `constrain_topology` did.
#[derive(Debug, Clone, Default)]
pub struct TopologyReport {
    pub resampling: Resampling,
    /// Cells seeding the complex region, and cells of the region after growth (last attempt; every
    /// cell of Θ's surface when the whole surface was replaced).
    pub seed_cells: usize,
    pub region_cells: usize,
    /// The complex region of a local re-sampling, sorted (empty otherwise). Input vertices in other
    /// cells keep their ids and positions; an input triangle is kept as it was unless it, or a
    /// triangle sharing a side with it, meets a cell of the region (the cut inserts its points on
    /// both triangles of a side it splits).
    pub region: Vec<[i32; 3]>,
    /// Input vertices kept (same id and position), removed, and new vertices on the cut and in
    /// the fill.
    pub kept: usize,
    pub deleted: usize,
    pub cut: usize,
    pub patch: usize,
    /// Ids of the input vertices a patch vertex standing on them continued
    /// (`TopologyOptions::continue_within`), sorted: counted in `deleted` as the surgery removed
    /// them, yet their ids go on.
    pub continued: Vec<u64>,
    /// Euler characteristic of each component of the result, sorted (equal to Θ's isosurface).
    pub euler: Vec<i64>,
    /// Why each earlier attempt was abandoned, in order.
    pub abandoned: Vec<Abandoned>,
    /// Time spent classifying and growing the region (over all attempts); cutting, filling,
    /// assembling, recording and verifying (over all attempts); and in the whole call.
    pub classify: Duration,
    pub rebuild: Duration,
    pub total: Duration,
}

impl TopologyReport {
    /// Whether the mesh was changed.
    pub fn changed(&self) -> bool {
        self.resampling != Resampling::None
    }

    /// Fraction of the input's vertices that were removed.
    pub fn replaced_fraction(&self) -> f64 {
        let input = self.kept + self.deleted;
        if input == 0 {
            0.0
        } else {
            self.deleted as f64 / input as f64
        }
    }
}

/// Why one local attempt of `constrain_topology` was abandoned; the next attempt is stricter
/// (a topology failure) or takes in the cells named (a local failure).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Abandoned {
    /// The topology differs from Θ's, but no cell differs deeply enough to re-sample.
    NoDeepDifference,
    /// A triangle could not be cut, or a cell's fill triangulated, in these cells.
    CutOrFill { cells: Vec<[i32; 3]> },
    /// The re-sampled surface is valid but has a topology other than Θ's.
    Topology,
    /// The re-sampled surface is not closed, manifold or non-degenerate in these cells.
    InvalidElement { cells: Vec<[i32; 3]> },
}

impl std::fmt::Display for Abandoned {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Abandoned::NoDeepDifference => {
                write!(f, "topology differs from Θ's with no deep difference")
            }
            Abandoned::CutOrFill { cells } => {
                write!(f, "could not cut or fill in cells {cells:?}")
            }
            Abandoned::Topology => write!(f, "topology differs from Θ's after re-sampling"),
            Abandoned::InvalidElement { cells } => {
                write!(f, "invalid element in cells {cells:?}")
            }
        }
    }
}
