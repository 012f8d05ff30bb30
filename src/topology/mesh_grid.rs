//! The tracked mesh on the topology grid: its grid-edge crossings and sweep windings (from the grid
//! module), and what the cut needs besides (thesis §3.4.2, appendix A): the edge table, the crossings
//! of each triangle, and where each mesh edge pierces the grid's planes, in order along the edge.

use glam::IVec3;
use rayon::prelude::*;
use std::sync::OnceLock;

use super::TopologyError;
use super::keys::{Cell, Corner, GridEdge, GridFace};
use super::segment::Segment;
use crate::compute::Backend;
use crate::grid::{
    CellBox, Crossings, GridCrossing, GridFrame, LatticeMesh, Windings, by_slot, rasterize,
    row_starts, sweep,
};
use crate::mesh::{FaceId, HalfEdgeId, IndexedMesh, Mesh};

/// Undirected edges of the mesh: each joins `verts[e]` (smaller index first) and
/// borders the two triangles `tris[e]`; side `k` of triangle `t` (from corner `k` to `k + 1`) is
/// edge `of_triangle[t][k]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct EdgeTable {
    pub verts: Vec<[u32; 2]>,
    pub tris: Vec<[u32; 2]>,
    pub of_triangle: Vec<[u32; 3]>,
}

impl EdgeTable {
    /// The table of `mesh`, which is `half.to_indexed()`: triangle `t` is the `t`-th live face of
    /// `half` and its side `k` that face's half-edge `k`, so each edge is found through its twin,
    /// without sorting.
    fn new(mesh: &IndexedMesh, half: &Mesh) -> Self {
        let faces: Vec<FaceId> = half.faces().collect();
        let slots = faces.last().map_or(0, |f| f.0 as usize + 1);
        let mut triangle_of = vec![u32::MAX; slots];
        for (t, f) in faces.iter().enumerate() {
            triangle_of[f.0 as usize] = t as u32;
        }
        let n = mesh.triangles.len();
        let mut table = EdgeTable {
            verts: Vec::with_capacity(3 * n / 2),
            tris: Vec::with_capacity(3 * n / 2),
            of_triangle: vec![[u32::MAX; 3]; n],
        };
        for (t, f) in faces.iter().enumerate() {
            for k in 0..3 {
                if table.of_triangle[t][k] != u32::MAX {
                    continue;
                }
                let twin = half.twin(HalfEdgeId(3 * f.0 + k as u32));
                let other = triangle_of[twin.0 as usize / 3];
                let e = table.verts.len() as u32;
                let tri = mesh.triangles[t];
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                table.verts.push([a.min(b), a.max(b)]);
                table.tris.push([t as u32, other]);
                table.of_triangle[t][k] = e;
                table.of_triangle[other as usize][twin.0 as usize % 3] = e;
            }
        }
        table
    }
}

/// A crossing of a mesh edge with a grid plane: the plane and the cell above the pierced face.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Pierce {
    pub axis: u8,
    pub plane: i32,
    pub face: Cell,
}

/// Rows of variable length stored back to back.
#[derive(Debug, Clone, Default)]
pub(crate) struct Rows<T> {
    starts: Vec<u32>,
    items: Vec<T>,
}

impl<T> Rows<T> {
    pub fn row(&self, r: usize) -> &[T] {
        &self.items[self.starts[r] as usize..self.starts[r + 1] as usize]
    }
}

impl Rows<u32> {
    /// Row `keys[i]` lists `i`, for `rows` rows (a counting sort).
    fn by_key(keys: impl Iterator<Item = u32> + Clone, rows: usize) -> Self {
        let mut starts = vec![0u32; rows + 1];
        for k in keys.clone() {
            starts[k as usize + 1] += 1;
        }
        for r in 0..rows {
            starts[r + 1] += starts[r];
        }
        let mut fill = starts.clone();
        let mut items = vec![0u32; starts[rows] as usize];
        for (i, k) in keys.enumerate() {
            items[fill[k as usize] as usize] = i as u32;
            fill[k as usize] += 1;
        }
        Self { starts, items }
    }
}

/// The tracked mesh rasterized on the topology grid. The tables the cut needs are built on first
/// use: a call that finds nothing to re-sample never pays for them.
pub(crate) struct MeshGrid<'a> {
    pub mesh: &'a IndexedMesh,
    half: &'a Mesh,
    pub lattice: LatticeMesh,
    pub crossings: Crossings,
    pub windings: Windings,
    tables: OnceLock<Tables>,
}

/// What the cut reads besides the crossings.
struct Tables {
    edges: EdgeTable,
    /// Indices into `crossings.all()` of each triangle's crossings.
    by_triangle: Rows<u32>,
    /// The planes each edge pierces, in order from its first vertex.
    pierces: Rows<Pierce>,
    /// `(face, edge)` for every edge piercing a face, sorted.
    pierced: Vec<(GridFace, u32)>,
}

