//! Which cell faces each mesh edge pierces and which cells each triangle overlaps: the records the
//! cutting step splits along (thesis §3.4.2 and appendix A; "type 2" vertices of §3.4.5).
//!
//! Decided with the same perturbation as the crossings ([`super::predicates`]), so the records
//! describe one configuration: walking a mesh edge through its faces leads from its first endpoint's
//! cell to its second's, and a triangle crossing a grid edge overlaps all four cells around it
//! (Birger's check, thesis §3.4.2). Under the perturbation a triangle meets a cell exactly when a
//! vertex lies in it, one of its edges pierces a face of it, or it crosses an edge of it, so the
//! union of those three gives the overlap without any further test.

use glam::IVec3;
use rayon::prelude::*;

use super::cell_box::CellBox;
use super::lattice::{LatticeMesh, cell_key, key_cell};
use super::predicates::{LocalSegment, cross_axes};
use super::sparse::{Crossings, row_starts};
use crate::kernels::shared::GridCrossing;

/// A mesh edge piercing a cell face: a "type 2" point of the cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeFace {
    /// The mesh edge's endpoints, smaller vertex index first.
    pub edge: [u32; 2],
    /// Axis the face is perpendicular to.
    pub axis: usize,
    /// The cell whose lower `axis` face is pierced; the other cell is one step down along `axis`.
    pub cell: [i32; 3],
    /// Position along the edge from `edge[0]`, in `(0, 1)`.
    pub s: f32,
    /// `edge[0]` lies below the face (in the cell one step down), `edge[1]` above.
    pub upward: bool,
}

impl EdgeFace {
    /// The two cells sharing the face: below, then above.
    pub fn cells(&self) -> [[i32; 3]; 2] {
        let mut below = self.cell;
        below[self.axis] -= 1;
        [below, self.cell]
    }
}

/// Every undirected edge of the mesh once, sorted.
pub fn mesh_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut keys: Vec<u64> = triangles
        .par_iter()
        .flat_map_iter(|&[a, b, c]| {
            [[a, b], [b, c], [c, a]].map(|[p, q]| u64::from(p.min(q)) << 32 | u64::from(p.max(q)))
        })
        .collect();
    keys.par_sort_unstable();
    keys.dedup();
    keys.par_iter()
        .map(|&k| [(k >> 32) as u32, k as u32])
        .collect()
}

/// Every face crossing of every mesh edge, edge by edge (in [`mesh_edges`] order) and in order
/// along each edge from its smaller vertex.
pub fn edge_faces(mesh: &LatticeMesh) -> Vec<EdgeFace> {
    let edges = mesh_edges(mesh.triangles());
    let per_block: Vec<Vec<EdgeFace>> = edges
        .par_chunks(1024)
        .map(|block| {
            let mut out = Vec::new();
            let mut planes: Vec<(usize, i32)> = Vec::new();
            for &edge in block {
                let [p, q] = edge.map(|v| mesh.points()[v as usize]);
                if p.cell == q.cell {
                    continue;
                }
                let seg = LocalSegment::new(&p, &q);
                planes.clear();
                for axis in 0..3 {
                    let (a, b) = (p.cell[axis], q.cell[axis]);
                    planes.extend((a.min(b) + 1..=a.max(b)).map(|plane| (axis, plane)));
                }
                planes.sort_unstable_by(|&x, &y| seg.compare(x, y));
                out.extend(planes.iter().map(|&(axis, plane)| EdgeFace {
                    edge,
                    axis,
                    cell: seg.face(axis, plane),
                    s: seg.parameter(axis, plane),
                    upward: p.cell[axis] < q.cell[axis],
                }));
            }
            out
        })
        .collect();
    per_block.concat()
}

/// The cells each triangle overlaps, as sorted lists (compressed rows over triangles).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct TriangleCells {
    starts: Vec<u32>,
    cells: Vec<[i32; 3]>,
}

impl TriangleCells {
    /// Cells overlapped by triangle `t`, sorted.
    pub fn of(&self, t: usize) -> &[[i32; 3]] {
        &self.cells[self.starts[t] as usize..self.starts[t + 1] as usize]
    }

