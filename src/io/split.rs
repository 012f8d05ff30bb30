//! Non-manifold input made manifold without moving a point.
//!
//! Dual meshers (surface nets, OpenVDB's volume-to-mesh) place one vertex per grid cell, so two
//! sheets of fluid that pass through one cell share a vertex (a bow-tie), and two that share a
//! cell edge share an edge of four triangles. A splash's thin sheets and touching droplets do
//! this on most frames. Such a surface still bounds a solid, only with parts that touch: each
//! non-manifold edge's triangles are paired around it across the solid between them, and each
//! vertex gets one copy per fan of triangles joined across its paired edges. The result is a closed
//! 2-manifold whose parts touch where the file's did, so the tracker sees each touching part as its
//! own component and the topology step decides, like any near-contact, whether they merge.
//!
//! A mesh with an edge it cannot pair (an open boundary, or triangles that disagree on
//! orientation) is left as it is, so validation names that defect rather than a split's result.

use glam::{DVec3, Vec3};

use crate::geometry::Components;
use crate::mesh::IndexedMesh;

/// What [`split_non_manifold`] did.
#[derive(Debug, Default, PartialEq, Eq)]
pub(crate) struct Split {
    /// For every vertex added, the vertex it copies; the copies are numbered after the input's.
    pub copies: Vec<u32>,
    /// Edges of more than two triangles whose triangles were paired.
    pub edges: usize,
}

/// Splits `mesh`'s triangles at non-manifold edges and vertices, renumbering the corners that
/// move to a copy (its other fields are left as they are). Nothing changes for a closed 2-manifold or for a mesh with an
/// edge that cannot be paired.
///
/// Where two parts touch along an edge whose ends each have one fan when paired across the solid
/// (the parts pinch together through both ends), the edge would still carry four triangles; its
/// triangles are then paired across the air instead, which parts the fans, and the split is
/// done again.
pub(crate) fn split_non_manifold(mesh: &mut IndexedMesh) -> Split {
    // A mesh that faces inward (the tracker turns it later, `sequence::orientation`) has its
    // solid where its normals point. Only an edge of more than two triangles asks, so a clean
    // frame does not sum its volume.
    let inward = std::cell::OnceCell::new();
    let inward = || *inward.get_or_init(|| mesh.signed_volume() < 0.0);
    let vertices = mesh.positions.len();
    let mut across_air = Vec::new();
    for _ in 0..MAX_ROUNDS {
        let Some((pairs, edges)) = pair_half_edges(mesh, &across_air, &inward) else {
            return Split::default();
        };
        let (split, copies) = split_fans(vertices, &mesh.triangles, &pairs);
        let source = |v: u32| match (v as usize).checked_sub(vertices) {
            Some(copy) => copies[copy],
            None => v,
        };
        let stuck: Vec<(u32, u32)> = if edges == 0 {
            Vec::new()
        } else {
            crowded_edges(&split)
                .into_iter()
                .map(|(a, b)| {
                    let (a, b) = (source(a), source(b));
                    (a.min(b), a.max(b))
                })
                .filter(|edge| across_air.binary_search(edge).is_err())
                .collect()
        };
        if stuck.is_empty() {
            if copies.is_empty() {
                return Split::default();
            }
            mesh.triangles = split;
            return Split { copies, edges };
        }
        across_air.extend(stuck);
        across_air.sort_unstable();
        across_air.dedup();
    }
    Split::default()
}

/// Pairings tried before a mesh is left as it is: each round re-pairs at least one edge.
const MAX_ROUNDS: usize = 4;

/// `triangles` with every vertex given one copy per fan of corners joined across `pairs`, and the
/// vertex each copy stands for (copies numbered from `vertices` on).
fn split_fans(
    vertices: usize,
    triangles: &[[u32; 3]],
    pairs: &[(u32, u32)],
) -> (Vec<[u32; 3]>, Vec<u32>) {
    // Corner `3t + k` of triangle `t` is joined to the corners of the same vertex across every
    // paired edge: its groups are the vertex's fans.
    let mut fans = Components::new(3 * triangles.len(), &[]);
    for &(f, g) in pairs {
        fans.join(f, next(g));
        fans.join(next(f), g);
    }
    let mut first_fan = vec![u32::MAX; vertices];
    let mut fan_vertex = vec![u32::MAX; 3 * triangles.len()];
    let mut copies = Vec::new();
    let mut split = triangles.to_vec();
    for corner in 0..3 * triangles.len() as u32 {
        let (t, k) = ((corner / 3) as usize, (corner % 3) as usize);
        let v = triangles[t][k];
        let fan = fans.find(corner) as usize;
        if fan_vertex[fan] == u32::MAX {
            fan_vertex[fan] = if first_fan[v as usize] == u32::MAX {
                first_fan[v as usize] = fan as u32;
                v
            } else {
                copies.push(v);
                (vertices + copies.len() - 1) as u32
            };
        }
        split[t][k] = fan_vertex[fan];
    }
    (split, copies)
}

