//! Nearest triangles within a bound from a uniform grid of cells instead of a tree.
//!
//! The sub-grid match measures every input vertex against the tracked surface within a bound of
//! under one edge (twice a frame on a torn fluid frame); a tree over the 30k–40k triangles of a
//! dam-break frame took 20 ms to build on one core, three times what its queries took. Here each
//! triangle is listed in the cells of spacing one mean edge length that its box meets, a counting
//! pass and a filling pass; a query reads the cell of its point first, then the cells that the
//! cube of half-side the nearest distance found there meets, each triangle once. The answer is the
//! one [`closest_points`](super::closest_points) gives on the CPU against a tree over the same
//! mesh: the nearest triangle within the bound, ties to the lower index, found with the same
//! point–triangle arithmetic, at the same distance.

use glam::{IVec3, Vec3};
use rayon::prelude::*;

use super::ProjectError;
use super::bvh::checked_bounds;
use super::cpu::closest_point::closest_on_triangle;
use super::options::absolute_distance;
use super::shading::mean_edge_length;
use crate::kernels::shared::BvhTriangle;
use crate::mesh::IndexedMesh;

/// The width of a cell in mean edge lengths: on a dam-break frame (33.5k triangles, 24k points
/// within 0.75 edges) the queries took 11.0 ms at 1 edge, 12.1 ms at 1.5, 14.8 ms at 2 and 17.5 ms
/// at 3 (one core), the tree's 13.5 ms; the listing about 5 ms at each, the tree's build 22 ms.
const CELL_EDGES: f32 = 1.0;

/// Most grid cells per triangle; a mesh spread thinly over a large box gets wider cells instead.
const CELLS_PER_TRIANGLE: usize = 8;

/// Share by which the cube a query searches and the boxes it compares are widened, so rounding
/// never leaves out a cell or a triangle holding the nearest point.
const MARGIN: f32 = 1e-3;

/// A mesh's triangles listed by the cells their boxes meet.
#[derive(Debug)]
pub struct Cells {
    /// The triangles in the mesh's order; `id` is the index.
    triangles: Vec<BvhTriangle>,
    /// The spacing of the cells and the lowest cell of the grid.
    cell: f32,
    low: IVec3,
    /// Cells along each axis.
    size: IVec3,
    /// The lowest cell each triangle's box meets.
    lowest: Vec<IVec3>,
    /// The triangles of cell `i` (x fastest) are `listed[first[i]..first[i + 1]]`.
    first: Vec<u32>,
    listed: Vec<u32>,
    mean_edge_length: f32,
}

