//! Local mutations: edge split, face split, edge collapse, edge merge, edge flip (paper §4.1).
//!
//! Each one states its precondition, refuses (returns `None`) when the result would not be a closed
//! 2-manifold with non-degenerate faces, and otherwise rewrites only the faces around the edge through
//! one routine (`rewrite`) that re-pairs twins locally, so every mutation is O(1) amortized and they
//! cannot disagree on how connectivity is patched.

use super::Mutation;
use super::halfedge::{FaceId, HalfEdgeId, INVALID, Mesh, VertexId};
use super::validate::degenerate_triangle;
use glam::Vec3;

impl Mesh {
    /// Splits the edge of `h` at parameter `t ∈ (0, 1)` from `origin(h)`, creating one vertex (new id)
    /// whose position and attributes are interpolated. `None` when `t` is outside (0, 1), a new face
    /// would be degenerate, or the two faces of the edge share their third vertex: a component of
    /// two faces back to back (which surface reconstructions of fluids do emit, as a flat droplet),
    /// whose split would pair the new faces' edges among themselves and leave the outer ones open.
    pub fn split_edge(&mut self, h: HalfEdgeId, t: f32) -> Option<VertexId> {
        if !(t > 0.0 && t < 1.0) {
            return None;
        }
        let t2 = self.twin(h);
        let (a, b) = (self.origin(h), self.target(h));
        let c = self.origin(self.prev(h));
        let d = self.origin(self.prev(t2));
        if c == d {
            return None;
        }
        let p = self.position(a).lerp(self.position(b), t);
        let [pa, pb, pc, pd] = [a, b, c, d].map(|v| self.position(v));
        if [[pa, p, pc], [p, pb, pc], [pb, p, pd], [p, pa, pd]]
            .iter()
            .any(|&[x, y, z]| degenerate_triangle(x, y, z))
        {
            return None;
        }
        let m = self.alloc_vertex(p, &[(a, 1.0 - t), (b, t)]);
        self.rewrite(
            &[self.face(h), self.face(t2)],
            &[[a, m, c], [m, b, c], [b, m, d], [m, a, d]],
        );
        self.log(|mesh| Mutation::SplitEdge {
            a: mesh.id(a),
            b: mesh.id(b),
            created: mesh.id(m),
            t,
        });
        Some(m)
    }

    /// Splits face `f` at barycentric `weights` (all positive, summing to 1) into three faces.
    pub fn split_face(&mut self, f: FaceId, weights: [f32; 3]) -> Option<VertexId> {
        if weights.iter().any(|&w| w.is_nan() || w <= 0.0) {
            return None;
        }
        let [a, b, c] = self.face_vertices(f);
        let [pa, pb, pc] = [a, b, c].map(|v| self.position(v));
        let p = pa * weights[0] + pb * weights[1] + pc * weights[2];
        if [[pa, pb, p], [pb, pc, p], [pc, pa, p]]
            .iter()
            .any(|&[x, y, z]| degenerate_triangle(x, y, z))
        {
            return None;
        }
        let m = self.alloc_vertex(p, &[(a, weights[0]), (b, weights[1]), (c, weights[2])]);
        self.rewrite(&[f], &[[a, b, m], [b, c, m], [c, a, m]]);
        self.log(|mesh| Mutation::SplitFace {
            corners: [a, b, c].map(|v| mesh.id(v)),
            created: mesh.id(m),
            weights,
        });
        Some(m)
    }

    /// Collapses the edge of `h` to one vertex at `position` with a new id and averaged attributes
    /// (paper §4.4: `v_new := (v_A + v_B)/2`). `None` when the link condition fails (the endpoints share
    /// a neighbour other than the two opposite vertices — this also catches the valence-3 trap of thesis
    /// §3.2.2), when an opposite vertex would drop below valence 3 (a tetrahedron), or when a remaining
    /// face would become degenerate. Folding checks are the caller's (mesh improvement).
    pub fn collapse(&mut self, h: HalfEdgeId, position: Vec3) -> Option<VertexId> {
        let (a, b) = (self.origin(h), self.target(h));
        let (region, tris) = self.contraction(h, position)?;
        let (ida, idb) = (self.id(a), self.id(b));
        let m = self.alloc_vertex(position, &[(a, 0.5), (b, 0.5)]);
        let tris: Vec<[VertexId; 3]> = tris
            .iter()
            .map(|tri| tri.map(|v| if v == a { m } else { v }))
            .collect();
        self.rewrite(&region, &tris);
        self.free_vertex(a);
        self.free_vertex(b);
        self.log(|mesh| Mutation::Collapse {
            a: ida,
            b: idb,
            created: mesh.id(m),
        });
        Some(m)
    }

