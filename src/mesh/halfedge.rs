//! The tracked mesh: a half-edge structure with implicit `next` (the three half-edges of face `f` are
//! `3f, 3f+1, 3f+2`), so a face is one slot and `next`/`prev` cost nothing to store.
//!
//! Vertices carry a persistent id that is never reused within a run: "vertex 17 at frame j" is
//! "vertex 17 at frame j+1" unless an event says otherwise (paper §4.4).

use super::{Attribute, IndexedMesh, MeshError};
use glam::Vec3;

/// Marks a deleted slot or an absent link.
pub(crate) const INVALID: u32 = u32::MAX;

/// A vertex slot in the mesh's arrays (not persistent: `compact` renumbers slots, never ids).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VertexId(pub u32);

/// A half-edge slot; `h / 3` is its face and `h % 3` its corner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct HalfEdgeId(pub u32);

/// A face slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FaceId(pub u32);

/// Closed, oriented 2-manifold triangle mesh with persistent vertex ids and attribute channels.
#[derive(Debug, Clone)]
pub struct Mesh {
    pub(crate) positions: Vec<Vec3>,
    pub(crate) ids: Vec<u64>,
    /// One outgoing half-edge per vertex, `INVALID` for a deleted vertex.
    pub(crate) vertex_half_edge: Vec<u32>,
    /// Origin vertex of each half-edge, `INVALID` for the half-edges of a deleted face.
    pub(crate) origin: Vec<u32>,
    pub(crate) twin: Vec<u32>,
    pub(crate) attributes: Vec<Attribute>,
    pub(crate) free_vertices: Vec<u32>,
    pub(crate) free_faces: Vec<u32>,
    pub(crate) next_id: u64,
    pub(crate) journal: Option<Vec<super::Mutation>>,
}