impl Cells {
    /// Lists the triangles of `mesh`, which needs what a [`Bvh`](super::Bvh) needs: at least one
    /// triangle, indices in range and finite coordinates.
    pub fn new(mesh: &IndexedMesh) -> Result<Self, ProjectError> {
        let boxes = checked_bounds(mesh)?;
        let mean_edge_length = mean_edge_length(mesh);
        let (lo, hi) = boxes.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), b| (lo.min(b.min), hi.max(b.max)),
        );
        let most = CELLS_PER_TRIANGLE * boxes.len().max(1024);
        let mut cell = (CELL_EDGES * mean_edge_length).max((hi - lo).max_element() / 1024.0);
        if !(cell.is_finite() && cell > 0.0) {
            cell = 1.0;
        }
        while volume(key(hi, cell) - key(lo, cell) + IVec3::ONE) > most {
            cell *= 1.5;
        }
        let low = key(lo, cell);
        let size = key(hi, cell) - low + IVec3::ONE;
        let ranges: Vec<(IVec3, IVec3)> = boxes
            .par_iter()
            .map(|b| (key(b.min, cell), key(b.max, cell)))
            .collect();
        let cells = volume(size);
        let mut first = vec![0u32; cells + 1];
        for &(a, b) in &ranges {
            for c in between(a, b) {
                first[index(c, low, size) + 1] += 1;
            }
        }
        for i in 0..cells {
            first[i + 1] += first[i];
        }
        let mut fill = first.clone();
        let mut listed = vec![0u32; first[cells] as usize];
        for (t, &(a, b)) in ranges.iter().enumerate() {
            for c in between(a, b) {
                let slot = &mut fill[index(c, low, size)];
                listed[*slot as usize] = t as u32;
                *slot += 1;
            }
        }
        let triangles = mesh
            .triangles
            .par_iter()
            .enumerate()
            .map(|(t, tri)| BvhTriangle::new(tri.map(|v| mesh.positions[v as usize]), t as u32))
            .collect();
        Ok(Self {
            triangles,
            cell,
            low,
            size,
            lowest: ranges.into_iter().map(|(a, _)| a).collect(),
            first,
            listed,
            mean_edge_length,
        })
    }

    /// The mesh's mean edge length: the unit of `max_distance` in [`Cells::nearest`].
    pub fn mean_edge_length(&self) -> f32 {
        self.mean_edge_length
    }

    /// For each point, the nearest triangle within `max_distance` mean edge lengths (its index in
    /// the mesh) and its distance: `None` beyond it, and for a point that is not finite.
    pub fn nearest(
        &self,
        points: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<Option<(u32, f32)>>, ProjectError> {
        let reach = absolute_distance(max_distance, self.mean_edge_length)?;
        Ok(points
            .par_iter()
            .map(|&p| self.nearest_one(p, reach))
            .collect())
    }

    fn nearest_one(&self, p: Vec3, reach: f32) -> Option<(u32, f32)> {
        if !p.is_finite() {
            return None;
        }
        let mut best = (reach * reach, u32::MAX);
        let own = key(p, self.cell);
        if self.holds(own) {
            self.search(own, p, &mut best, None);
        }
        let half = best.0.sqrt() * (1.0 + MARGIN) + MARGIN * self.cell;
        let (a, b) = (
            key(p - Vec3::splat(half), self.cell).max(self.low),
            key(p + Vec3::splat(half), self.cell).min(self.low + self.size - IVec3::ONE),
        );
        for c in between(a, b).filter(|&c| c != own) {
            self.search(c, p, &mut best, Some(a));
        }
        let (_, id) = best;
        let tri = self.triangles.get(id as usize)?;
        Some((id, (p - closest_on_triangle(p, tri).point).length()))
    }

    fn holds(&self, c: IVec3) -> bool {
        let c = c - self.low;
        c.cmpge(IVec3::ZERO).all() && c.cmplt(self.size).all()
    }

    /// Tries the triangles of cell `c` on `best` (squared distance, index). Searching the cells
    /// from `from` up, a triangle is tried only in the first of them that it meets.
    fn search(&self, c: IVec3, p: Vec3, best: &mut (f32, u32), from: Option<IVec3>) {
        let i = index(c, self.low, self.size);
        for &t in &self.listed[self.first[i] as usize..self.first[i + 1] as usize] {
            if let Some(from) = from
                && self.lowest[t as usize].max(from) != c
            {
                continue;
            }
            let tri = &self.triangles[t as usize];
            let [x, y, z] = tri.corners();
            let (lo, hi) = (x.min(y).min(z), x.max(y).max(z));
            let gap = (lo - p).max(p - hi).max(Vec3::ZERO);
            if gap.length_squared() > best.0 * (1.0 + MARGIN) {
                continue;
            }
            let q = closest_on_triangle(p, tri).point;
            let d2 = (p - q).length_squared();
            if d2 < best.0 || (d2 == best.0 && t < best.1) {
                *best = (d2, t);
            }
        }
    }
}

/// The cell holding `p`, of spacing `cell`.
fn key(p: Vec3, cell: f32) -> IVec3 {
    (p / cell).floor().as_ivec3()
}

/// The number of cells in a block of `size` cells along each axis.
fn volume(size: IVec3) -> usize {
    size.x as usize * size.y as usize * size.z as usize
}