    /// Merges the edge of `h` into its origin: the target is removed and the origin keeps its
    /// position, id and attributes. Where a collapse re-samples both ends, a merge re-samples one
    /// and creates nothing, so a vertex that improvement must remove costs one vertex of coherence
    /// rather than two plus a new one. Refused in the same cases as [`Mesh::collapse`].
    pub fn merge(&mut self, h: HalfEdgeId) -> Option<VertexId> {
        self.merge_to(h, self.position(self.origin(h)))
    }

    /// [`Mesh::merge`], with the origin moved to `position`: the paper's collapse to the midpoint
    /// (§4.1) that keeps one end's id and attributes instead of creating a vertex. Refused in the
    /// same cases as [`Mesh::collapse`] to `position`.
    pub fn merge_to(&mut self, h: HalfEdgeId, position: Vec3) -> Option<VertexId> {
        let (a, b) = (self.origin(h), self.target(h));
        let (region, tris) = self.contraction(h, position)?;
        let (kept, removed) = (self.id(a), self.id(b));
        self.set_position(a, position);
        self.rewrite(&region, &tris);
        self.free_vertex(b);
        self.log(|_| Mutation::Merge { kept, removed });
        Some(a)
    }

    /// The faces around the edge of `h` and what they become when its target is renamed to its
    /// origin, placed at `position`; `None` when that would break the manifold (see `collapse`).
    fn contraction(
        &self,
        h: HalfEdgeId,
        position: Vec3,
    ) -> Option<(Vec<FaceId>, Vec<[VertexId; 3]>)> {
        let t2 = self.twin(h);
        let (a, b) = (self.origin(h), self.target(h));
        let c = self.origin(self.prev(h));
        let d = self.origin(self.prev(t2));
        if self.valence(c) <= 3 || self.valence(d) <= 3 {
            return None;
        }
        let ring_a: Vec<VertexId> = self.neighbours(a).collect();
        let shared = self.neighbours(b).filter(|v| ring_a.contains(v)).count();
        if shared != 2 {
            return None;
        }
        let (fa, fb) = (self.face(h), self.face(t2));
        let mut region: Vec<FaceId> = self
            .outgoing(a)
            .chain(self.outgoing(b))
            .map(|e| self.face(e))
            .collect();
        region.sort_unstable();
        region.dedup();
        let tris: Vec<[VertexId; 3]> = region
            .iter()
            .filter(|&&f| f != fa && f != fb)
            .map(|&f| self.face_vertices(f).map(|v| if v == b { a } else { v }))
            .collect();
        let at = |v: VertexId| if v == a { position } else { self.position(v) };
        if tris
            .iter()
            .any(|tri| degenerate_triangle(at(tri[0]), at(tri[1]), at(tri[2])))
        {
            return None;
        }
        Some((region, tris))
    }

    /// Flips the edge of `h` (between faces `(a,b,c)` and `(b,a,d)`) to the edge `(c, d)`. `None` when
    /// `c` and `d` are already adjacent, when `a` or `b` would drop below valence 3, or when a new face
    /// would be degenerate. Whether the flip improves the surface is the caller's decision.
    pub fn flip(&mut self, h: HalfEdgeId) -> Option<HalfEdgeId> {
        let t2 = self.twin(h);
        let (a, b) = (self.origin(h), self.target(h));
        let c = self.origin(self.prev(h));
        let d = self.origin(self.prev(t2));
        if c == d || self.valence(a) <= 3 || self.valence(b) <= 3 {
            return None;
        }
        if self.find_half_edge(c, d).is_some() {
            return None;
        }
        let [pa, pb, pc, pd] = [a, b, c, d].map(|v| self.position(v));
        if degenerate_triangle(pc, pa, pd) || degenerate_triangle(pd, pb, pc) {
            return None;
        }
        self.rewrite(&[self.face(h), self.face(t2)], &[[c, a, d], [d, b, c]]);
        self.log(|mesh| Mutation::Flip {
            a: mesh.id(a),
            b: mesh.id(b),
            c: mesh.id(c),
            d: mesh.id(d),
        });
        self.find_half_edge(c, d)
    }

