//! `Mesh::validate`: the half-edge structure's own invariants plus every invariant of the indexed form.

use super::MeshError;
use super::halfedge::{HalfEdgeId, INVALID, Mesh, VertexId};

impl Mesh {
    /// Checks the pointer structure (twins symmetric and opposite, every vertex's half-edge its own, the
    /// ring around each vertex reaching all its half-edges) and then that the mesh is closed, manifold,
    /// consistently oriented, finite and non-degenerate. Tests call it after every mutation.
    pub fn validate(&self) -> Result<(), MeshError> {
        let mut outgoing_count = vec![0usize; self.positions.len()];
        for h in 0..self.origin.len() as u32 {
            let o = self.origin[h as usize];
            if o == INVALID {
                continue;
            }
            if self.vertex_half_edge[o as usize] == INVALID {
                return Err(MeshError::Corrupt(format!(
                    "half-edge {h} starts at deleted vertex {o}"
                )));
            }
            outgoing_count[o as usize] += 1;
            let t = self.twin[h as usize];
            if t == INVALID || self.origin[t as usize] == INVALID {
                return Err(MeshError::Corrupt(format!(
                    "half-edge {h} has no live twin"
                )));
            }
            let he = HalfEdgeId(h);
            let tw = HalfEdgeId(t);
            if self.twin(tw) != he
                || self.origin(tw) != self.target(he)
                || self.target(tw) != self.origin(he)
            {
                return Err(MeshError::Corrupt(format!(
                    "half-edges {h} and {t} are not opposite twins"
                )));
            }
        }
        for v in self.vertices() {
            let h = self.vertex_half_edge(v);
            if self.origin[h.0 as usize] != v.0 {
                return Err(MeshError::Corrupt(format!(
                    "vertex {} points at half-edge {} that starts elsewhere",
                    v.0, h.0
                )));
            }
            let ring = self.ring_len(v, outgoing_count[v.0 as usize]);
            if ring != outgoing_count[v.0 as usize] {
                return Err(MeshError::NonManifoldVertex {
                    vertex: v.0,
                    fans: 2,
                });
            }
        }
        self.to_indexed().validate()
    }

    /// Length of the ring walk around `v`, stopping after `limit + 1` steps so a corrupt ring that never
    /// returns cannot loop forever.
    fn ring_len(&self, v: VertexId, limit: usize) -> usize {
        self.outgoing(v).take(limit + 1).count()
    }
}