impl Mesh {
    /// Builds the half-edge structure from a closed, manifold, consistently oriented indexed mesh.
    /// Persistent ids come from `mesh.ids` when present, else are `0..n`.
    pub fn from_indexed(mesh: &IndexedMesh) -> Result<Mesh, MeshError> {
        let edges = mesh.validated_edges()?;
        let ids = match &mesh.ids {
            Some(ids) if ids.len() == mesh.positions.len() => ids.clone(),
            Some(ids) => {
                return Err(MeshError::Corrupt(format!(
                    "{} persistent ids for {} vertices",
                    ids.len(),
                    mesh.positions.len()
                )));
            }
            None => (0..mesh.positions.len() as u64).collect(),
        };
        let mut sorted = ids.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(MeshError::Corrupt(format!(
                "persistent id {} appears twice",
                w[0]
            )));
        }
        for a in &mesh.attributes {
            if a.values.len() != a.components * mesh.positions.len() {
                return Err(MeshError::Corrupt(format!(
                    "attribute '{}' has {} values for {} vertices × {} components",
                    a.name,
                    a.values.len(),
                    mesh.positions.len(),
                    a.components
                )));
            }
        }
        let next_id = sorted.last().map_or(0, |&m| m + 1);
        let origin: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        let twin = twins_of(&edges, &mesh.triangles);
        let mut vertex_half_edge = vec![INVALID; mesh.positions.len()];
        for (h, &v) in origin.iter().enumerate() {
            if vertex_half_edge[v as usize] == INVALID {
                vertex_half_edge[v as usize] = h as u32;
            }
        }
        Ok(Mesh {
            positions: mesh.positions.clone(),
            ids,
            vertex_half_edge,
            origin,
            twin,
            attributes: mesh.attributes.clone(),
            free_vertices: Vec::new(),
            free_faces: Vec::new(),
            next_id,
            journal: None,
        })
    }

    /// The indexed form with live vertices renumbered densely (slot order), persistent ids and
    /// attributes attached.
    pub fn to_indexed(&self) -> IndexedMesh {
        let mut map = vec![INVALID; self.positions.len()];
        let mut positions = Vec::with_capacity(self.vertex_count());
        let mut ids = Vec::with_capacity(self.vertex_count());
        for v in self.vertices() {
            map[v.0 as usize] = positions.len() as u32;
            positions.push(self.positions[v.0 as usize]);
            ids.push(self.ids[v.0 as usize]);
        }
        let triangles = self
            .faces()
            .map(|f| self.face_vertices(f).map(|v| map[v.0 as usize]))
            .collect();
        let attributes = self
            .attributes
            .iter()
            .map(|a| Attribute {
                name: a.name.clone(),
                components: a.components,
                values: self
                    .vertices()
                    .flat_map(|v| {
                        let s = v.0 as usize * a.components;
                        a.values[s..s + a.components].iter().copied()
                    })
                    .collect(),
            })
            .collect();
        IndexedMesh {
            positions,
            triangles,
            ids: Some(ids),
            attributes,
        }
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len() - self.free_vertices.len()
    }

    pub fn face_count(&self) -> usize {
        self.origin.len() / 3 - self.free_faces.len()
    }

    /// Live vertex slots in increasing order.
    pub fn vertices(&self) -> impl Iterator<Item = VertexId> + '_ {
        (0..self.positions.len() as u32)
            .filter(|&v| self.vertex_half_edge[v as usize] != INVALID)
            .map(VertexId)
    }

    /// Live face slots in increasing order.
    pub fn faces(&self) -> impl Iterator<Item = FaceId> + '_ {
        (0..(self.origin.len() / 3) as u32)
            .filter(|&f| self.origin[3 * f as usize] != INVALID)
            .map(FaceId)
    }

    /// Every live half-edge whose twin has a larger index: each undirected edge exactly once.
    pub fn edges(&self) -> impl Iterator<Item = HalfEdgeId> + '_ {
        (0..self.origin.len() as u32)
            .filter(|&h| self.origin[h as usize] != INVALID && self.twin[h as usize] > h)
            .map(HalfEdgeId)
    }

    pub fn position(&self, v: VertexId) -> Vec3 {
        self.positions[v.0 as usize]
    }

    pub fn set_position(&mut self, v: VertexId, p: Vec3) {
        self.positions[v.0 as usize] = p;
    }

    /// True when slot `v` holds a live vertex: a collapse frees its endpoints' slots, and a later
    /// mutation may reuse a slot for a vertex with a new id, so callers that keep slots across
    /// mutations check this together with the id.
    pub fn is_live(&self, v: VertexId) -> bool {
        self.vertex_half_edge
            .get(v.0 as usize)
            .is_some_and(|&h| h != INVALID)
    }

    /// Persistent id of a live vertex.
    pub fn id(&self, v: VertexId) -> u64 {
        self.ids[v.0 as usize]
    }

    /// The id the next created vertex will get; ids below it are never handed out again.
    pub fn next_id(&self) -> u64 {
        self.next_id
    }

    pub fn attributes(&self) -> &[Attribute] {
        &self.attributes
    }

    /// Adds a per-vertex channel (indexed by vertex slot) that every mutation carries along.
    pub fn add_attribute(&mut self, name: &str, components: usize, fill: f32) -> usize {
        self.attributes.push(Attribute {
            name: name.to_string(),
            components,
            values: vec![fill; components * self.positions.len()],
        });
        self.attributes.len() - 1
    }

    /// The `components` values of channel `channel` at vertex `v`.
    pub fn attribute(&self, channel: usize, v: VertexId) -> &[f32] {
        let a = &self.attributes[channel];
        &a.values[v.0 as usize * a.components..(v.0 as usize + 1) * a.components]
    }

    pub fn attribute_mut(&mut self, channel: usize, v: VertexId) -> &mut [f32] {
        let a = &mut self.attributes[channel];
        &mut a.values[v.0 as usize * a.components..(v.0 as usize + 1) * a.components]
    }

    pub fn face_half_edge(&self, f: FaceId) -> HalfEdgeId {
        HalfEdgeId(3 * f.0)
    }

    pub fn face(&self, h: HalfEdgeId) -> FaceId {
        FaceId(h.0 / 3)
    }

    pub fn next(&self, h: HalfEdgeId) -> HalfEdgeId {
        HalfEdgeId(if h.0 % 3 == 2 { h.0 - 2 } else { h.0 + 1 })
    }

    pub fn prev(&self, h: HalfEdgeId) -> HalfEdgeId {
        HalfEdgeId(if h.0.is_multiple_of(3) {
            h.0 + 2
        } else {
            h.0 - 1
        })
    }

    pub fn twin(&self, h: HalfEdgeId) -> HalfEdgeId {
        HalfEdgeId(self.twin[h.0 as usize])
    }

    pub fn origin(&self, h: HalfEdgeId) -> VertexId {
        VertexId(self.origin[h.0 as usize])
    }

    pub fn target(&self, h: HalfEdgeId) -> VertexId {
        self.origin(self.next(h))
    }

    /// One outgoing half-edge of a live vertex.
    pub fn vertex_half_edge(&self, v: VertexId) -> HalfEdgeId {
        HalfEdgeId(self.vertex_half_edge[v.0 as usize])
    }

    pub fn face_vertices(&self, f: FaceId) -> [VertexId; 3] {
        let h = 3 * f.0 as usize;
        [0, 1, 2].map(|k| VertexId(self.origin[h + k]))
    }

    pub fn face_positions(&self, f: FaceId) -> [Vec3; 3] {
        self.face_vertices(f).map(|v| self.position(v))
    }

    /// Outgoing half-edges of `v` in counter-clockwise order (seen from outside).
    pub fn outgoing(&self, v: VertexId) -> Outgoing<'_> {
        let start = self.vertex_half_edge(v);
        Outgoing {
            mesh: self,
            start,
            current: Some(start),
        }
    }

    /// Neighbouring vertices of `v` in counter-clockwise order.
    pub fn neighbours(&self, v: VertexId) -> impl Iterator<Item = VertexId> + '_ {
        self.outgoing(v).map(|h| self.target(h))
    }

    pub fn valence(&self, v: VertexId) -> usize {
        self.outgoing(v).count()
    }

    /// The half-edge from `a` to `b`, if that edge exists.
    pub fn find_half_edge(&self, a: VertexId, b: VertexId) -> Option<HalfEdgeId> {
        self.outgoing(a).find(|&h| self.target(h) == b)
    }

    /// Starts recording every mutation into a journal (drained by `take_journal`): the hook through which
    /// event lists (paper §4.4) observe mesh improvement and surgery, so no caller can forget to record.
    pub fn record_mutations(&mut self) {
        self.journal.get_or_insert_with(Vec::new);
    }

    /// Returns the mutations recorded since the last call (empty when recording is off).
    pub fn take_journal(&mut self) -> Vec<super::Mutation> {
        self.journal
            .as_mut()
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// How many records the journal holds: a mark for [`Mesh::journal_since`].
    pub fn journal_len(&self) -> usize {
        self.journal.as_ref().map_or(0, Vec::len)
    }

    /// The records journaled since `mark` (empty when recording is off).
    pub fn journal_since(&self, mark: usize) -> &[super::Mutation] {
        self.journal
            .as_deref()
            .and_then(|j| j.get(mark..))
            .unwrap_or_default()
    }

    /// Raises the id counter to at least `next`, so ids handed out before a restart (and since
    /// destroyed) are never reused after it.
    pub fn reserve_ids_below(&mut self, next: u64) {
        self.next_id = self.next_id.max(next);
    }

    /// Renumbers slots densely, dropping deleted vertices and faces; ids and attributes follow.
    pub fn compact(&mut self) {
        let journal = self.journal.take();
        let next_id = self.next_id;
        let indexed = self.to_indexed();
        let twin = twins_of(&indexed.sorted_edges(), &indexed.triangles);
        let origin: Vec<u32> = indexed.triangles.iter().flatten().copied().collect();
        let mut vertex_half_edge = vec![INVALID; indexed.positions.len()];
        for (h, &v) in origin.iter().enumerate() {
            if vertex_half_edge[v as usize] == INVALID {
                vertex_half_edge[v as usize] = h as u32;
            }
        }
        *self = Mesh {
            positions: indexed.positions,
            ids: indexed.ids.unwrap_or_default(),
            vertex_half_edge,
            origin,
            twin,
            attributes: indexed.attributes,
            free_vertices: Vec::new(),
            free_faces: Vec::new(),
            next_id,
            journal,
        };
    }
}