/// The edges of more than two triangles.
fn crowded_edges(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    edges
        .chunk_by(|x, y| x == y)
        .filter(|group| group.len() > 2)
        .map(|group| group[0])
        .collect()
}

/// The corner after `corner` in its triangle.
fn next(corner: u32) -> u32 {
    corner - corner % 3 + (corner + 1) % 3
}

/// Every half-edge paired with one running the other way (half-edge `3t + k` runs from corner `k`
/// of triangle `t` to the next), and how many edges had more than two triangles; `None` when an
/// edge has unequal numbers of triangles each way or cannot be paired around. Edges of more than
/// two triangles pair across the solid, except those in `across_air`; `inward()` (whether the mesh
/// faces inward) swaps the two.
fn pair_half_edges(
    mesh: &IndexedMesh,
    across_air: &[(u32, u32)],
    inward: &dyn Fn() -> bool,
) -> Option<(Vec<(u32, u32)>, usize)> {
    let (positions, triangles) = (&mesh.positions, &mesh.triangles);
    let half_edges: Vec<(u32, u32, u32)> = mesh
        .sorted_edges()
        .into_iter()
        .map(|(a, b, forward, t)| {
            let from = if forward { a } else { b };
            let k = triangles[t as usize].iter().position(|&v| v == from);
            (a, b, 3 * t + k.unwrap_or(0) as u32)
        })
        .collect();
    let origin = |h: u32| triangles[h as usize / 3][h as usize % 3];
    let mut pairs = Vec::with_capacity(half_edges.len() / 2);
    let mut edges = 0;
    for group in half_edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let (a, b) = (group[0].0, group[0].1);
        let forward = group.iter().filter(|e| origin(e.2) == a).count();
        if 2 * forward != group.len() {
            return None;
        }
        if group.len() == 2 {
            let (f, g) = (group[0].2, group[1].2);
            pairs.push(if origin(f) == a { (f, g) } else { (g, f) });
        } else {
            edges += 1;
            let air = across_air.binary_search(&(a, b)).is_ok() != inward();
            pairs.extend(pair_around(positions, triangles, a, b, group, air)?);
        }
    }
    Some((pairs, edges))
}

