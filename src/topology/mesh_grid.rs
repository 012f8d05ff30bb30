//! The tracked mesh on the topology grid: its grid-edge crossings and sweep windings (from the grid
//! module), and what the cut needs besides (thesis §3.4.2, appendix A): the edge table, the crossings
//! of each triangle, and where each mesh edge pierces the grid's planes, in order along the edge.

use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::TopologyError;
use super::keys::{Cell, Corner, GridEdge, GridFace};
use super::segment::Segment;
use crate::compute::Backend;
use crate::grid::{Crossings, GridCrossing, GridFrame, LatticeMesh, Windings, rasterize, sweep};
use crate::mesh::IndexedMesh;

/// Undirected edges of a closed manifold mesh: each joins `verts[e]` (smaller index first) and
/// borders the two triangles `tris[e]`; side `k` of triangle `t` (from corner `k` to `k + 1`) is
/// edge `of_triangle[t][k]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct EdgeTable {
    pub verts: Vec<[u32; 2]>,
    pub tris: Vec<[u32; 2]>,
    pub of_triangle: Vec<[u32; 3]>,
}

impl EdgeTable {
    fn new(mesh: &IndexedMesh) -> Result<Self, TopologyError> {
        let mut sides: Vec<(u32, u32, u32, u8)> = mesh
            .triangles
            .iter()
            .enumerate()
            .flat_map(|(t, tri)| {
                (0..3).map(move |k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    (a.min(b), a.max(b), t as u32, k as u8)
                })
            })
            .collect();
        sides.par_sort_unstable();
        let mut table = EdgeTable {
            verts: Vec::with_capacity(sides.len() / 2),
            tris: Vec::with_capacity(sides.len() / 2),
            of_triangle: vec![[0; 3]; mesh.triangles.len()],
        };
        for pair in sides.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let [s0, s1] = pair else {
                return Err(TopologyError::NotManifold {
                    a: pair[0].0,
                    b: pair[0].1,
                    count: pair.len(),
                });
            };
            let e = table.verts.len() as u32;
            table.verts.push([s0.0, s0.1]);
            table.tris.push([s0.2, s1.2]);
            table.of_triangle[s0.2 as usize][usize::from(s0.3)] = e;
            table.of_triangle[s1.2 as usize][usize::from(s1.3)] = e;
        }
        Ok(table)
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
    fn from_rows(rows: Vec<Vec<T>>) -> Self {
        let mut starts = Vec::with_capacity(rows.len() + 1);
        let mut n = 0u32;
        starts.push(0);
        for r in &rows {
            n += r.len() as u32;
            starts.push(n);
        }
        Self {
            starts,
            items: rows.into_iter().flatten().collect(),
        }
    }

    pub fn row(&self, r: usize) -> &[T] {
        &self.items[self.starts[r] as usize..self.starts[r + 1] as usize]
    }
}

/// The tracked mesh rasterized on the topology grid.
pub(crate) struct MeshGrid<'a> {
    pub mesh: &'a IndexedMesh,
    pub lattice: LatticeMesh,
    pub crossings: Crossings,
    pub windings: Windings,
    pub edges: EdgeTable,
    pub segments: Vec<Segment>,
    /// Indices into `crossings.all()` of each triangle's crossings.
    by_triangle: Rows<u32>,
    /// The planes each edge pierces, in order from its first vertex.
    pierces: Rows<Pierce>,
    /// The edges piercing each face, in edge order.
    pierced: FxHashMap<GridFace, Vec<u32>>,
}

impl<'a> MeshGrid<'a> {
    pub fn new(mesh: &'a IndexedMesh, frame: GridFrame) -> Result<Self, TopologyError> {
        let lattice = LatticeMesh::new(frame, mesh)?;
        let crossings = rasterize(&Backend::Cpu, &lattice)?;
        let windings = sweep(&Backend::Cpu, &crossings)?;
        let edges = EdgeTable::new(mesh)?;
        let points = lattice.points();
        let segments: Vec<Segment> = edges
            .verts
            .par_iter()
            .map(|[a, b]| Segment::new(&points[*a as usize], &points[*b as usize]))
            .collect();
        let rows: Vec<Vec<Pierce>> = segments
            .par_iter()
            .map(|seg| {
                let mut row: Vec<Pierce> = (0..3)
                    .flat_map(|axis| {
                        seg.planes(axis).map(move |plane| Pierce {
                            axis: axis as u8,
                            plane,
                            face: seg.face(axis, plane),
                        })
                    })
                    .collect();
                row.sort_by(|x, y| {
                    seg.compare(
                        (usize::from(x.axis), x.plane),
                        (usize::from(y.axis), y.plane),
                    )
                });
                row
            })
            .collect();
        let mut pierced: FxHashMap<GridFace, Vec<u32>> = FxHashMap::default();
        for (e, row) in rows.iter().enumerate() {
            for p in row {
                pierced
                    .entry(GridFace::new(p.face, usize::from(p.axis)))
                    .or_default()
                    .push(e as u32);
            }
        }
        let mut per_triangle = vec![Vec::new(); mesh.triangles.len()];
        for (i, c) in crossings.all().iter().enumerate() {
            per_triangle[c.triangle as usize].push(i as u32);
        }
        Ok(Self {
            mesh,
            lattice,
            crossings,
            windings,
            edges,
            segments,
            by_triangle: Rows::from_rows(per_triangle),
            pierces: Rows::from_rows(rows),
            pierced,
        })
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
        self.by_triangle
            .row(t as usize)
            .iter()
            .map(|&i| &self.crossings.all()[i as usize])
    }

    /// The grid edge where triangle `t` crosses the grid line along `axis` through the planes
    /// `(other, at)` and `(third, at')`; `None` when the rasterizer found no such crossing.
    pub fn triangle_line_crossing(&self, t: u32, axis: usize, line: [(usize, i32); 2]) -> Option<GridEdge> {
        self.triangle_crossings(t)
            .find(|c| c.axis() == axis && line.iter().all(|&(a, at)| c.corner[a] == at))
            .map(|c| GridEdge::new(c.corner, axis))
    }

    /// The planes mesh edge `e` pierces, in order from its first vertex.
    pub fn pierces(&self, e: u32) -> &[Pierce] {
        self.pierces.row(e as usize)
    }

    /// Mesh edges piercing `face`.
    pub fn pierced(&self, face: &GridFace) -> &[u32] {
        self.pierced.get(face).map_or(&[], |v| v.as_slice())
    }

    /// Every face some mesh edge pierces.
    pub fn pierced_faces(&self) -> impl Iterator<Item = &GridFace> + '_ {
        self.pierced.keys()
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