/// Iterator over a vertex's outgoing half-edges: `twin(prev(h))` walks counter-clockwise.
pub struct Outgoing<'a> {
    mesh: &'a Mesh,
    start: HalfEdgeId,
    current: Option<HalfEdgeId>,
}

impl Iterator for Outgoing<'_> {
    type Item = HalfEdgeId;

    fn next(&mut self) -> Option<HalfEdgeId> {
        let h = self.current?;
        let n = self.mesh.twin(self.mesh.prev(h));
        self.current = (n != self.start).then_some(n);
        Some(h)
    }
}

/// Twin of every half-edge of a validated (closed, manifold, oriented) indexed mesh.
fn twins_of(sorted_edges: &[(u32, u32, bool, u32)], triangles: &[[u32; 3]]) -> Vec<u32> {
    let half_edge = |a: u32, b: u32, t: u32| -> u32 {
        let tri = triangles[t as usize];
        let k = (0..3)
            .find(|&k| (tri[k], tri[(k + 1) % 3]) == (a, b) || (tri[k], tri[(k + 1) % 3]) == (b, a))
            .unwrap_or(0);
        3 * t + k as u32
    };
    let mut twin = vec![INVALID; triangles.len() * 3];
    for pair in sorted_edges.chunks_exact(2) {
        let (a, b) = (pair[0].0, pair[0].1);
        let h0 = half_edge(a, b, pair[0].3);
        let h1 = half_edge(a, b, pair[1].3);
        twin[h0 as usize] = h1;
        twin[h1 as usize] = h0;
    }
    twin
}