impl Tables {
    fn new(mesh: &IndexedMesh, half: &Mesh, lattice: &LatticeMesh, crossings: &Crossings) -> Self {
        let edges = EdgeTable::new(mesh, half);
        let points = lattice.points();
        // Blocks of edges each fill one list, every edge's planes a run of it: most edges
        // pierce one or two, and a list per edge cost an allocation each.
        let blocks: Vec<(Vec<u32>, Vec<Pierce>)> = edges
            .verts
            .par_chunks(1024)
            .map(|block| {
                let mut lengths = Vec::with_capacity(block.len());
                let mut items: Vec<Pierce> = Vec::new();
                for [a, b] in block {
                    let start = items.len();
                    let (p, q) = (&points[*a as usize], &points[*b as usize]);
                    if p.cell != q.cell {
                        let seg = Segment::new(p, q);
                        items.extend((0..3).flat_map(|axis| {
                            seg.planes(axis).map(move |plane| Pierce {
                                axis: axis as u8,
                                plane,
                                face: seg.face(axis, plane),
                            })
                        }));
                        items[start..].sort_by(|x, y| {
                            seg.compare(
                                (usize::from(x.axis), x.plane),
                                (usize::from(y.axis), y.plane),
                            )
                        });
                    }
                    lengths.push((items.len() - start) as u32);
                }
                (lengths, items)
            })
            .collect();
        let pierces = Rows {
            starts: row_starts(
                blocks
                    .iter()
                    .flat_map(|(lengths, _)| lengths.iter().copied()),
            ),
            items: blocks.into_iter().flat_map(|(_, items)| items).collect(),
        };
        let pierced: Vec<(GridFace, u32)> = (0..edges.verts.len())
            .into_par_iter()
            .flat_map_iter(|e| {
                pierces
                    .row(e)
                    .iter()
                    .map(move |p| (GridFace::new(p.face, usize::from(p.axis)), e as u32))
            })
            .collect();
        Self {
            pierced: sorted_by_face(pierced),
            edges,
            by_triangle: Rows::by_key(
                crossings.all().iter().map(|c| c.triangle),
                mesh.triangles.len(),
            ),
            pierces,
        }
    }
}

/// `pierced` (in order of its edges, each face at most once an edge) sorted. Over a box of at
/// most [`SLOTS_PER_PIERCE`] faces per entry (a frame's surface), by counting the entries of
/// each face into place, which keeps them in their edges' order; else by sorting.
fn sorted_by_face(mut pierced: Vec<(GridFace, u32)>) -> Vec<(GridFace, u32)> {
    // Faces sort by cell x first: the box is over (z, y, x), whose numbers run x slowest.
    let reversed = |c: Cell| IVec3::new(c[2], c[1], c[0]);
    let (low, high) = pierced
        .iter()
        .fold((IVec3::MAX, IVec3::MIN), |(l, h), (f, _)| {
            (l.min(reversed(f.cell)), h.max(reversed(f.cell)))
        });
    let Some(cells) = CellBox::spanning(low, high, SLOTS_PER_PIERCE * pierced.len() / 3) else {
        pierced.par_sort_unstable();
        return pierced;
    };
    // A cell's three faces in axis order.
    by_slot(&pierced, 3 * cells.volume(), |(f, _)| {
        3 * cells.index(reversed(f.cell)).unwrap_or_default() + usize::from(f.axis)
    })
    .0
}

/// Faces a box may hold per entry of [`sorted_by_face`] before it sorts instead.
const SLOTS_PER_PIERCE: usize = 16;

/// A closed mesh rasterized on a grid: its lattice form, where it crosses the grid's edges, and
/// the sweep's windings. `Φ(M)` is measured from these, and `ConstrainTopology(M, Φ(M))` cuts M
/// along the same crossings (paper Algorithm 1, lines 8–9): made once, they serve both.
#[derive(Debug, Clone)]
pub struct MeshRaster {
    pub(crate) lattice: LatticeMesh,
    pub(crate) crossings: Crossings,
    pub(crate) windings: Windings,
}

impl MeshRaster {
    /// `mesh` rasterized and swept on the grid `frame`, on `backend`. A device's crossings lie
    /// within a tolerance of the CPU twin's, its windings are the twin's.
    pub fn new(
        backend: &Backend,
        frame: GridFrame,
        mesh: &IndexedMesh,
    ) -> Result<Self, TopologyError> {
        let lattice = LatticeMesh::new(frame, mesh)?;
        let crossings = rasterize(backend, &lattice)?;
        let windings = sweep(backend, &crossings)?;
        Ok(Self {
            lattice,
            crossings,
            windings,
        })
    }

    /// Whether this is a raster of a mesh of `vertices` vertices on the grid `frame`.
    pub(crate) fn fits(&self, frame: &GridFrame, vertices: usize) -> bool {
        self.lattice.frame() == frame && self.lattice.points().len() == vertices
    }
}

impl<'a> MeshGrid<'a> {
    /// The mesh `half` (whose indexed form is `mesh`) on the grid `frame`.
    pub fn new(
        mesh: &'a IndexedMesh,
        half: &'a Mesh,
        frame: GridFrame,
    ) -> Result<Self, TopologyError> {
        Ok(Self::rastered(
            mesh,
            half,
            MeshRaster::new(&Backend::Cpu, frame, mesh)?,
        ))
    }

