//! Assembling the kept surface and the fill into one indexed mesh: kept input vertices first, in
//! input order, then new points in order of first use, so the result is deterministic.

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::cut::Cut;
use super::field::Field;
use super::fill::Fill;
use super::mesh_grid::MeshGrid;
use super::place::{centre, pierce_parameters, position};
use super::points::Point;
use super::triangulate::triangulate;
use crate::mesh::IndexedMesh;

/// The assembled surface and the point each of its vertices stands for.
#[derive(Debug, Clone)]
pub(crate) struct Built {
    pub mesh: IndexedMesh,
    pub points: Vec<Point>,
    /// Parameter along its mesh edge of every pierce point, keyed by (edge, axis, plane).
    pub parameters: FxHashMap<(u32, u8, i32), f64>,
}

/// Assembles the surface; fails with the points of a polygon that could not be placed or
/// triangulated.
pub(crate) fn build(
    grid: &MeshGrid,
    field: &Field,
    cut: &Cut,
    fill: &Fill,
) -> Result<Built, Vec<Point>> {
    let parameters = pierce_parameters(grid, &cut.splits);
    let place = |p: &Point| position(grid, field, &parameters, p);
    let mut centres: FxHashMap<Point, DVec3> = FxHashMap::default();
    for (c, around) in &fill.centres {
        let Point::Centre { cell, .. } = *c else {
            return Err(around.clone());
        };
        let at = around
            .iter()
            .map(place)
            .collect::<Option<Vec<DVec3>>>()
            .ok_or_else(|| around.clone())?;
        centres.insert(*c, centre(field, cell, &at));
    }
    let pieces: Vec<Result<Vec<[Point; 3]>, Vec<Point>>> = cut
        .polygons
        .par_iter()
        .with_min_len(64)
        .map(|poly| {
            let at = poly
                .points
                .iter()
                .map(place)
                .collect::<Option<Vec<DVec3>>>()
                .ok_or_else(|| poly.points.clone())?;
            let tris = triangulate(&at, &poly.lines).ok_or_else(|| poly.points.clone())?;
            Ok(tris.iter().map(|t| t.map(|i| poly.points[i])).collect())
        })
        .collect();
    let mut keyed: Vec<[Point; 3]> = Vec::new();
    for p in pieces {
        keyed.extend(p?);
    }
    keyed.extend_from_slice(&fill.triangles);

    let input = grid.mesh;
    let mut index = vec![u32::MAX; input.positions.len()];
    for &t in &cut.untouched {
        for v in input.triangles[t as usize] {
            index[v as usize] = 0;
        }
    }
    for tri in &keyed {
        for p in tri {
            if let Point::Vertex(v) = *p {
                index[v as usize] = 0;
            }
        }
    }
    let mut points: Vec<Point> = Vec::new();
    let mut positions = Vec::new();
    for (v, slot) in index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = points.len() as u32;
            points.push(Point::Vertex(v as u32));
            positions.push(input.positions[v]);
        }
    }
    let mut new_index: FxHashMap<Point, u32> = FxHashMap::default();
    let mut triangles: Vec<[u32; 3]> = cut
        .untouched
        .iter()
        .map(|&t| input.triangles[t as usize].map(|v| index[v as usize]))
        .collect();
    for tri in &keyed {
        let mut out = [0u32; 3];
        for (k, p) in tri.iter().enumerate() {
            out[k] = match *p {
                Point::Vertex(v) => index[v as usize],
                _ => match new_index.get(p) {
                    Some(&i) => i,
                    None => {
                        let at = match p {
                            Point::Centre { .. } => centres.get(p).copied(),
                            _ => place(p),
                        }
                        .ok_or_else(|| tri.to_vec())?;
                        let i = points.len() as u32;
                        points.push(*p);
                        positions.push(at.as_vec3());
                        new_index.insert(*p, i);
                        i
                    }
                },
            };
        }
        triangles.push(out);
    }
    Ok(Built {
        mesh: IndexedMesh::new(positions, triangles),
        points,
        parameters,
    })
}