    pub fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The cells each triangle of `mesh` overlaps, from its vertices' cells, its edges' face crossings
/// (`faces`, from [`edge_faces`]) and its grid-edge crossings (`crossings`, from the rasterizer).
pub fn triangle_cells(
    mesh: &LatticeMesh,
    crossings: &Crossings,
    faces: &[EdgeFace],
) -> TriangleCells {
    let triangles = mesh.triangles();
    let mut by_triangle: Vec<(u32, u32)> = crossings
        .all()
        .par_iter()
        .enumerate()
        .map(|(k, c)| (c.triangle, k as u32))
        .collect();
    by_triangle.par_sort_unstable();
    let lists: Vec<Vec<[i32; 3]>> = (0..triangles.len())
        .into_par_iter()
        .with_min_len(256)
        .map(|t| {
            let tri = triangles[t];
            let mut cells: Vec<[i32; 3]> = tri.iter().map(|&v| mesh.vertex_cell(v)).collect();
            for [p, q] in [[tri[0], tri[1]], [tri[1], tri[2]], [tri[2], tri[0]]] {
                let edge = [p.min(q), p.max(q)];
                let lo = faces.partition_point(|f| f.edge < edge);
                let hi = faces.partition_point(|f| f.edge <= edge);
                cells.extend(faces[lo..hi].iter().flat_map(EdgeFace::cells));
            }
            let lo = by_triangle.partition_point(|&(x, _)| x < t as u32);
            let hi = by_triangle.partition_point(|&(x, _)| x <= t as u32);
            for &(_, k) in &by_triangle[lo..hi] {
                cells.extend(cells_around(&crossings.all()[k as usize]));
            }
            cells.sort_unstable();
            cells.dedup();
            cells
        })
        .collect();
    let starts = row_starts(lists.iter().map(|l| l.len() as u32));
    TriangleCells {
        starts,
        cells: lists.into_iter().flatten().collect(),
    }
}

/// The four cells around the grid edge of a crossing.
pub fn cells_around(c: &GridCrossing) -> [[i32; 3]; 4] {
    let (u, v) = cross_axes(c.axis());
    std::array::from_fn(|k| {
        let mut cell = c.corner;
        cell[u] -= (k & 1) as i32;
        cell[v] -= (k >> 1) as i32;
        cell
    })
}

/// Every cell the surface meets, sorted by `(z, y, x)`: the cells of the vertices, both cells of
/// every face crossing (`faces`, from [`edge_faces`]) and the four cells around every grid-edge
/// crossing. Its size follows the surface's area; it is what the grid stores per cell.
pub fn footprint(mesh: &LatticeMesh, crossings: &Crossings, faces: &[EdgeFace]) -> Vec<[i32; 3]> {
    let met: Vec<[i32; 3]> = mesh
        .points()
        .par_iter()
        .map(|p| p.cell)
        .chain(faces.par_iter().flat_map_iter(|f| f.cells()))
        .chain(crossings.all().par_iter().flat_map_iter(cells_around))
        .collect();
    distinct_cells(met)
}

/// The distinct cells of `met`, sorted by `(z, y, x)`. Over a box of at most a few cells per
/// cell listed (a frame's surface), they are marked and read back in order; sorting every one
/// of them cost more.
fn distinct_cells(met: Vec<[i32; 3]>) -> Vec<[i32; 3]> {
    let (low, high) = met
        .par_iter()
        .fold(
            || (IVec3::MAX, IVec3::MIN),
            |(l, h), &c| (l.min(c.into()), h.max(c.into())),
        )
        .reduce(
            || (IVec3::MAX, IVec3::MIN),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    let Some(cells) = CellBox::spanning(low, high, FOOTPRINT_BOX_PER_CELL * met.len()) else {
        let mut keys: Vec<u64> = met.par_iter().map(|&c| cell_key(c)).collect();
        keys.par_sort_unstable();
        keys.dedup();
        return keys.par_iter().map(|&k| key_cell(k)).collect();
    };
    let mut marked = vec![false; cells.volume()];
    for c in met {
        if let Some(i) = cells.index(c.into()) {
            marked[i] = true;
        }
    }
    marked
        .iter()
        .enumerate()
        .filter(|&(_, &m)| m)
        .map(|(i, _)| cells.cell(i).to_array())
        .collect()
}

/// The box [`footprint`] marks its cells in may hold this many cells per cell listed (with
/// repeats) before they are sorted instead.
const FOOTPRINT_BOX_PER_CELL: usize = 4;

#[cfg(test)]
mod tests {
    use super::*;

    /// Cells close together are marked in their box, cells far apart sorted: either way every
    /// distinct cell comes once, in `(z, y, x)` order.
    #[test]
    fn distinct_cells_come_once_in_order_either_way() {
        let near: Vec<[i32; 3]> = (0..500)
            .map(|k: i32| [k % 7 - 3, (k / 7) % 5 - 2, k % 11 - 5])
            .collect();
        let mut far = near.clone();
        far.push([100_000, -90_000, 80_000]);
        for cells in [near, far] {
            let mut expected = cells.clone();
            expected.sort_by_key(|c| (c[2], c[1], c[0]));
            expected.dedup();
            assert_eq!(distinct_cells(cells), expected);
        }
        assert!(distinct_cells(Vec::new()).is_empty());
    }
}