    /// The mesh `half` (whose indexed form is `mesh`) on the grid of `raster`, a raster of `mesh`.
    pub fn rastered(mesh: &'a IndexedMesh, half: &'a Mesh, raster: MeshRaster) -> Self {
        Self {
            mesh,
            half,
            lattice: raster.lattice,
            crossings: raster.crossings,
            windings: raster.windings,
            tables: OnceLock::new(),
        }
    }

    fn tables(&self) -> &Tables {
        self.tables
            .get_or_init(|| Tables::new(self.mesh, self.half, &self.lattice, &self.crossings))
    }

    /// Builds the tables now if they are not built yet. Their first use from inside a parallel
    /// loop would build them on that loop's thread while its others wait for them, so the
    /// building's own parallel parts would run on one core: a loop over faces calls this first.
    pub fn build_tables(&self) {
        self.tables();
    }

    /// The mesh's edges.
    pub fn edges(&self) -> &EdgeTable {
        &self.tables().edges
    }

    /// Mesh edge `e` in lattice units.
    pub fn segment(&self, e: u32) -> Segment {
        let [a, b] = self.edges().verts[e as usize];
        let points = self.lattice.points();
        Segment::new(&points[a as usize], &points[b as usize])
    }

    pub fn frame(&self) -> &GridFrame {
        self.lattice.frame()
    }

    /// Crossings of the mesh with a grid edge, in order along it.
    pub fn on_edge(&self, edge: GridEdge) -> &[GridCrossing] {
        self.crossings.on_edge(edge.axis(), edge.corner)
    }

    /// Crossings of triangle `t` with grid edges.
    pub fn triangle_crossings(&self, t: u32) -> impl Iterator<Item = &GridCrossing> + '_ {
        self.tables()
            .by_triangle
            .row(t as usize)
            .iter()
            .map(|&i| &self.crossings.all()[i as usize])
    }

    /// The grid edge where triangle `t` crosses the grid line along `axis` through the planes
    /// `(other, at)` and `(third, at')`; `None` when the rasterizer found no such crossing.
    pub fn triangle_line_crossing(
        &self,
        t: u32,
        axis: usize,
        line: [(usize, i32); 2],
    ) -> Option<GridEdge> {
        self.triangle_crossings(t)
            .find(|c| c.axis() == axis && line.iter().all(|&(a, at)| c.corner[a] == at))
            .map(|c| GridEdge::new(c.corner, axis))
    }

    /// The planes mesh edge `e` pierces, in order from its first vertex.
    pub fn pierces(&self, e: u32) -> &[Pierce] {
        self.tables().pierces.row(e as usize)
    }

    /// Mesh edges piercing `face`.
    pub fn pierced(&self, face: &GridFace) -> impl Iterator<Item = u32> + '_ {
        let all = &self.tables().pierced;
        let lo = all.partition_point(|(f, _)| f < face);
        let hi = lo + all[lo..].partition_point(|(f, _)| f == face);
        all[lo..hi].iter().map(|&(_, e)| e)
    }

    /// Every face some mesh edge pierces, in order, each once.
    pub fn pierced_faces(&self) -> impl Iterator<Item = GridFace> + '_ {
        let all = &self.tables().pierced;
        all.iter()
            .enumerate()
            .filter(|&(i, (f, _))| i == 0 || all[i - 1].0 != *f)
            .map(|(_, (f, _))| *f)
    }

    /// Winding number of a corner from the sweep along `axis`.
    pub fn winding(&self, axis: usize, corner: Corner) -> i32 {
        self.windings.winding(axis, corner)
    }

    /// Whether the mesh holds a corner inside (winding at least 1).
    pub fn inside(&self, corner: Corner) -> bool {
        self.windings.winding(0, corner) >= 1
    }

    /// The cell holding vertex `v`.
    pub fn vertex_cell(&self, v: u32) -> Cell {
        self.lattice.vertex_cell(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Entries of faces close together are counted into place, of faces far apart sorted:
    /// either way they come as sorting them gives.
    #[test]
    fn pierced_faces_come_sorted_either_way() {
        let near: Vec<(GridFace, u32)> = (0..600u32)
            .flat_map(|e| {
                let k = e as i32;
                [0, 1]
                    .map(|j| {
                        let cell = [k % 5 - 2, (k / 5) % 4 + j, k % 3 - 1];
                        (GridFace::new(cell, (e as usize + j as usize) % 3), e)
                    })
                    .into_iter()
                    .take(1 + (e % 2) as usize)
            })
            .collect();
        let mut far = near.clone();
        far.push((GridFace::new([90_000, -70_000, 60_000], 2), 600));
        for pierced in [near, far] {
            let mut expected = pierced.clone();
            expected.sort_unstable();
            assert_eq!(sorted_by_face(pierced), expected);
        }
        assert!(sorted_by_face(Vec::new()).is_empty());
    }
}
