//! Independent references for the grid tests: winding numbers by solid angles and distances by
//! brute force, both in f64 on the unsnapped mesh, plus small mesh builders.

use glam::{DVec3, Vec3};
use surftrack::grid::GridFrame;
use surftrack::mesh::IndexedMesh;

/// SplitMix64: a small deterministic generator, so failures reproduce exactly.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

fn corners(mesh: &IndexedMesh, t: usize) -> [DVec3; 3] {
    mesh.triangles[t].map(|v| mesh.positions[v as usize].as_dvec3())
}

/// Winding number of `p` with respect to the closed mesh: the sum of the signed solid angles of its
/// triangles (Van Oosterom & Strackee) over 4π, rounded.
pub fn winding_reference(mesh: &IndexedMesh, p: DVec3) -> i32 {
    let mut total = 0.0;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = corners(mesh, t).map(|x| x - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        total += 2.0 * num.atan2(den);
    }
    (total / (4.0 * std::f64::consts::PI)).round() as i32
}

/// Distance from `p` to triangle `abc` (Ericson, Real-Time Collision Detection §5.1.5), in f64.
pub fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + ab * (d1 / (d1 - d3)))).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + ac * (d2 / (d2 - d6)))).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

/// Distance from `p` to the mesh, by brute force.
pub fn distance_reference(mesh: &IndexedMesh, p: DVec3) -> f64 {
    (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = corners(mesh, t);
            point_triangle_distance(p, a, b, c)
        })
        .fold(f64::INFINITY, f64::min)
}

/// World position of a grid corner, in f64.
pub fn corner_world(frame: &GridFrame, c: [i32; 3]) -> DVec3 {
    frame.origin().as_dvec3() + DVec3::from_array(c.map(f64::from)) * f64::from(frame.spacing())
}

/// Every corner of the box `lo ..= hi`.
pub fn box_corners(lo: [i32; 3], hi: [i32; 3]) -> impl Iterator<Item = [i32; 3]> {
    (lo[2]..=hi[2]).flat_map(move |k| {
        (lo[1]..=hi[1]).flat_map(move |j| (lo[0]..=hi[0]).map(move |i| [i, j, k]))
    })
}

/// The mesh's corner box in cells, padded by `pad`.
pub fn cell_box(frame: &GridFrame, mesh: &IndexedMesh, pad: i32) -> ([i32; 3], [i32; 3]) {
    let mut lo = [i32::MAX; 3];
    let mut hi = [i32::MIN; 3];
    for &p in &mesh.positions {
        let g = frame.to_grid(p);
        for a in 0..3 {
            lo[a] = lo[a].min(g[a].floor() as i32 - pad);
            hi[a] = hi[a].max(g[a].ceil() as i32 + pad);
        }
    }
    (lo, hi)
}

/// The mesh with every triangle reversed (inside out).
pub fn flipped(mesh: &IndexedMesh) -> IndexedMesh {
    IndexedMesh::new(
        mesh.positions.clone(),
        mesh.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect(),
    )
}

/// Disjoint union of meshes.
pub fn union(meshes: &[IndexedMesh]) -> IndexedMesh {
    meshes
        .iter()
        .fold(IndexedMesh::default(), |all, m| all.joined(m))
}

/// The closed surface of the box `lo ..= hi` (in cells, integers) with one vertex on every grid
/// corner of its faces: every vertex on three grid planes, every edge along a grid line or a face
/// diagonal, triangles outward.
pub fn grid_box(frame: &GridFrame, lo: [i32; 3], hi: [i32; 3]) -> IndexedMesh {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut vertex = |c: [i32; 3], positions: &mut Vec<Vec3>| -> u32 {
        *index.entry(c).or_insert_with(|| {
            positions.push(corner_world(frame, c).as_vec3());
            (positions.len() - 1) as u32
        })
    };
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for (side, plane) in [(-1, lo[axis]), (1, hi[axis])] {
            for a in lo[u]..hi[u] {
                for b in lo[v]..hi[v] {
                    let at = |du: i32, dv: i32| {
                        let mut c = [0; 3];
                        c[axis] = plane;
                        c[u] = a + du;
                        c[v] = b + dv;
                        c
                    };
                    let q =
                        [at(0, 0), at(1, 0), at(1, 1), at(0, 1)].map(|c| vertex(c, &mut positions));
                    // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
                    if side > 0 {
                        triangles.push([q[0], q[1], q[2]]);
                        triangles.push([q[0], q[2], q[3]]);
                    } else {
                        triangles.push([q[0], q[2], q[1]]);
                        triangles.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    IndexedMesh::new(positions, triangles)
}
