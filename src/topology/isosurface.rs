//! Θ's own isosurface, from the grid's case table over the cells where Θ changes sign only: the
//! topology the result must have, and the result itself when the whole surface is replaced.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::field::Field;
use super::keys::{Cell, GridEdge, cell_edge};
use super::place::to_world;
use crate::geometry::Components;
use crate::grid::cases::cell_case;
use crate::mesh::IndexedMesh;

/// The connectivity of Θ's isosurface over `cells` (sorted, with their configurations): one vertex
/// per grid edge where Θ's sign flips (in the order of [`Field::signs`]), triangles cell by cell;
/// positions are left at the origin until [`place_isosurface`] computes them.
pub(crate) fn isosurface(field: &Field, cells: &[(Cell, u8)]) -> (IndexedMesh, Vec<GridEdge>) {
    let edges: Vec<GridEdge> = field.signs().edges().collect();
    let index: FxHashMap<GridEdge, u32> = edges
        .iter()
        .enumerate()
        .map(|(i, &e)| (e, i as u32))
        .collect();
    let triangles: Vec<[u32; 3]> = cells
        .par_iter()
        .with_min_len(256)
        .flat_map_iter(|&(cell, config)| {
            let index = &index;
            cell_case(config).triangles.iter().map(move |t| {
                t.map(|e| {
                    let edge = cell_edge(cell, usize::from(e));
                    index.get(&edge).copied().unwrap_or(u32::MAX)
                })
            })
        })
        .collect();
    let positions = vec![Vec3::ZERO; edges.len()];
    (IndexedMesh::new(positions, triangles), edges)
}

/// Places the vertices of an isosurface from [`isosurface`] on Θ's zero set.
pub(crate) fn place_isosurface(field: &Field, mesh: &mut IndexedMesh, edges: &[GridEdge]) {
    mesh.positions = isosurface_positions(field, edges);
}

/// Where the vertices of an isosurface from [`isosurface`] lie on Θ's zero set: one on each grid
/// edge of `edges`, where Θ crosses it.
pub(crate) fn isosurface_positions(field: &Field, edges: &[GridEdge]) -> Vec<Vec3> {
    let frame = field.frame();
    edges
        .par_iter()
        .map(|edge| {
            let mut g = DVec3::from_array(edge.corner.map(f64::from));
            g[edge.axis()] += f64::from(field.crossing(*edge));
            to_world(frame, g).as_vec3()
        })
        .collect()
}

/// The topology the result must have: the Euler characteristic of every component, sorted.
///
/// For a closed triangle mesh every edge has two triangles, so a component with `V` vertices and
/// `F` triangles has `χ = V − 3F/2 + F = V − F/2`; components come from a union-find over the
/// triangles' corners, so no edge needs to be listed. Vertices no triangle uses are ignored.
pub(crate) fn signature(mesh: &IndexedMesh) -> Vec<i64> {
    let n = mesh.positions.len();
    if mesh.triangles.iter().flatten().any(|&v| v as usize >= n) {
        return vec![i64::MIN];
    }
    let mut components = Components::new(n, &mesh.triangles);
    let mut vertices = vec![0i64; n];
    let mut faces = vec![0i64; n];
    let mut used = vec![false; n];
    for t in &mesh.triangles {
        faces[components.find(t[0]) as usize] += 1;
        for &v in t {
            used[v as usize] = true;
        }
    }
    for v in 0..n as u32 {
        if used[v as usize] {
            vertices[components.find(v) as usize] += 1;
        }
    }
    let mut euler: Vec<i64> = (0..n)
        .filter(|&r| components.is_root(r as u32) && used[r])
        .map(|r| vertices[r] - faces[r] / 2)
        .collect();
    euler.sort_unstable();
    euler
}
