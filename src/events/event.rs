use super::{Assignment, EventError};
use crate::mesh::Mutation;
use serde::{Deserialize, Serialize};

/// What re-sampled the vertices of an event; the rules say how, the kind says why (for reports and
/// for the file format).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EventKind {
    SplitEdge,
    SplitFace,
    Collapse,
    /// An edge merged into one of its ends, which keeps its data (improvement's cheaper collapse).
    Merge,
    /// A vertex created inside a patch of new geometry after a topology change (paper §4.4).
    PatchCreated,
    /// A vertex deleted inside a patch destroyed by a topological merge (paper §4.4).
    PatchDeleted,
}

/// One record `(V_in, V_out, f, g)` of the paper's event list (§4.4).
///
/// `forward` is `f`: it assigns values to vertices of `outputs` from vertices of `inputs`. `backward` is
/// `g`: it assigns values to vertices of `inputs` from vertices of `outputs`; empty means the paper's
/// "null". Vertices in both sets keep their values; those only in `inputs` vanish going forward, those
/// only in `outputs` vanish going backward.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Event {
    pub kind: EventKind,
    pub inputs: Vec<u64>,
    pub outputs: Vec<u64>,
    pub forward: Vec<Assignment>,
    pub backward: Vec<Assignment>,
}

impl Event {
    /// `({a, b}, {a, b, new}, new := (1 − t)·a + t·b, null)`; the paper splits at `t = ½`.
    pub fn split_edge(a: u64, b: u64, created: u64, t: f32) -> Self {
        Self {
            kind: EventKind::SplitEdge,
            inputs: vec![a, b],
            outputs: vec![a, b, created],
            forward: vec![Assignment::new(created, vec![(a, 1.0 - t), (b, t)])],
            backward: Vec::new(),
        }
    }

    /// `({A, B, C}, {A, B, C, new}, new := αA + βB + γC, null)`.
    pub fn split_face(corners: [u64; 3], created: u64, weights: [f32; 3]) -> Self {
        let mut outputs = corners.to_vec();
        outputs.push(created);
        Self {
            kind: EventKind::SplitFace,
            inputs: corners.to_vec(),
            outputs,
            forward: vec![Assignment::new(
                created,
                corners.into_iter().zip(weights).collect(),
            )],
            backward: Vec::new(),
        }
    }

    /// `({a, b}, {new}, new := (a + b)/2, a := b := new)`.
    pub fn collapse(a: u64, b: u64, created: u64) -> Self {
        Self {
            kind: EventKind::Collapse,
            inputs: vec![a, b],
            outputs: vec![created],
            forward: vec![Assignment::new(created, vec![(a, 0.5), (b, 0.5)])],
            backward: vec![Assignment::copy(a, created), Assignment::copy(b, created)],
        }
    }

    /// `({kept, removed}, {kept}, null, removed := kept)`: the kept end keeps its values going
    /// forward, and the removed one takes them going backward.
    pub fn merge(kept: u64, removed: u64) -> Self {
        Self {
            kind: EventKind::Merge,
            inputs: vec![kept, removed],
            outputs: vec![kept],
            forward: Vec::new(),
            backward: vec![Assignment::copy(removed, kept)],
        }
    }

    /// A vertex created in a patch of new geometry: `(boundary, boundary ∪ {new}, new := Σ w·b, null)`,
    /// the weights being the breadth-first boundary averages of §4.4. An empty `boundary` (nothing
    /// survives to take data from) gives `(∅, {new}, null, null)`.
    pub fn patch_created(created: u64, boundary: Vec<(u64, f32)>) -> Self {
        let (before, after) = patch_sides(created, &boundary);
        Self {
            kind: EventKind::PatchCreated,
            inputs: before,
            outputs: after,
            forward: rule(created, boundary),
            backward: Vec::new(),
        }
    }

    /// A vertex deleted in a merged patch: `(boundary ∪ {old}, boundary, null, old := Σ w·b)`. An
    /// empty `boundary` gives `({old}, ∅, null, null)`.
    pub fn patch_deleted(deleted: u64, boundary: Vec<(u64, f32)>) -> Self {
        let (after, before) = patch_sides(deleted, &boundary);
        Self {
            kind: EventKind::PatchDeleted,
            inputs: before,
            outputs: after,
            forward: Vec::new(),
            backward: rule(deleted, boundary),
        }
    }

    /// The event a mesh mutation stands for; `None` for a flip, which re-connects vertices without
    /// re-sampling any (every vertex keeps its id and its data).
    pub fn from_mutation(mutation: &Mutation) -> Option<Self> {
        match mutation {
            &Mutation::SplitEdge { a, b, created, t } => Some(Self::split_edge(a, b, created, t)),
            &Mutation::SplitFace {
                corners,
                created,
                weights,
            } => Some(Self::split_face(corners, created, weights)),
            &Mutation::Collapse { a, b, created } => Some(Self::collapse(a, b, created)),
            &Mutation::Merge { kept, removed } => Some(Self::merge(kept, removed)),
            Mutation::PatchCreated { created, sources } => {
                Some(Self::patch_created(*created, sources.clone()))
            }
            Mutation::PatchDeleted { deleted, sources } => {
                Some(Self::patch_deleted(*deleted, sources.clone()))
            }
            Mutation::Flip { .. } => None,
        }
    }

    /// Checks that `f` reads only `V_in` and writes only `V_out`, that `g` reads only `V_out` and writes
    /// only `V_in`, that no vertex is written twice, and that every weight is finite. `index` names the
    /// event in the error.
    pub fn check(&self, index: usize) -> Result<(), EventError> {
        let malformed = |what: String| EventError::Malformed { event: index, what };
        let sides = [
            ("forward", &self.forward, &self.inputs, &self.outputs),
            ("backward", &self.backward, &self.outputs, &self.inputs),
        ];
        for (name, rules, readable, writable) in sides {
            let mut written = Vec::with_capacity(rules.len());
            for rule in rules {
                if !writable.contains(&rule.target) {
                    return Err(malformed(format!(
                        "{name} rule writes vertex {} outside its output set",
                        rule.target
                    )));
                }
                if written.contains(&rule.target) {
                    return Err(malformed(format!(
                        "{name} rules write vertex {} twice",
                        rule.target
                    )));
                }
                written.push(rule.target);
                for &(source, weight) in &rule.terms {
                    if !readable.contains(&source) {
                        return Err(malformed(format!(
                            "{name} rule reads vertex {source} outside its input set"
                        )));
                    }
                    if !weight.is_finite() {
                        return Err(malformed(format!(
                            "{name} rule for vertex {} has weight {weight}",
                            rule.target
                        )));
                    }
                }
            }
        }
        Ok(())
    }
}

/// The boundary's vertices, and the same with `vertex` after them: the two vertex sets of a patch
/// event, the smaller on the side `vertex` is missing from.
fn patch_sides(vertex: u64, boundary: &[(u64, f32)]) -> (Vec<u64>, Vec<u64>) {
    let without: Vec<u64> = boundary.iter().map(|&(id, _)| id).collect();
    let mut with = without.clone();
    with.push(vertex);
    (without, with)
}

/// `target := Σ w·source` over `terms`, or no rule (the paper's null) when there are no terms.
fn rule(target: u64, terms: Vec<(u64, f32)>) -> Vec<Assignment> {
    if terms.is_empty() {
        Vec::new()
    } else {
        vec![Assignment::new(target, terms)]
    }
}
