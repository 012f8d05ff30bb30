//! The voxel grid over a surface and the surface mapped into the grid's index space.
//!
//! Every combinatorial decision of rasterization (which grid edge a triangle crosses, which cell a
//! vertex sits in, which cell face a mesh edge pierces) is made on integers, so it is exact and the
//! CPU and the GPU reach the same answer (thesis §3.4.3 and §3.4.6: tolerances make independent tests
//! disagree, and the cut that follows then cannot close its loops). Vertices are snapped once, on the
//! CPU, to a fixed lattice of `2^-FRACTION_BITS` of a cell: a snapped vertex moves by at most
//! `2^-21` cell per coordinate (under `1e-6` cell in length), so every grid corner farther than
//! that from the surface keeps its inside/outside answer. When the input coordinates carry fewer
//! bits than the lattice (a mesh far from the world origin, or on a dyadic grid) the snap is exact.

use glam::Vec3;
use rayon::prelude::*;

use super::RasterError;
use crate::kernels::shared::{
    CELL_UNITS, FRACTION_BITS, LatticePoint, MAX_CELL_INDEX, MAX_TRIANGLE_SPAN,
};
use crate::mesh::IndexedMesh;

/// A cell as one sortable integer: ordering keys orders cells by `(z, y, x)`.
pub fn cell_key(c: [i32; 3]) -> u64 {
    let field = |v: i32| u64::from((v + (1 << 20)) as u32 & 0x1f_ffff);
    field(c[2]) << 42 | field(c[1]) << 21 | field(c[0])
}

/// The cell of a [`cell_key`].
pub fn key_cell(key: u64) -> [i32; 3] {
    let field = |shift: u32| ((key >> shift) & 0x1f_ffff) as i32 - (1 << 20);
    [field(0), field(21), field(42)]
}

/// A regular grid with corner `(i, j, k)` at `origin + spacing * (i, j, k)`, unbounded in every
/// direction (indices are signed); only what the surface touches is ever stored.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridFrame {
    origin: Vec3,
    spacing: f32,
}

impl GridFrame {
    pub fn new(origin: Vec3, spacing: f32) -> Result<Self, RasterError> {
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(RasterError::Spacing(spacing));
        }
        if !origin.is_finite() {
            return Err(RasterError::Origin(origin.to_array()));
        }
        Ok(Self { origin, spacing })
    }

    /// The grid the tracker uses for `mesh`: spacing `factor` times its mean edge length (paper
    /// §4.3 uses the mean edge length itself), origin at the world origin.
    pub fn for_mesh(mesh: &IndexedMesh, factor: f32) -> Result<Self, RasterError> {
        let mean = mesh.mean_edge_length();
        if mean == 0.0 || mesh.triangles.is_empty() {
            return Err(RasterError::NoEdges);
        }
        Self::new(Vec3::ZERO, factor * mean)
    }

    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// World position of a grid corner.
    pub fn corner_position(&self, corner: [i32; 3]) -> Vec3 {
        let p: [f32; 3] = std::array::from_fn(|a| {
            (f64::from(self.origin[a]) + f64::from(self.spacing) * f64::from(corner[a])) as f32
        });
        Vec3::from_array(p)
    }

    /// Grid coordinates (in cells, from the origin) of a world position, in f64.
    pub fn to_grid(&self, p: Vec3) -> [f64; 3] {
        std::array::from_fn(|a| {
            (f64::from(p[a]) - f64::from(self.origin[a])) / f64::from(self.spacing)
        })
    }

    /// The lattice point nearest to `p`: a cell index and `FRACTION_BITS` bits of fraction.
    pub fn snap(&self, vertex: usize, p: Vec3) -> Result<LatticePoint, RasterError> {
        if !p.is_finite() {
            return Err(RasterError::NonFinite { vertex });
        }
        let g = self.to_grid(p);
        let mut cell = [0i32; 3];
        let mut frac = [0u32; 3];
        for a in 0..3 {
            if g[a].abs() >= f64::from(MAX_CELL_INDEX) {
                return Err(RasterError::OutOfRange {
                    vertex,
                    cells: g[a],
                });
            }
            // |g| < 2^24, so g * 2^20 < 2^44 is exact in f64 and rounding is deterministic.
            let units = (g[a] * CELL_UNITS as f64).round() as i64;
            cell[a] = (units >> FRACTION_BITS) as i32;
            frac[a] = (units & (CELL_UNITS - 1)) as u32;
        }
        Ok(LatticePoint { cell, frac })
    }
}

/// A triangle mesh in grid index space: the input of every rasterization stage.
///
/// Built once per frame; construction snaps every vertex to the lattice and checks that every
/// triangle is small enough for the exact predicates, so the stages themselves cannot fail on input.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeMesh {
    frame: GridFrame,
    points: Vec<LatticePoint>,
    triangles: Vec<[u32; 3]>,
}

impl LatticeMesh {
    pub fn new(frame: GridFrame, mesh: &IndexedMesh) -> Result<Self, RasterError> {
        let points = mesh
            .positions
            .par_iter()
            .enumerate()
            .map(|(v, &p)| frame.snap(v, p))
            .collect::<Result<Vec<_>, _>>()?;
        let bad = mesh
            .triangles
            .par_iter()
            .enumerate()
            .find_map_first(|(t, tri)| check_triangle(&points, t, tri).err());
        if let Some(error) = bad {
            return Err(error);
        }
        Ok(Self {
            frame,
            points,
            triangles: mesh.triangles.clone(),
        })
    }

