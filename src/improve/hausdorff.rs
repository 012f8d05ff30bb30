//! Distance from points to a triangle mesh through a uniform hash grid, and the one-sided Hausdorff
//! distance built on it: how far improvement moved the surface (improved → original).

use crate::geometry::point_triangle_distance;
use crate::mesh::IndexedMesh;
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;

/// Rings searched before a query far from the surface falls back to every triangle: the shell of
/// ring `r` has about `24 r²` cells, so beyond a few rings the grid stops paying for itself.
const MAX_RING: i32 = 4;

/// Triangles of a mesh bucketed by the grid cells their bounding boxes overlap.
pub struct SurfaceDistance<'a> {
    mesh: &'a IndexedMesh,
    cell: f32,
    buckets: HashMap<IVec3, Vec<u32>>,
    /// The range of occupied cells: once a search covers it, nothing is left to find.
    lo: IVec3,
    hi: IVec3,
}

impl<'a> SurfaceDistance<'a> {
    /// Buckets `mesh` with cells twice its mean edge length, so a triangle spans few cells.
    pub fn new(mesh: &'a IndexedMesh) -> Self {
        let mean = mesh.mean_edge_length();
        let cell = if mean > 0.0 { 2.0 * mean } else { 1.0 };
        let mut buckets: HashMap<IVec3, Vec<u32>> = HashMap::new();
        let (mut lo, mut hi) = (IVec3::MAX, IVec3::MIN);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let p = tri.map(|v| mesh.positions[v as usize]);
            let (min, max) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
            let (a, b) = (cell_of(min, cell), cell_of(max, cell));
            lo = lo.min(a);
            hi = hi.max(b);
            for z in a.z..=b.z {
                for y in a.y..=b.y {
                    for x in a.x..=b.x {
                        buckets
                            .entry(IVec3::new(x, y, z))
                            .or_default()
                            .push(t as u32);
                    }
                }
            }
        }
        Self {
            mesh,
            cell,
            buckets,
            lo,
            hi,
        }
    }

    /// Distance from `p` to the nearest triangle (∞ for a mesh without triangles). Rings of cells are
    /// searched outward until the nearest triangle found is closer than anything outside the searched
    /// block of cells can be.
    pub fn distance(&self, p: Vec3) -> f32 {
        if self.buckets.is_empty() {
            return f32::INFINITY;
        }
        let center = cell_of(p, self.cell);
        let last_ring = (center - self.lo)
            .abs()
            .max(self.hi - center)
            .max_element()
            .max(0);
        let below = p - center.as_vec3() * self.cell;
        let above = (center + IVec3::ONE).as_vec3() * self.cell - p;
        let margin = below.min(above).min_element().max(0.0);
        let nearest = |tris: &[u32]| {
            tris.iter()
                .map(|&t| {
                    let [a, b, c] =
                        self.mesh.triangles[t as usize].map(|v| self.mesh.positions[v as usize]);
                    point_triangle_distance(p, a, b, c)
                })
                .fold(f32::INFINITY, f32::min)
        };
        let mut best = f32::INFINITY;
        for ring in 0..=last_ring.min(MAX_RING) {
            for tris in self.ring(center, ring) {
                best = best.min(nearest(tris));
            }
            if best <= margin + ring as f32 * self.cell {
                return best;
            }
        }
        if last_ring > MAX_RING {
            let all: Vec<u32> = (0..self.mesh.triangles.len() as u32).collect();
            best = best.min(nearest(&all));
        }
        best
    }

    /// The non-empty buckets on the surface of the cube of cells at Chebyshev distance `ring`.
    fn ring(&self, center: IVec3, ring: i32) -> impl Iterator<Item = &Vec<u32>> + '_ {
        (-ring..=ring).flat_map(move |z| {
            (-ring..=ring).flat_map(move |y| {
                (-ring..=ring).filter_map(move |x| {
                    let offset = IVec3::new(x, y, z);
                    if offset.abs().max_element() != ring {
                        return None;
                    }
                    self.buckets.get(&(center + offset))
                })
            })
        })
    }
}

fn cell_of(p: Vec3, cell: f32) -> IVec3 {
    (p / cell).floor().as_ivec3()
}

/// One-sided Hausdorff distance from `from` to `to`: the largest distance from a point of `from` to
/// the surface `to`, sampled at every vertex, edge midpoint and face centroid of `from` and at the
/// points halfway from each centroid to its corners.
pub fn one_sided_hausdorff(from: &IndexedMesh, to: &IndexedMesh) -> f32 {
    let target = SurfaceDistance::new(to);
    from.triangles
        .par_iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|v| from.positions[v as usize]);
            let g = (a + b + c) / 3.0;
            [
                a,
                b,
                c,
                (a + b) * 0.5,
                (b + c) * 0.5,
                (c + a) * 0.5,
                g,
                (g + a) * 0.5,
                (g + b) * 0.5,
                (g + c) * 0.5,
            ]
            .into_iter()
            .map(|p| target.distance(p))
            .fold(0.0f32, f32::max)
        })
        .reduce(|| 0.0, f32::max)
}
