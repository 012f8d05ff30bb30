use serde::Serialize;

/// Why an operation that would fix a bad element was not performed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Refusal {
    /// The endpoints share a neighbour besides the two opposite vertices (collapse), or the two
    /// opposite vertices are already adjacent (flip): the result would not be a manifold.
    LinkCondition,
    /// A vertex would drop below valence 3 (the valence-3 trap of thesis §3.2.2).
    Valence,
    /// A remaining face would be degenerate (the mesh refused the mutation).
    Degenerate,
    /// A face would turn over (its normal would point against one it replaces).
    NormalFlip,
    /// A flip would not raise the smallest angle of its two faces, or a split would raise the
    /// number of failing faces.
    NoGain,
    /// A new edge would be longer than the split threshold.
    LongEdge,
    /// A split would create an edge shorter than the collapse threshold.
    ShortEdge,
    /// Two faces would meet at a dihedral angle below the minimum.
    SharpDihedral,
    /// A face would have an angle below the minimum (a merge must leave none behind).
    SmallAngle,
    /// The surface would move farther than `max_deviation`.
    Deviation,
}

/// The kind of operation a refusal concerns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Operation {
    Flip,
    Collapse,
    Merge,
    Split,
    Relax,
}

/// What is wrong with an element improvement could not fix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Problem {
    SmallAngle,
    ShortEdge,
    SharpDihedral,
    LongEdge,
}

/// A bad element left after improvement, with the reasons its candidate fixes were refused.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unfixed {
    pub problem: Problem,
    /// Persistent ids: the face's three corners, or the edge's two ends.
    pub vertices: Vec<u64>,
    /// The measure that fails: angle or dihedral in degrees, or length relative to the target.
    pub measure: f32,
    /// Each kind of operation tried with each reason it was refused, sorted, without repeats.
    pub refusals: Vec<(Operation, Refusal)>,
}

/// What one improvement did.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ImproveReport {
    pub splits: usize,
    pub collapses: usize,
    pub merges: usize,
    pub flips: usize,
    /// Vertices moved along the surface instead of removed.
    pub relaxes: usize,
    pub rounds: usize,
    /// False when `max_rounds` ran out while rounds were still changing the mesh.
    pub converged: bool,
    /// How often each reason stopped an attempted fix, in `Refusal` order.
    pub refusals: Vec<(Refusal, usize)>,
}

impl ImproveReport {
    /// Splits, collapses, merges and flips performed.
    pub fn operations(&self) -> usize {
        self.splits + self.collapses + self.merges + self.flips + self.relaxes
    }

    pub(super) fn refused(&mut self, reason: Refusal) {
        match self.refusals.binary_search_by(|(r, _)| r.cmp(&reason)) {
            Ok(i) => self.refusals[i].1 += 1,
            Err(i) => self.refusals.insert(i, (reason, 1)),
        }
    }
}
