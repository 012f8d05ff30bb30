//! Validation of an indexed mesh: the tracked mesh must be a closed, consistently oriented
//! 2-manifold with finite coordinates and no zero-area faces (DESIGN.md "Invariants").

use super::{IndexedMesh, MeshError};
use glam::Vec3;

/// Relative area below which a triangle counts as degenerate: twice its area against the square of its
/// longest edge. Scale-free, so scaling a mesh never changes the verdict.
const DEGENERATE_RELATIVE_AREA: f64 = 1e-12;

impl IndexedMesh {
    /// Checks every invariant of a tracked mesh and names the first offending element.
    ///
    /// Checks run in a fixed order (indices, coordinates, faces, edges, vertices) so the same broken file
    /// always reports the same error.
    pub fn validate(&self) -> Result<(), MeshError> {
        self.validated_edges().map(|_| ())
    }

    /// [`IndexedMesh::validate`], returning the [`IndexedMesh::sorted_edges`] its edge checks read,
    /// so that building the half-edge structure does not sort them again.
    pub(crate) fn validated_edges(&self) -> Result<Vec<(u32, u32, bool, u32)>, MeshError> {
        if self.triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        let n = self.positions.len();
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(MeshError::IndexOutOfRange {
                    triangle: t,
                    vertex: v,
                    count: n,
                });
            }
        }
        if let Some((v, p)) = self
            .positions
            .iter()
            .enumerate()
            .find(|(_, p)| !p.is_finite())
        {
            return Err(MeshError::NonFiniteCoordinate {
                vertex: v,
                position: p.to_array(),
            });
        }
        for t in 0..self.triangles.len() {
            if self.is_degenerate(t) {
                return Err(MeshError::DegenerateFace { triangle: t });
            }
        }
        let edges = self.sorted_edges();
        self.check_edges(&edges)?;
        self.check_vertices(&edges)?;
        Ok(edges)
    }

    /// True when triangle `t` repeats a vertex or has (relatively) zero area.
    pub fn is_degenerate(&self, t: usize) -> bool {
        let [a, b, c] = self.triangles[t];
        if a == b || b == c || a == c {
            return true;
        }
        let p = |v: u32| self.positions[v as usize];
        degenerate_triangle(p(a), p(b), p(c))
    }

    /// Directed half-edges `(min, max, forward, triangle)` sorted by undirected edge: the shared basis of
    /// the edge checks and of component/Euler counting.
    ///
    /// A counting sort by the smaller vertex, then each vertex's few half-edges sorted on their
    /// own: linear in the mesh, where one comparison sort of every half-edge was the largest cost
    /// of validating a frame's surface and counting its topology.
    pub(crate) fn sorted_edges(&self) -> Vec<(u32, u32, bool, u32)> {
        let half_edges = || {
            self.triangles.iter().enumerate().flat_map(|(t, tri)| {
                (0..3).map(move |k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    (a.min(b), a.max(b), a < b, t as u32)
                })
            })
        };
        let buckets = self
            .triangles
            .iter()
            .flatten()
            .max()
            .map_or(0, |&v| v as usize + 1);
        let mut starts = vec![0usize; buckets + 1];
        for (a, ..) in half_edges() {
            starts[a as usize + 1] += 1;
        }
        for v in 0..buckets {
            starts[v + 1] += starts[v];
        }
        let mut fill = starts.clone();
        let mut edges = vec![(0, 0, false, 0); 3 * self.triangles.len()];
        for edge in half_edges() {
            let slot = &mut fill[edge.0 as usize];
            edges[*slot] = edge;
            *slot += 1;
        }
        for v in 0..buckets {
            edges[starts[v]..starts[v + 1]].sort_unstable();
        }
        edges
    }

    fn check_edges(&self, edges: &[(u32, u32, bool, u32)]) -> Result<(), MeshError> {
        for group in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let (a, b) = (group[0].0, group[0].1);
            match group.len() {
                1 => {
                    let (a, b) = if group[0].2 { (a, b) } else { (b, a) };
                    return Err(MeshError::OpenBoundary {
                        a,
                        b,
                        triangle: group[0].3 as usize,
                    });
                }
                2 if group[0].2 == group[1].2 => {
                    return Err(MeshError::InconsistentOrientation {
                        a,
                        b,
                        t0: group[0].3 as usize,
                        t1: group[1].3 as usize,
                    });
                }
                2 => {}
                count => return Err(MeshError::NonManifoldEdge { a, b, count }),
            }
        }
        Ok(())
    }

    /// Counts the fans of triangles around every vertex (union of corners across shared edges); more
    /// than one fan is a bow-tie, none is an isolated vertex. Assumes `check_edges` passed.
    fn check_vertices(&self, edges: &[(u32, u32, bool, u32)]) -> Result<(), MeshError> {
        let corners = self.triangles.len() * 3;
        let mut parent: Vec<u32> = (0..corners as u32).collect();
        let corner_of = |t: u32, v: u32| -> u32 {
            let tri = self.triangles[t as usize];
            let k = tri.iter().position(|&x| x == v).unwrap_or(0);
            t * 3 + k as u32
        };
        for pair in edges.chunks_exact(2) {
            let (a, b, t0, t1) = (pair[0].0, pair[0].1, pair[0].3, pair[1].3);
            union(&mut parent, corner_of(t0, a), corner_of(t1, a));
            union(&mut parent, corner_of(t0, b), corner_of(t1, b));
        }
        let mut fans = vec![0usize; self.positions.len()];
        for c in 0..corners as u32 {
            if find(&mut parent, c) == c {
                fans[self.triangles[(c / 3) as usize][(c % 3) as usize] as usize] += 1;
            }
        }
        for (v, &count) in fans.iter().enumerate() {
            match count {
                0 => return Err(MeshError::IsolatedVertex { vertex: v }),
                1 => {}
                fans => {
                    return Err(MeshError::NonManifoldVertex {
                        vertex: v as u32,
                        fans,
                    });
                }
            }
        }
        Ok(())
    }
}