    /// Creates a vertex with a fresh persistent id whose attributes are `Σ w · attr(v)`.
    fn alloc_vertex(&mut self, p: Vec3, sources: &[(VertexId, f32)]) -> VertexId {
        let v = match self.free_vertices.pop() {
            Some(v) => {
                self.positions[v as usize] = p;
                self.ids[v as usize] = self.next_id;
                v
            }
            None => {
                self.positions.push(p);
                self.ids.push(self.next_id);
                self.vertex_half_edge.push(INVALID);
                for a in &mut self.attributes {
                    a.values.extend(std::iter::repeat_n(0.0, a.components));
                }
                (self.positions.len() - 1) as u32
            }
        };
        self.next_id += 1;
        for a in &mut self.attributes {
            let k = a.components;
            for c in 0..k {
                let value = sources
                    .iter()
                    .map(|&(s, w)| w * a.values[s.0 as usize * k + c])
                    .sum();
                a.values[v as usize * k + c] = value;
            }
        }
        VertexId(v)
    }

    fn free_vertex(&mut self, v: VertexId) {
        self.vertex_half_edge[v.0 as usize] = INVALID;
        self.free_vertices.push(v.0);
    }

    fn log(&mut self, record: impl FnOnce(&Mesh) -> Mutation) {
        if self.journal.is_some() {
            let m = record(self);
            if let Some(j) = self.journal.as_mut() {
                j.push(m);
            }
        }
    }

    /// Replaces the faces `old` by `new` (which must cover the same disk with the same boundary up to
    /// the vertices the caller renamed), re-pairing twins among the new half-edges and the outside
    /// half-edges that bordered `old`. Face slots are reused last-freed-first, so slot assignment is
    /// deterministic.
    fn rewrite(&mut self, old: &[FaceId], new: &[[VertexId; 3]]) {
        let mut outside: Vec<u32> = Vec::with_capacity(3 * old.len());
        for &f in old {
            for k in 0..3 {
                let t = self.twin[3 * f.0 as usize + k];
                if !old.contains(&FaceId(t / 3)) && !outside.contains(&t) {
                    outside.push(t);
                }
            }
        }
        for &f in old {
            for k in 0..3 {
                self.origin[3 * f.0 as usize + k] = INVALID;
                self.twin[3 * f.0 as usize + k] = INVALID;
            }
        }
        self.free_faces.extend(old.iter().rev().map(|f| f.0));
        let mut open: Vec<u32> = outside;
        for tri in new {
            let f = match self.free_faces.pop() {
                Some(f) => f,
                None => {
                    self.origin.extend([INVALID; 3]);
                    self.twin.extend([INVALID; 3]);
                    (self.origin.len() / 3 - 1) as u32
                }
            };
            for (k, v) in tri.iter().enumerate() {
                self.origin[3 * f as usize + k] = v.0;
                open.push(3 * f + k as u32);
            }
        }
        // Twins share an undirected edge: sorting by it puts every pair side by side, so pairing
        // costs O(n log n) rather than a search per half-edge.
        let mut keyed: Vec<(u32, u32, u32)> = open
            .iter()
            .map(|&h| {
                let (from, to) = (self.origin[h as usize], self.target(HalfEdgeId(h)).0);
                (from.min(to), from.max(to), h)
            })
            .collect();
        keyed.sort_unstable();
        for pair in keyed.chunks_exact(2) {
            let (h, g) = (pair[0].2, pair[1].2);
            let opposite = (pair[0].0, pair[0].1) == (pair[1].0, pair[1].1)
                && self.origin[h as usize] != self.origin[g as usize];
            debug_assert!(opposite, "rewrite left half-edges {h} and {g} unpaired");
            if opposite {
                self.twin[h as usize] = g;
                self.twin[g as usize] = h;
            }
        }
        for &h in open.iter().rev() {
            self.vertex_half_edge[self.origin[h as usize] as usize] = h;
        }
    }
}
