//! The record every mesh mutation leaves in the journal, in persistent ids, so event lists
//! (paper §4.4) can be derived without the caller's help.

/// One elementary change to the tracked mesh. Weights give each created vertex's data as a combination
/// of the vertices it came from (the forward rule of paper §4.4).
#[derive(Debug, Clone, PartialEq)]
pub enum Mutation {
    /// Edge `(a, b)` split at parameter `t`: `created := (1 − t)·a + t·b`; nothing removed.
    SplitEdge {
        a: u64,
        b: u64,
        created: u64,
        t: f32,
    },
    /// A face split at barycentric `weights`: `created := Σ weights[i]·corners[i]`.
    SplitFace {
        corners: [u64; 3],
        created: u64,
        weights: [f32; 3],
    },
    /// Edge `(a, b)` collapsed: both removed, `created := (a + b) / 2`, and backwards `a := b := created`.
    Collapse { a: u64, b: u64, created: u64 },
    /// Edge `(kept, removed)` merged into `kept`, which keeps its position and data; backwards
    /// `removed := kept`.
    Merge { kept: u64, removed: u64 },
    /// Edge `(a, b)` flipped to `(c, d)`: connectivity only, no vertex created or removed.
    Flip { a: u64, b: u64, c: u64, d: u64 },
    /// A vertex created inside a replaced patch (paper §4.4): `created := Σ w·source` over
    /// `sources`, which are empty when nothing survives to take data from.
    PatchCreated {
        created: u64,
        sources: Vec<(u64, f32)>,
    },
    /// A vertex removed with a replaced patch: going backward, `deleted := Σ w·source`.
    PatchDeleted {
        deleted: u64,
        sources: Vec<(u64, f32)>,
    },
}

impl Mutation {
    /// The vertex this record creates, with the vertices it takes its data from going forward.
    pub(crate) fn created(&self) -> Option<(u64, Vec<(u64, f32)>)> {
        match self {
            Mutation::SplitEdge { a, b, created, t } => {
                Some((*created, vec![(*a, 1.0 - t), (*b, *t)]))
            }
            Mutation::SplitFace {
                corners,
                created,
                weights,
            } => Some((*created, corners.iter().copied().zip(*weights).collect())),
            Mutation::Collapse { a, b, created } => Some((*created, vec![(*a, 0.5), (*b, 0.5)])),
            Mutation::PatchCreated { created, sources } => Some((*created, sources.clone())),
            Mutation::Merge { .. } | Mutation::Flip { .. } | Mutation::PatchDeleted { .. } => None,
        }
    }

    /// The vertices this record removes.
    pub(crate) fn removed(&self) -> Vec<u64> {
        match self {
            Mutation::Collapse { a, b, .. } => vec![*a, *b],
            Mutation::Merge { removed, .. } => vec![*removed],
            Mutation::PatchDeleted { deleted, .. } => vec![*deleted],
            _ => Vec::new(),
        }
    }
}
