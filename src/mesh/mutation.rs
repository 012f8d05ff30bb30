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
    /// Edge `(a, b)` flipped to `(c, d)`: connectivity only, no vertex created or removed.
    Flip { a: u64, b: u64, c: u64, d: u64 },
}
