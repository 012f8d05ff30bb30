//! Where a frame's vertices went: how many each stage created and removed, and how many of those it
//! removed the frame had begun with — the coherence each stage cost. A vertex carried over keeps
//! its id, so a texture or simulation state on it stays put; every one lost is re-sampled from its
//! neighbours (paper §4.4), which is what blurs data carried through many frames.

use crate::mesh::Mutation;
use rustc_hash::FxHashSet;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// What one stage did to the vertices in one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Churn {
    /// Vertices it created (some may be removed again later in the frame).
    pub created: usize,
    /// Vertices it removed.
    pub removed: usize,
    /// Vertices it removed that the frame began with.
    pub lost: usize,
    /// Vertices the frame began with that its patches would have removed, whose ids a new vertex
    /// standing on them continues instead (`TopologyOptions::continue_within`): counted in neither
    /// `removed` nor `lost`.
    #[serde(default)]
    pub continued: usize,
}

impl Churn {
    fn plus(&self, other: &Churn) -> Churn {
        Churn {
            created: self.created + other.created,
            removed: self.removed + other.removed,
            lost: self.lost + other.lost,
            continued: self.continued + other.continued,
        }
    }

    /// The churn of `records`, against the ids the frame began with.
    pub(crate) fn of<'a>(
        records: impl IntoIterator<Item = &'a Mutation>,
        start: &FxHashSet<u64>,
    ) -> Self {
        let mut churn = Churn::default();
        for m in records {
            churn.created += usize::from(m.created().is_some());
            for id in m.removed() {
                churn.removed += 1;
                churn.lost += usize::from(start.contains(&id));
            }
        }
        churn
    }
}

/// One frame's churn by cause (the stages of Algorithm 1 that re-sample).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StageChurn {
    /// Mesh improvement, both passes (§4.1).
    pub improve: Churn,
    /// `ConstrainTopology(M, Φ(M))`: merging self-intersections (§4.3).
    pub topology_self: Churn,
    /// `ConstrainTopology(M, Φ(T))`: taking the target's topology (§4.3).
    pub topology_target: Churn,
    /// The sub-grid match: droplets deleted and copied, components grafted or replaced.
    pub subgrid: Churn,
}

impl StageChurn {
    /// The two frames' churn together, stage by stage.
    pub fn plus(&self, other: &StageChurn) -> StageChurn {
        StageChurn {
            improve: self.improve.plus(&other.improve),
            topology_self: self.topology_self.plus(&other.topology_self),
            topology_target: self.topology_target.plus(&other.topology_target),
            subgrid: self.subgrid.plus(&other.subgrid),
        }
    }

    /// Vertices of the frame's start lost, over every stage.
    pub fn lost(&self) -> usize {
        self.improve.lost + self.topology_self.lost + self.topology_target.lost + self.subgrid.lost
    }
}

/// Journal marks of the frame's stages, from which its churn is tallied at the end of the frame.
#[derive(Debug, Clone, Default)]
pub(crate) struct Marks {
    pub improve: Vec<Range<usize>>,
    pub topology_self: Range<usize>,
    pub topology_target: Range<usize>,
    pub subgrid: Range<usize>,
}

impl Marks {
    /// The churn of `journal` (the frame's records, from mark 0) by stage.
    pub fn churn(&self, journal: &[Mutation], start: &FxHashSet<u64>) -> StageChurn {
        let span = |r: &Range<usize>| journal.get(r.clone()).unwrap_or_default();
        let improve: Vec<&Mutation> = self.improve.iter().flat_map(span).collect();
        let in_improve = |i: usize| self.improve.iter().any(|r| r.contains(&i));
        let subgrid = self
            .subgrid
            .clone()
            .filter(|&i| !in_improve(i))
            .filter_map(|i| journal.get(i));
        StageChurn {
            improve: Churn::of(improve, start),
            topology_self: Churn::of(span(&self.topology_self), start),
            topology_target: Churn::of(span(&self.topology_target), start),
            subgrid: Churn::of(subgrid, start),
        }
    }
}
