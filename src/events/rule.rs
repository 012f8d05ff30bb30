use serde::{Deserialize, Serialize};

/// One line of a sparse linear rule: `target := Σ weight · source` over per-vertex values keyed by
/// persistent id. Every event of the paper (§4.4) is a handful of these: the midpoint of a split or
/// collapsed edge, barycentric weights of a face split, the boundary averages of a topology patch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Assignment {
    pub target: u64,
    pub terms: Vec<(u64, f32)>,
}

impl Assignment {
    pub fn new(target: u64, terms: Vec<(u64, f32)>) -> Self {
        Self { target, terms }
    }

    /// `target := source`, the backward rule of a collapse (`v_A := v_B := v_new`).
    pub fn copy(target: u64, source: u64) -> Self {
        Self::new(target, vec![(source, 1.0)])
    }
}