    pub fn frame(&self) -> &GridFrame {
        &self.frame
    }

    pub fn points(&self) -> &[LatticePoint] {
        &self.points
    }

    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The cell holding vertex `v` (under the grid's perturbation, see [`LatticePoint`]).
    pub fn vertex_cell(&self, v: u32) -> [i32; 3] {
        self.points[v as usize].cell
    }

    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [LatticePoint; 3] {
        self.triangles[t].map(|v| self.points[v as usize])
    }

    /// Smallest and largest vertex cell of triangle `t` along each axis.
    pub fn cell_range(&self, t: usize) -> ([i32; 3], [i32; 3]) {
        cell_range(&self.corners(t))
    }
}

/// Smallest and largest cell of three points along each axis.
pub(crate) fn cell_range(p: &[LatticePoint; 3]) -> ([i32; 3], [i32; 3]) {
    let lo = std::array::from_fn(|a| p[0].cell[a].min(p[1].cell[a]).min(p[2].cell[a]));
    let hi = std::array::from_fn(|a| p[0].cell[a].max(p[1].cell[a]).max(p[2].cell[a]));
    (lo, hi)
}

fn check_triangle(
    points: &[LatticePoint],
    triangle: usize,
    tri: &[u32; 3],
) -> Result<(), RasterError> {
    let count = points.len();
    if let Some(&vertex) = tri.iter().find(|&&v| v as usize >= count) {
        return Err(RasterError::IndexOutOfRange {
            triangle,
            vertex,
            count,
        });
    }
    let (lo, hi) = cell_range(&tri.map(|v| points[v as usize]));
    let spans = (0..3).map(|axis| (axis, i64::from(hi[axis]) - i64::from(lo[axis])));
    match spans
        .into_iter()
        .find(|&(_, span)| span > MAX_TRIANGLE_SPAN)
    {
        Some((axis, span)) => Err(RasterError::TriangleTooLarge {
            triangle,
            axis,
            span,
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snapping_is_floor_with_exact_fraction() {
        let frame = GridFrame::new(Vec3::ZERO, 0.25).unwrap();
        let p = frame.snap(0, Vec3::new(0.5, -0.125, 0.3)).unwrap();
        assert_eq!(p.cell, [2, -1, 1]);
        assert_eq!(p.frac[0], 0);
        assert_eq!(p.frac[1], (CELL_UNITS / 2) as u32);
        let expected = ((0.3f32 as f64 / 0.25 - 1.0) * CELL_UNITS as f64).round() as u32;
        assert_eq!(p.frac[2], expected);
        // On a plane: the cell above, as the perturbation (mesh shifted by +ε) says.
        assert_eq!(
            frame.snap(0, Vec3::new(-0.25, 0.0, 0.0)).unwrap().cell,
            [-1, 0, 0]
        );
    }

    #[test]
    fn snap_error_is_below_a_millionth_of_a_cell() {
        let frame = GridFrame::new(Vec3::new(0.1, -0.3, 7.0), 0.0173).unwrap();
        for i in 0..1000 {
            let p = Vec3::new(i as f32 * 0.0137, (i as f32).sin(), 7.0 + (i as f32).cos());
            let snapped = frame.snap(i, p).unwrap();
            let g = frame.to_grid(p);
            for (a, g) in g.iter().enumerate() {
                let back = snapped.units(a) as f64 / CELL_UNITS as f64;
                assert!((back - g).abs() <= 0.5 / CELL_UNITS as f64 + 1e-12);
            }
        }
    }

    #[test]
    fn cell_keys_sort_by_z_y_x_and_round_trip() {
        let m = MAX_CELL_INDEX + 1;
        let mut cells = vec![
            [0, 0, 0],
            [-m, m, 3],
            [m, -m, 3],
            [5, 5, -m],
            [-1, 0, 0],
            [0, -1, 0],
        ];
        for &c in &cells {
            assert_eq!(key_cell(cell_key(c)), c);
        }
        let mut by_key = cells.clone();
        by_key.sort_by_key(|&c| cell_key(c));
        cells.sort_by_key(|c| [c[2], c[1], c[0]]);
        assert_eq!(by_key, cells);
    }

    #[test]
    fn bad_input_is_reported() {
        assert_eq!(
            GridFrame::new(Vec3::ZERO, 0.0),
            Err(RasterError::Spacing(0.0))
        );
        let frame = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
        assert_eq!(
            frame.snap(3, Vec3::new(f32::NAN, 0.0, 0.0)),
            Err(RasterError::NonFinite { vertex: 3 })
        );
        assert!(matches!(
            frame.snap(1, Vec3::new(0.0, 2e6, 0.0)),
            Err(RasterError::OutOfRange { vertex: 1, .. })
        ));
        let mesh = IndexedMesh::new(vec![Vec3::ZERO, Vec3::X * 5000.0, Vec3::Y], vec![[0, 1, 2]]);
        assert_eq!(
            LatticeMesh::new(frame, &mesh),
            Err(RasterError::TriangleTooLarge {
                triangle: 0,
                axis: 0,
                span: 5000
            })
        );
        let mesh = IndexedMesh::new(vec![Vec3::ZERO], vec![[0, 0, 4]]);
        assert_eq!(
            LatticeMesh::new(frame, &mesh),
            Err(RasterError::IndexOutOfRange {
                triangle: 0,
                vertex: 4,
                count: 1
            })
        );
    }
}
