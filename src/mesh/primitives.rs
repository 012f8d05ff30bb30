//! Closed analytic meshes for tests, benchmarks and examples: their topology and geometry are known
//! exactly, which is what analytic tests need.

use super::IndexedMesh;
use glam::Vec3;
use std::collections::HashMap;

impl IndexedMesh {
    /// This mesh and `other` side by side as one, `other`'s vertices numbered after this one's
    /// (positions and triangles only): scenes of several shapes.
    pub fn joined(&self, other: &IndexedMesh) -> IndexedMesh {
        let offset = self.positions.len() as u32;
        let mut positions = self.positions.clone();
        positions.extend(&other.positions);
        let mut triangles = self.triangles.clone();
        triangles.extend(other.triangles.iter().map(|t| t.map(|v| v + offset)));
        IndexedMesh::new(positions, triangles)
    }

    /// Every triangle split into four at its edges' midpoints, `times` times: the same surface,
    /// sampled finer (edges shared by two triangles get one midpoint).
    pub fn split_flat(&self, times: u32) -> IndexedMesh {
        let mut positions = self.positions.clone();
        let mut triangles = self.triangles.clone();
        for _ in 0..times {
            triangles = split_in_four(&mut positions, &triangles, |a, b| (a + b) * 0.5);
        }
        IndexedMesh::new(positions, triangles)
    }

    /// Torus around the z axis with major radius `major`, tube radius `minor`, `nu × nv` quads split
    /// into triangles (genus 1, χ = 0).
    pub fn torus(major: f32, minor: f32, nu: usize, nv: usize) -> IndexedMesh {
        let mut positions = Vec::with_capacity(nu * nv);
        for i in 0..nu {
            let u = i as f32 / nu as f32 * std::f32::consts::TAU;
            for j in 0..nv {
                let v = j as f32 / nv as f32 * std::f32::consts::TAU;
                let r = major + minor * v.cos();
                positions.push(Vec3::new(r * u.cos(), r * u.sin(), minor * v.sin()));
            }
        }
        let idx = |i: usize, j: usize| ((i % nu) * nv + (j % nv)) as u32;
        let mut triangles = Vec::with_capacity(2 * nu * nv);
        for i in 0..nu {
            for j in 0..nv {
                let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        IndexedMesh::new(positions, triangles)
    }

    /// Sphere of `radius` about `center` from an icosahedron subdivided `levels` times
    /// (20·4^levels triangles, vertices exactly on the sphere up to rounding).
    pub fn icosphere(center: Vec3, radius: f32, levels: u32) -> IndexedMesh {
        let t = (1.0 + 5.0f32.sqrt()) / 2.0;
        let mut positions: Vec<Vec3> = [
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ]
        .iter()
        .map(|p| Vec3::from_array(*p).normalize())
        .collect();
        let mut triangles: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        for _ in 0..levels {
            triangles = split_in_four(&mut positions, &triangles, |a, b| (a + b).normalize());
        }
        for p in &mut positions {
            *p = center + *p * radius;
        }
        IndexedMesh::new(positions, triangles)
    }
}

/// `triangles` split into four each, the new vertex of an edge `(x, y)` at `middle(x, y)` appended
/// to `positions` once per edge.
fn split_in_four(
    positions: &mut Vec<Vec3>,
    triangles: &[[u32; 3]],
    middle: impl Fn(Vec3, Vec3) -> Vec3,
) -> Vec<[u32; 3]> {
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut next = Vec::with_capacity(triangles.len() * 4);
    for &[a, b, c] in triangles {
        let mut mid = |x: u32, y: u32| -> u32 {
            *midpoints.entry((x.min(y), x.max(y))).or_insert_with(|| {
                positions.push(middle(positions[x as usize], positions[y as usize]));
                (positions.len() - 1) as u32
            })
        };
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    next
}
