//! Positions of the named points, computed once every combinatorial decision is made.
//!
//! Cut points lie on the mesh: a pierce point at its plane's parameter along the mesh edge, a crossing
//! at the rasterizer's parameter along the grid edge. Both are kept a thousandth of an edge away from
//! the ends (as marching cubes keeps its vertices off grid corners), consecutive pierce points on
//! one edge keep a gap, and a crossing moves a thousandth of a cell into its triangle, off the
//! triangle's sides: a mesh edge lying on a grid line, or a vertex on a grid corner, would otherwise
//! put a crossing exactly on the line through the pierce points of that edge, and a piece of the cut
//! would have zero area. Fill points lie on Θ's zero set: on grid edges by linear interpolation, and
//! loop centres on the trilinear interpolant inside their cell (see [`centre`]).

use glam::DVec3;
use rustc_hash::FxHashMap;

use super::field::Field;
use super::keys::{Cell, GridEdge};
use super::mesh_grid::MeshGrid;
use super::points::Point;
use crate::grid::{GridFrame, T_MIN};

/// Smallest parameter of a cut point along its edge, and its smallest gap to the next one.
const END_GAP: f64 = 1e-3;

/// How far a loop centre stays from its cell's faces, in cells.
const CENTRE_MARGIN: f64 = 0.02;

/// Newton steps towards Θ's zero set for a loop centre.
const CENTRE_STEPS: usize = 8;

pub(crate) fn to_world(frame: &GridFrame, g: DVec3) -> DVec3 {
    frame.origin().as_dvec3() + f64::from(frame.spacing()) * g
}

pub(crate) fn to_grid(frame: &GridFrame, p: DVec3) -> DVec3 {
    (p - frame.origin().as_dvec3()) / f64::from(frame.spacing())
}

/// Parameters of the split points of every split edge, spread as the module docs say.
pub(crate) fn pierce_parameters(
    grid: &MeshGrid,
    splits: &FxHashMap<u32, Vec<(u8, i32)>>,
) -> FxHashMap<(u32, u8, i32), f64> {
    let mut out = FxHashMap::default();
    for (&e, list) in splits {
        let seg = &grid.segment(e);
        let n = list.len();
        let gap = END_GAP.min((1.0 - 2.0 * END_GAP) / (n as f64 + 1.0));
        let mut s: Vec<f64> = list
            .iter()
            .map(|&(a, i)| seg.parameter(usize::from(a), i))
            .collect();
        let mut low = END_GAP - gap;
        for x in s.iter_mut() {
            *x = x.max(low + gap);
            low = *x;
        }
        let mut high = 1.0 - END_GAP + gap;
        for x in s.iter_mut().rev() {
            *x = x.min(high - gap);
            high = *x;
        }
        for (&(a, i), &x) in list.iter().zip(&s) {
            out.insert((e, a, i), x);
        }
    }
    out
}

/// Position of a point on a grid edge at parameter `t`.
fn on_grid_edge(frame: &GridFrame, edge: &GridEdge, t: f64) -> DVec3 {
    let mut g = DVec3::from_array(edge.corner.map(f64::from));
    g[edge.axis()] += t;
    to_world(frame, g)
}

/// World position of every point but loop centres.
pub(crate) fn position(
    grid: &MeshGrid,
    field: &Field,
    parameters: &FxHashMap<(u32, u8, i32), f64>,
    p: &Point,
) -> Option<DVec3> {
    let positions = &grid.mesh.positions;
    match *p {
        Point::Vertex(v) => Some(positions[v as usize].as_dvec3()),
        Point::Pierce { edge, axis, plane } => {
            let s = *parameters.get(&(edge, axis, plane))?;
            let [a, b] =
                grid.edges().verts[edge as usize].map(|v| positions[v as usize].as_dvec3());
            Some(a + (b - a) * s)
        }
        Point::Crossing { triangle, edge } => {
            let c = grid.on_edge(edge).iter().find(|c| c.triangle == triangle)?;
            let t = f64::from(c.t).clamp(f64::from(T_MIN), 1.0 - f64::from(T_MIN));
            let at = on_grid_edge(grid.frame(), &edge, t);
            let corners = grid.mesh.triangles[triangle as usize];
            let centroid = corners
                .iter()
                .fold(DVec3::ZERO, |s, &v| s + positions[v as usize].as_dvec3())
                / 3.0;
            let inward = (centroid - at).normalize_or_zero();
            Some(at + inward * (END_GAP * f64::from(grid.frame().spacing())))
        }
        Point::Level(edge) => Some(on_grid_edge(
            grid.frame(),
            &edge,
            f64::from(field.crossing(edge)),
        )),
        Point::Centre { .. } => None,
    }
}