/// Pairs the half-edges of one edge `(a, b)` with more than two triangles, each `(a → b, b → a)`,
/// across the solid between them (or across the air).
///
/// Around the edge, rotating positively about `b − a`, a triangle running `a → b` faces (its
/// normal points) towards rising angles, and one running `b → a` towards falling angles. So a
/// `b → a` triangle's solid side looks towards rising angles, and its partner across the solid
/// is the next triangle that way, which must run `a → b`; across the air, an `a → b` triangle's
/// partner is the next one. Triangles that do not alternate so (they cross each other at the
/// edge) give `None`.
fn pair_around(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    a: u32,
    b: u32,
    group: &[(u32, u32, u32)],
    across_air: bool,
) -> Option<Vec<(u32, u32)>> {
    let p = |v: u32| positions[v as usize].as_dvec3();
    let (pa, pb) = (p(a), p(b));
    let axis = (pb - pa).normalize_or_zero();
    if axis == DVec3::ZERO {
        return None;
    }
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let mut around: Vec<(f64, u32, bool)> = group
        .iter()
        .map(|&(_, _, h)| {
            let tri = triangles[h as usize / 3];
            let k = h as usize % 3;
            let w = p(tri[(k + 2) % 3]) - pa;
            (w.dot(e2).atan2(w.dot(e1)), h, tri[k] == a)
        })
        .collect();
    around.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    // Each pair is a triangle of the kind that opens the wedge and the next one around.
    let opens = across_air;
    let start = usize::from(around[0].2 != opens);
    let n = around.len();
    let mut pairs = Vec::with_capacity(n / 2);
    for i in (start..start + n).step_by(2) {
        let (first, second) = (around[i % n], around[(i + 1) % n]);
        if first.2 != opens || second.2 == opens {
            return None;
        }
        let (forward, back) = if opens {
            (first, second)
        } else {
            (second, first)
        };
        pairs.push((forward.1, back.1));
    }
    Some(pairs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::cube::CORNER_OFFSETS;
    use glam::UVec3;

    /// Two tetrahedra touching at vertex 0 (`tests/data/touching/tetrahedra_at_a_vertex.obj`).
    fn bowtie() -> IndexedMesh {
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, 0.0, -1.0),
        ];
        let triangles = vec![
            [0, 2, 1],
            [0, 1, 3],
            [0, 3, 2],
            [1, 2, 3],
            [0, 4, 5],
            [0, 6, 4],
            [0, 5, 6],
            [4, 6, 5],
        ];
        IndexedMesh::new(positions, triangles)
    }

    #[test]
    fn a_bow_tie_vertex_gets_one_copy_per_fan() {
        let mut mesh = bowtie();
        let split = split_non_manifold(&mut mesh);
        assert_eq!(split.copies, vec![0]);
        assert_eq!(split.edges, 0);
        let triangles = mesh.triangles;
        assert_eq!(&triangles[..4], &bowtie().triangles[..4]);
        assert_eq!(triangles[4], [7, 4, 5]);
        assert_eq!(triangles[5], [7, 6, 4]);
        assert_eq!(triangles[6], [7, 5, 6]);
    }

    #[test]
    fn a_closed_manifold_is_left_alone() {
        let mut mesh = bowtie();
        mesh.triangles.truncate(4);
        let before = mesh.clone();
        assert_eq!(split_non_manifold(&mut mesh), Split::default());
        assert_eq!(mesh, before);
    }

    #[test]
    fn an_open_mesh_is_left_alone() {
        let mut mesh = bowtie();
        mesh.triangles.remove(0);
        let before = mesh.clone();
        assert_eq!(split_non_manifold(&mut mesh), Split::default());
        assert_eq!(mesh, before);
    }

    /// Two unit cubes touching along the z axis edge through the origin, each face of each (corners
    /// numbered as a grid cell's) split along the diagonal through its least corner: four triangles
    /// meet along the shared edge.
    fn cubes_on_an_edge() -> IndexedMesh {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for offset in [Vec3::ZERO, Vec3::new(-1.0, -1.0, 0.0)] {
            let base = positions.len() as u32;
            positions.extend(
                CORNER_OFFSETS.map(|c| offset + UVec3::from(c.map(|x| x as u32)).as_vec3()),
            );
            // A grid cell's faces (`grid::cube::FACE_CORNERS`) in the order −z, +z, −y, +y, −x,
            // +x, which fixes the order the split meets the shared corners in (the tests read it).
            let quads = [
                [0, 2, 3, 1],
                [4, 5, 7, 6],
                [0, 1, 5, 4],
                [2, 6, 7, 3],
                [0, 4, 6, 2],
                [1, 3, 7, 5],
            ];
            for q in quads {
                triangles.push([base + q[0], base + q[1], base + q[2]]);
                triangles.push([base + q[0], base + q[2], base + q[3]]);
            }
        }
        // Weld the second cube's edge (x = y = 0 at its corners 3 and 7) onto the first's (0, 4).
        for tri in &mut triangles {
            for v in tri.iter_mut() {
                *v = match *v {
                    11 => 0,
                    15 => 4,
                    v => v,
                };
            }
        }
        IndexedMesh::new(positions, triangles)
    }

    #[test]
    fn an_edge_of_four_triangles_is_paired_across_each_solid() {
        let mut mesh = cubes_on_an_edge();
        let split = split_non_manifold(&mut mesh);
        assert_eq!(split.edges, 1);
        assert_eq!(split.copies, vec![0, 4]);
        let triangles = mesh.triangles;
        let first: Vec<u32> = triangles[..12].iter().flatten().copied().collect();
        let second: Vec<u32> = triangles[12..].iter().flatten().copied().collect();
        assert!(first.iter().all(|&v| v < 8));
        assert!(
            second
                .iter()
                .all(|&v| (8..18).contains(&v) && v != 11 && v != 15)
        );
    }

    #[test]
    fn an_inward_mesh_pairs_across_its_solid_too() {
        let mut mesh = cubes_on_an_edge();
        for tri in &mut mesh.triangles {
            tri.swap(1, 2);
        }
        let split = split_non_manifold(&mut mesh);
        assert_eq!((split.edges, split.copies), (1, vec![0, 4]));
        assert!(mesh.triangles[..12].iter().flatten().all(|&v| v < 8));
    }
}
