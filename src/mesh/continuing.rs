//! Vertices a re-sampled patch replaces by a new vertex standing on them. The topology step and the
//! sub-grid match replace every old vertex of a region and give each new vertex the data of the
//! old surface at its closest point (paper §4.4). Where a new vertex stands within a small reach of
//! an old vertex the patch removes, and takes its data from that vertex above all (the closest
//! triangle's corner nearest it, or its largest barycentric weight), the two are one material
//! point as far as tracking can tell: registration itself moves vertices farther than that in one
//! frame. The old vertex then continues at the new position with its id and its data, instead of
//! ending there while a new id starts beside it; so a re-sampled region keeps the ids (and the
//! per-vertex state carried with them) that its new sampling lands on. Only the ids change: the
//! surface, its positions and its connectivity are the patch's.

use super::Mutation;
use super::halfedge::Mesh;
use super::replace::Replacement;
use glam::Vec3;
use rustc_hash::{FxHashMap, FxHashSet};

impl Replacement {
    /// The same surface in which every new vertex of a patch (`PatchCreated`) that stands within
    /// `reach` (world units) of the old vertex it takes most of its data from, when the record
    /// removes that vertex (`PatchDeleted`), is that old vertex moved there: its creation and the
    /// old vertex's removal leave the record, and the record's other rules read the old id. Each
    /// old vertex continues at most one new one, the nearest; ties go to the smaller ids, so the
    /// result does not depend on the record's order. `before` is the mesh the record applies to.
    /// Returns the replacement and the ids of the old vertices that continue, sorted.
    pub fn continuing(mut self, before: &Mesh, reach: f32) -> (Replacement, Vec<u64>) {
        if reach <= 0.0 {
            return (self, Vec::new());
        }
        let deleted: FxHashSet<u64> = self
            .record
            .iter()
            .filter_map(|m| match m {
                Mutation::PatchDeleted { deleted, .. } => Some(*deleted),
                _ => None,
            })
            .collect();
        if deleted.is_empty() {
            return (self, Vec::new());
        }
        let removed: FxHashMap<u64, Vec3> = before
            .vertices()
            .filter(|&v| deleted.contains(&before.id(v)))
            .map(|v| (before.id(v), before.position(v)))
            .collect();
        let slot: FxHashMap<u64, usize> = self
            .surface
            .vertices()
            .map(|v| (self.surface.id(v), v.0 as usize))
            .collect();
        let mut pairs: Vec<(f32, u64, u64)> = self
            .record
            .iter()
            .filter_map(|m| match m {
                Mutation::PatchCreated { created, sources } => {
                    let (old, _) = sources
                        .iter()
                        .copied()
                        .reduce(|best, s| if s.1 > best.1 { s } else { best })?;
                    let from = *removed.get(&old)?;
                    let to = self.surface.positions[*slot.get(created)?];
                    let d = from.distance(to);
                    (d <= reach).then_some((d, *created, old))
                }
                _ => None,
            })
            .collect();
        pairs.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut renamed: FxHashMap<u64, u64> = FxHashMap::default();
        let mut taken: FxHashSet<u64> = FxHashSet::default();
        for (_, created, old) in pairs {
            if taken.insert(old) {
                renamed.insert(created, old);
            }
        }
        if renamed.is_empty() {
            return (self, Vec::new());
        }
        for (created, old) in &renamed {
            self.surface.ids[slot[created]] = *old;
        }
        let rename = |id: &mut u64| {
            if let Some(&old) = renamed.get(id) {
                *id = old;
            }
        };
        self.record.retain(|m| match m {
            Mutation::PatchCreated { created, .. } => !renamed.contains_key(created),
            Mutation::PatchDeleted { deleted, .. } => !taken.contains(deleted),
            _ => true,
        });
        for m in &mut self.record {
            match m {
                Mutation::PatchCreated { sources, .. } | Mutation::PatchDeleted { sources, .. } => {
                    sources.iter_mut().for_each(|(s, _)| rename(s));
                }
                Mutation::SplitEdge { a, b, .. } => {
                    rename(a);
                    rename(b);
                }
                Mutation::SplitFace { corners, .. } => corners.iter_mut().for_each(rename),
                Mutation::Collapse { a, b, .. } => {
                    rename(a);
                    rename(b);
                }
                Mutation::Merge { kept, removed } => {
                    rename(kept);
                    rename(removed);
                }
                Mutation::Flip { a, b, c, d } => [a, b, c, d].into_iter().for_each(rename),
            }
        }
        let mut continued: Vec<u64> = taken.into_iter().collect();
        continued.sort_unstable();
        (self, continued)
    }
}
