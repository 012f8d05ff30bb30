//! Patch replacement (paper §4.3–4.4): the topology step and the sub-grid match re-sample whole
//! regions of the surface at once — cut points on the old surface, a patch of new vertices, the old
//! vertices inside the region removed. They hand the mesh the surface they built and the record of
//! how every vertex came and went. The surface is a `Mesh`, so it is closed, manifold, oriented and
//! non-degenerate by construction, checked once where it was built; the mesh checks the record
//! against the surface and against itself, carries its attribute channels by the record's forward rules, and journals the record like the
//! records of its local mutations. So the journal is the one channel every change to the mesh goes
//! through, and no stage can change the mesh without its events.

use super::halfedge::Mesh;
use super::{Attribute, MeshError, Mutation, ReplacementError};
use rustc_hash::{FxHashMap, FxHashSet};

/// A new surface for the mesh and the record of how it came from the old one.
#[derive(Debug, Clone)]
pub struct Replacement {
    /// The whole surface afterwards (`Mesh::from_indexed` of what the stage built, or
    /// [`Mesh::empty`]), with persistent ids: a vertex whose id the mesh has is that vertex (same
    /// material point); every other id is created by `record`. Its attribute channels are ignored:
    /// the replacement derives them from the record.
    pub surface: Mesh,
    /// Every created vertex (`SplitEdge`, `SplitFace`, `PatchCreated`) and every removed one
    /// (`PatchDeleted`), in the order the event list applies them.
    pub record: Vec<Mutation>,
}

impl Mesh {
    /// Replaces the surface by `replacement.surface` after checking that its record creates
    /// exactly the vertices the mesh lacks and removes exactly those the surface lacks, with ids
    /// never handed out before; on a refusal the mesh is unchanged. Attribute channels follow the
    /// record's forward rules; the record is journaled.
    pub fn replace(&mut self, replacement: Replacement) -> Result<(), MeshError> {
        let Replacement {
            mut surface,
            record,
        } = replacement;
        let live: Vec<u64> = surface.vertices().map(|v| surface.id(v)).collect();
        let next_id = self.check_record(&live, &record)?;
        surface.attributes = self.carried_attributes(&surface.ids, &record);
        surface.next_id = next_id;
        surface.journal = self.journal.take();
        if let Some(journal) = surface.journal.as_mut() {
            journal.extend(record);
        }
        *self = surface;
        Ok(())
    }

    /// Checks `record` against the mesh and the surface's `ids`; the id counter afterwards.
    fn check_record(&self, ids: &[u64], record: &[Mutation]) -> Result<u64, ReplacementError> {
        let before: FxHashSet<u64> = self.vertices().map(|v| self.id(v)).collect();
        let after: FxHashSet<u64> = ids.iter().copied().collect();
        let mut created: FxHashSet<u64> = FxHashSet::default();
        let mut removed: FxHashSet<u64> = FxHashSet::default();
        let mut next_id = self.next_id;
        for m in record {
            if let Some((id, _)) = m.created() {
                if id < self.next_id || !created.insert(id) {
                    return Err(ReplacementError::Reused { id });
                }
                if !after.contains(&id) {
                    return Err(ReplacementError::Lost { id });
                }
                next_id = next_id.max(id + 1);
            }
            for id in m.removed() {
                if !before.contains(&id) || after.contains(&id) || !removed.insert(id) {
                    return Err(ReplacementError::NotRemovable { id });
                }
            }
        }
        if let Some(&id) = ids
            .iter()
            .find(|id| !before.contains(id) && !created.contains(id))
        {
            return Err(ReplacementError::Unrecorded { id });
        }
        let mut vanished: Vec<u64> = before
            .iter()
            .copied()
            .filter(|id| !after.contains(id) && !removed.contains(id))
            .collect();
        vanished.sort_unstable();
        if let Some(&id) = vanished.first() {
            return Err(ReplacementError::Vanished { id });
        }
        Ok(next_id)
    }

    /// The mesh's attribute channels on the vertices `ids`: kept vertices keep their values, created
    /// ones take them by the record's forward rules in order (a rule may read a vertex the record
    /// removes, or one it created earlier); a vertex with no rule gets zeros.
    fn carried_attributes(&self, ids: &[u64], record: &[Mutation]) -> Vec<Attribute> {
        if self.attributes.is_empty() {
            return Vec::new();
        }
        let mut slot: FxHashMap<u64, usize> = self
            .vertices()
            .map(|v| (self.id(v), v.0 as usize))
            .collect();
        let mut values: Vec<Vec<f32>> = self.attributes.iter().map(|a| a.values.clone()).collect();
        let created = record.iter().filter_map(Mutation::created);
        for (at, (created, terms)) in (self.positions.len()..).zip(created) {
            for (channel, a) in values.iter_mut().zip(&self.attributes) {
                let k = a.components;
                let mut sum = vec![0.0f32; k];
                for &(source, weight) in &terms {
                    if let Some(&s) = slot.get(&source) {
                        for (c, x) in sum.iter_mut().enumerate() {
                            *x += weight * channel[s * k + c];
                        }
                    }
                }
                channel.extend(sum);
            }
            slot.insert(created, at);
        }
        self.attributes
            .iter()
            .zip(&values)
            .map(|(a, channel)| {
                let k = a.components;
                Attribute {
                    name: a.name.clone(),
                    components: k,
                    values: ids
                        .iter()
                        .flat_map(|id| match slot.get(id) {
                            Some(&s) => channel[s * k..s * k + k].to_vec(),
                            None => vec![0.0; k],
                        })
                        .collect(),
                }
            })
            .collect()
    }

    /// A mesh with no vertices: the surface of a replacement that removes everything.
    pub fn empty() -> Mesh {
        Mesh {
            positions: Vec::new(),
            ids: Vec::new(),
            vertex_half_edge: Vec::new(),
            origin: Vec::new(),
            twin: Vec::new(),
            attributes: Vec::new(),
            free_vertices: Vec::new(),
            free_faces: Vec::new(),
            next_id: 0,
            journal: None,
        }
    }
}
