//! Θ's own isosurface, extracted cell by cell with the grid's case table over the cells where Θ
//! changes sign only: the surface the result's topology must match, and the result itself when the
//! whole surface is replaced.

use rustc_hash::FxHashMap;

use super::field::Field;
use super::keys::{Cell, GridEdge, cell_edge};
use super::place::to_world;
use crate::grid::cases::cell_case;
use crate::mesh::IndexedMesh;
use glam::DVec3;

/// The isosurface of Θ over `cells` (sorted) and the grid edge each vertex lies on.
pub(crate) fn isosurface(field: &Field, cells: &[Cell]) -> (IndexedMesh, Vec<GridEdge>) {
    let mut index: FxHashMap<GridEdge, u32> = FxHashMap::default();
    let mut edges: Vec<GridEdge> = Vec::new();
    let mut triangles = Vec::new();
    for &cell in cells {
        let case = cell_case(field.config(cell));
        for t in &case.triangles {
            triangles.push(t.map(|e| {
                let edge = cell_edge(cell, usize::from(e));
                *index.entry(edge).or_insert_with(|| {
                    edges.push(edge);
                    edges.len() as u32 - 1
                })
            }));
        }
    }
    let frame = field.frame();
    let positions = edges
        .iter()
        .map(|edge| {
            let mut g = DVec3::from_array(edge.corner.map(f64::from));
            g[edge.axis()] += f64::from(field.crossing(*edge));
            to_world(frame, g).as_vec3()
        })
        .collect();
    (IndexedMesh::new(positions, triangles), edges)
}

/// The topology the result must have: the Euler characteristic of every component, sorted.
pub(crate) fn signature(mesh: &IndexedMesh) -> Vec<i64> {
    let mut euler: Vec<i64> = mesh.topology().components.iter().map(|c| c.euler).collect();
    euler.sort_unstable();
    euler
}