/// Where cell `c` lies among the `size` cells from `low` on, x fastest.
fn index(c: IVec3, low: IVec3, size: IVec3) -> usize {
    let c = c - low;
    (c.x + size.x * (c.y + size.y * c.z)) as usize
}

/// The cells from `a` to `b` (both included), x fastest.
fn between(a: IVec3, b: IVec3) -> impl Iterator<Item = IVec3> {
    (a.z..=b.z).flat_map(move |z| {
        (a.y..=b.y).flat_map(move |y| (a.x..=b.x).map(move |x| IVec3::new(x, y, z)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compute::Backend;
    use crate::project::{Bvh, closest_points};
    use glam::Quat;

    /// Points around a bumpy sphere, some on it, some off by up to two edges, some far.
    fn bumpy() -> (IndexedMesh, Vec<Vec3>) {
        let mut mesh = IndexedMesh::icosphere(Vec3::new(0.3, -0.2, 0.1), 1.0, 4);
        for p in &mut mesh.positions {
            let bump = (5.0 * p.x).sin() * (4.0 * p.y).cos() * (3.0 * p.z).sin();
            *p *= 1.0 + 0.1 * bump;
        }
        let turn = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.4);
        let mut points: Vec<Vec3> = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3)
            .positions
            .iter()
            .enumerate()
            .map(|(i, &p)| turn * p * (0.9 + 0.2 * ((i * 7919) % 101) as f32 / 100.0))
            .collect();
        points.extend(mesh.positions.iter().step_by(7).copied());
        points.extend([
            Vec3::splat(5.0),
            Vec3::splat(f32::NAN),
            Vec3::new(0.3, -0.2, 0.1),
        ]);
        (mesh, points)
    }

    /// The grid finds the tree's nearest triangle at the tree's distance, at every bound, on and
    /// off the surface, and nothing where the tree finds nothing.
    #[test]
    fn the_cells_answer_as_the_tree_does() {
        let (mesh, points) = bumpy();
        let bvh = Bvh::build_unsigned(&mesh).unwrap();
        let cells = Cells::new(&mesh).unwrap();
        assert_eq!(cells.mean_edge_length(), bvh.mean_edge_length());
        let mut found = 0;
        for reach in [0.0, 0.3, 0.75, 2.0, 40.0, f32::INFINITY] {
            let tree = closest_points(&Backend::Cpu, &bvh, &points, reach).unwrap();
            let grid = cells.nearest(&points, reach).unwrap();
            for (t, g) in tree.iter().zip(&grid) {
                let expected = t.hit_triangle().map(|k| (k, t.distance.abs()));
                assert_eq!(*g, expected);
                found += usize::from(g.is_some());
            }
        }
        assert!(found > 3 * points.len(), "too few hits to compare: {found}");
    }

    /// A mesh whose triangles lie far apart gets wider cells, not a huge grid, and answers alike.
    #[test]
    fn far_apart_triangles_widen_the_cells() {
        let mut mesh = IndexedMesh::icosphere(Vec3::ZERO, 0.01, 1);
        let far = IndexedMesh::icosphere(Vec3::splat(1000.0), 0.01, 1);
        let offset = mesh.positions.len() as u32;
        mesh.positions.extend(far.positions);
        mesh.triangles
            .extend(far.triangles.iter().map(|t| t.map(|v| v + offset)));
        let cells = Cells::new(&mesh).unwrap();
        assert!(cells.first.len() <= CELLS_PER_TRIANGLE * 1024 + 1);
        let bvh = Bvh::build_unsigned(&mesh).unwrap();
        let points = [Vec3::splat(0.02), Vec3::splat(999.99), Vec3::splat(500.0)];
        let tree = closest_points(&Backend::Cpu, &bvh, &points, f32::INFINITY).unwrap();
        let grid = cells.nearest(&points, f32::INFINITY).unwrap();
        for (t, g) in tree.iter().zip(&grid) {
            assert_eq!(*g, t.hit_triangle().map(|k| (k, t.distance.abs())));
        }
    }
}