/// True when the triangle's area is zero relative to its longest edge (computed in f64).
pub(crate) fn degenerate_triangle(a: Vec3, b: Vec3, c: Vec3) -> bool {
    let (pa, pb, pc) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let twice_area = (pb - pa).cross(pc - pa).length();
    let longest = (pb - pa)
        .length_squared()
        .max((pc - pb).length_squared())
        .max((pa - pc).length_squared());
    twice_area <= DEGENERATE_RELATIVE_AREA * longest
}

/// Union-find root with path halving.
pub(crate) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

/// Union by smaller root index, so the result does not depend on the order of unions.
pub(crate) fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The edges of `mesh` by one comparison sort of every half-edge.
    fn compared(mesh: &IndexedMesh) -> Vec<(u32, u32, bool, u32)> {
        let mut edges: Vec<(u32, u32, bool, u32)> = mesh
            .triangles
            .iter()
            .enumerate()
            .flat_map(|(t, tri)| {
                (0..3).map(move |k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    (a.min(b), a.max(b), a < b, t as u32)
                })
            })
            .collect();
        edges.sort_unstable();
        edges
    }

    #[test]
    fn sorted_edges_match_a_comparison_sort() {
        let mut mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2);
        // Triangles out of order, a fin on one edge (three triangles), a repeated triangle and a
        // vertex no triangle uses.
        mesh.triangles.reverse();
        let [a, b, _] = mesh.triangles[5];
        let extra = mesh.positions.len() as u32;
        mesh.positions.push(Vec3::new(3.0, 0.0, 0.0));
        mesh.positions.push(Vec3::new(4.0, 0.0, 0.0));
        mesh.triangles.push([b, a, extra]);
        mesh.triangles.push(mesh.triangles[9]);
        let edges = mesh.sorted_edges();
        assert_eq!(edges.len(), 3 * mesh.triangles.len());
        assert_eq!(edges, compared(&mesh));
        assert!(IndexedMesh::default().sorted_edges().is_empty());
    }
}
