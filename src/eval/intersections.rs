//! Triangles of a tracked frame that pass through each other. A surface that crosses itself is
//! still a closed 2-manifold, so validity does not see it, but a renderer does (refraction through
//! a fluid turns every crossing into a visible seam). The inputs of a marching-cubes mesher never
//! cross themselves; the count says whether tracking made the frame do so.

use glam::DVec3;

use crate::mesh::IndexedMesh;

/// Pairs of triangles without a common corner where an edge of one passes through the interior of
/// the other (a crossing of two surfaces gives at least one such pair; touching and coplanar
/// overlaps are not counted).
pub fn intersecting_pairs(mesh: &IndexedMesh) -> usize {
    let p = |v: u32| mesh.positions[v as usize].as_dvec3();
    let corners: Vec<[DVec3; 3]> = mesh.triangles.iter().map(|t| t.map(p)).collect();
    let boxes: Vec<(DVec3, DVec3)> = corners
        .iter()
        .map(|c| (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2])))
        .collect();
    let cell = f64::from(mesh.mean_edge_length()) * 2.0;
    if !(cell.is_finite() && cell > 0.0) {
        return 0;
    }
    // Broad phase: each triangle in every cell its box meets; candidates share a cell.
    let index = |x: f64| (x / cell).floor() as i64;
    let mut entries: Vec<([i64; 3], u32)> = Vec::new();
    for (t, (lo, hi)) in boxes.iter().enumerate() {
        for x in index(lo.x)..=index(hi.x) {
            for y in index(lo.y)..=index(hi.y) {
                for z in index(lo.z)..=index(hi.z) {
                    entries.push(([x, y, z], t as u32));
                }
            }
        }
    }
    entries.sort_unstable();
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for group in entries.chunk_by(|a, b| a.0 == b.0) {
        for (k, &(_, a)) in group.iter().enumerate() {
            for &(_, b) in &group[k + 1..] {
                let (ta, tb) = (mesh.triangles[a as usize], mesh.triangles[b as usize]);
                let (ba, bb) = (boxes[a as usize], boxes[b as usize]);
                let overlap = ba.0.cmple(bb.1).all() && bb.0.cmple(ba.1).all();
                if overlap && !ta.iter().any(|v| tb.contains(v)) {
                    pairs.push((a.min(b), a.max(b)));
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
        .iter()
        .filter(|&&(a, b)| {
            let (ca, cb) = (&corners[a as usize], &corners[b as usize]);
            edges_pierce(ca, cb) || edges_pierce(cb, ca)
        })
        .count()
}

/// Whether an edge of triangle `a` passes through the interior of triangle `b`.
fn edges_pierce(a: &[DVec3; 3], b: &[DVec3; 3]) -> bool {
    (0..3).any(|k| segment_pierces(a[k], a[(k + 1) % 3], b))
}

/// Whether the open segment `p0 p1` passes through the interior of triangle `t`
/// (Möller–Trumbore, with a relative margin so that touching does not count).
fn segment_pierces(p0: DVec3, p1: DVec3, t: &[DVec3; 3]) -> bool {
    const MARGIN: f64 = 1e-7;
    let d = p1 - p0;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() <= 1e-12 * e1.length() * e2.length() * d.length() {
        return false;
    }
    let s = p0 - t[0];
    let u = s.dot(h) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let along = e2.dot(q) / det;
    u > MARGIN && v > MARGIN && u + v < 1.0 - MARGIN && along > MARGIN && along < 1.0 - MARGIN
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_closed_sphere_does_not_cross_itself() {
        let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        assert_eq!(intersecting_pairs(&sphere), 0);
    }

    #[test]
    fn two_spheres_through_each_other_cross_and_apart_do_not() {
        // Off the axis: spheres mirrored about a plane would cross edge on edge there.
        let sphere = |x: f32| IndexedMesh::icosphere(Vec3::new(x, 0.23 * x, 0.17 * x), 1.0, 2);
        assert!(intersecting_pairs(&sphere(0.0).joined(&sphere(1.1))) > 0);
        assert_eq!(intersecting_pairs(&sphere(0.0).joined(&sphere(2.2))), 0);
    }

    #[test]
    fn an_edge_through_a_triangle_is_one_pair_and_a_shared_corner_none() {
        let positions = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.5, 0.5, -1.0),
            Vec3::new(0.5, 0.5, 1.0),
            Vec3::new(0.6, 0.4, 1.0),
        ];
        let crossing = IndexedMesh::new(positions.clone(), vec![[0, 1, 2], [3, 4, 5]]);
        assert_eq!(intersecting_pairs(&crossing), 1);
        let sharing = IndexedMesh::new(positions, vec![[0, 1, 2], [0, 4, 5]]);
        assert_eq!(intersecting_pairs(&sharing), 0);
    }
}