/// Position of the centre of a loop of `cell` whose points are at `around`: Newton steps on the
/// trilinear interpolant from the loop's centroid. Where they stall (against the cell's margin, by
/// a sheet leaving the cell near the centroid, a cap of Θ around one corner, or two sheets in one
/// cell), the zero crossing nearest the centroid on a lattice of samples over the closed cell,
/// moved inside the margin and refined by Newton steps if they converge from there. A cell with a
/// sign change always has such a crossing (at least on its edges), so a centre lies within a
/// lattice step plus the margin's diagonal (about 0.12 cell) of Θ's zero set.
pub(crate) fn centre(field: &Field, cell: Cell, around: &[DVec3]) -> DVec3 {
    let frame = field.frame();
    let base = DVec3::from_array(cell.map(f64::from));
    let mean = around
        .iter()
        .fold(DVec3::ZERO, |s, &p| s + to_grid(frame, p))
        / around.len() as f64;
    let values = field.cell_values(cell);
    let start = clamp_local(mean - base);
    let mut local = newton(&values, start);
    if residual(&values, local) > CENTRE_TOLERANCE
        && let Some(near) = nearest_crossing(&values, mean - base)
    {
        let near = clamp_local(near);
        let refined = newton(&values, near);
        local = if residual(&values, refined) <= CENTRE_TOLERANCE {
            refined
        } else {
            near
        };
    }
    to_world(frame, base + local)
}

/// Residual (in cells) below which Newton steps count as converged onto Θ's zero set.
const CENTRE_TOLERANCE: f64 = 1e-3;

/// Lattice steps per cell side in the search for a zero crossing.
const CENTRE_SAMPLES: usize = 12;

fn clamp_local(g: DVec3) -> DVec3 {
    g.clamp(
        DVec3::splat(CENTRE_MARGIN),
        DVec3::splat(1.0 - CENTRE_MARGIN),
    )
}

/// Newton steps towards the zero set of the interpolant, kept inside the cell's margin.
fn newton(values: &[f32; 8], start: DVec3) -> DVec3 {
    let mut local = start;
    for _ in 0..CENTRE_STEPS {
        let (value, gradient) = Field::trilinear(values, local.to_array());
        let g = DVec3::from_array(gradient);
        let norm = g.length_squared();
        if !(norm > 0.0 && value.is_finite()) {
            break;
        }
        local = clamp_local(local - g * (value / norm));
    }
    local
}

/// First-order distance (in cells) from a local point to the interpolant's zero set.
fn residual(values: &[f32; 8], local: DVec3) -> f64 {
    let (value, gradient) = Field::trilinear(values, local.to_array());
    let norm = DVec3::from_array(gradient).length();
    if norm > 0.0 && value.is_finite() {
        value.abs() / norm
    } else {
        f64::INFINITY
    }
}

/// The zero crossing nearest `from` along the lines of a lattice of samples over the closed cell,
/// placed by linear interpolation between two samples; `None` when no line crosses (no sign change
/// in the cell).
fn nearest_crossing(values: &[f32; 8], from: DVec3) -> Option<DVec3> {
    let n = CENTRE_SAMPLES;
    let point = |i: [usize; 3]| DVec3::from_array(i.map(|k| k as f64 / n as f64));
    let value = |p: DVec3| Field::trilinear(values, p.to_array()).0;
    let mut best: Option<(f64, DVec3)> = None;
    for x in 0..=n {
        for y in 0..=n {
            for z in 0..=n {
                let i = [x, y, z];
                let (p, a) = (point(i), value(point(i)));
                for axis in (0..3).filter(|&axis| i[axis] < n) {
                    let mut j = i;
                    j[axis] += 1;
                    let (q, b) = (point(j), value(point(j)));
                    if (a < 0.0) == (b < 0.0) {
                        continue;
                    }
                    let c = p + (q - p) * (a / (a - b)).clamp(0.0, 1.0);
                    let d = c.distance_squared(from);
                    if best.is_none_or(|(e, _)| d < e) {
                        best = Some((d, c));
                    }
                }
            }
        }
    }
    best.map(|(_, c)| c)
}
