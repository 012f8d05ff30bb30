//! Cell faces pierced by mesh edges and cells overlapped by triangles: consistent with the
//! crossings (one perturbed configuration), with the vertex cells, and with a geometric overlap
//! test wherever that test is unambiguous.

pub mod grid_support;

use std::collections::BTreeSet;

use glam::{DVec3, Vec3};
use grid_support::*;
use surftrack::compute::Backend;
use surftrack::grid::{
    EdgeFace, GridFrame, LatticeMesh, cells_around, edge_faces, footprint, mesh_edges, rasterize,
    triangle_cells,
};
use surftrack::mesh::IndexedMesh;

fn meshes() -> Vec<(GridFrame, IndexedMesh)> {
    let mut quarter = IndexedMesh::icosphere(Vec3::new(0.3, 0.1, -0.2), 2.7, 2);
    for p in &mut quarter.positions {
        *p = (*p * 4.0).round() / 4.0;
    }
    let unit = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
    vec![
        (
            GridFrame::new(Vec3::new(0.1, 0.2, 0.3), 0.37).unwrap(),
            IndexedMesh::icosphere(Vec3::new(0.3, -0.2, 0.1), 2.0, 2),
        ),
        (
            GridFrame::new(Vec3::ZERO, 0.3).unwrap(),
            IndexedMesh::torus(1.5, 0.6, 24, 12),
        ),
        (unit, quarter),
        (unit, grid_box(&unit, [-2, -1, 0], [2, 3, 3])),
    ]
}

/// Walking each mesh edge through its faces leads from its first endpoint's cell to its second's,
/// one face at a time, in increasing order along the edge.
#[test]
fn edge_walks_chain_cells() {
    for (frame, mesh) in meshes() {
        let lattice = LatticeMesh::new(frame, &mesh).unwrap();
        let faces = edge_faces(&lattice);
        let edges = mesh_edges(&mesh.triangles);
        assert_eq!(edges.len(), mesh.triangles.len() * 3 / 2);
        let mut k = 0;
        for edge in edges {
            let mut cell = lattice.vertex_cell(edge[0]);
            let mut last_s = 0.0f32;
            while k < faces.len() && faces[k].edge == edge {
                let f: &EdgeFace = &faces[k];
                let [below, above] = f.cells();
                if f.upward {
                    assert_eq!(cell, below, "edge {edge:?} face {k}");
                    cell = above;
                } else {
                    assert_eq!(cell, above, "edge {edge:?} face {k}");
                    cell = below;
                }
                assert!(f.s > 0.0 && f.s < 1.0 && f.s >= last_s - 1e-6, "{f:?}");
                last_s = f.s;
                k += 1;
            }
            assert_eq!(cell, lattice.vertex_cell(edge[1]), "edge {edge:?}");
        }
        assert_eq!(k, faces.len());
    }
}

/// Does the triangle meet the box `[lo, hi]`? Separating-axis test (Akenine-Möller) in f64.
fn triangle_meets_box(t: [DVec3; 3], lo: DVec3, hi: DVec3) -> bool {
    let c = (lo + hi) * 0.5;
    let h = (hi - lo) * 0.5;
    let v = t.map(|p| p - c);
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let separated = |axis: DVec3| {
        let p = v.map(|x| x.dot(axis));
        let r = h.x * axis.x.abs() + h.y * axis.y.abs() + h.z * axis.z.abs();
        p.iter().cloned().fold(f64::INFINITY, f64::min) > r
            || p.iter().cloned().fold(f64::NEG_INFINITY, f64::max) < -r
    };
    for a in [DVec3::X, DVec3::Y, DVec3::Z] {
        if separated(a) {
            return false;
        }
        for edge in e {
            let axis = a.cross(edge);
            if axis.length_squared() > 0.0 && separated(axis) {
                return false;
            }
        }
    }
    let n = e[0].cross(e[1]);
    !(n.length_squared() > 0.0 && separated(n))
}

/// The cells of each triangle contain its vertices' cells and the four cells around each of its
/// grid-edge crossings (thesis §3.4.2's check); a cell that the triangle meets with a margin is
/// listed, one it misses by a margin is not; the footprint is the union of all lists.
#[test]
fn triangle_cells_agree_with_crossings_and_geometry() {
    for (frame, mesh) in meshes() {
        let lattice = LatticeMesh::new(frame, &mesh).unwrap();
        let crossings = rasterize(&Backend::Cpu, &lattice).unwrap();
        let faces = edge_faces(&lattice);
        let cells = triangle_cells(&lattice, &crossings, &faces);
        assert_eq!(cells.len(), mesh.triangles.len());
        for c in crossings.all() {
            let listed = cells.of(c.triangle as usize);
            for around in cells_around(c) {
                assert!(listed.binary_search(&around).is_ok(), "{c:?}: {around:?}");
            }
        }
        let margin = 1e-4;
        let mut union = BTreeSet::new();
        for (t, tri) in mesh.triangles.iter().enumerate() {
            let listed = cells.of(t);
            assert!(listed.windows(2).all(|w| w[0] < w[1]));
            for &v in tri {
                assert!(listed.binary_search(&lattice.vertex_cell(v)).is_ok());
            }
            let g = tri.map(|v| DVec3::from_array(frame.to_grid(mesh.positions[v as usize])));
            let lo = g.iter().fold(DVec3::INFINITY, |a, &b| a.min(b)).floor() - 1.0;
            let hi = g.iter().fold(DVec3::NEG_INFINITY, |a, &b| a.max(b)).floor() + 1.0;
            for cell in box_corners(lo.as_ivec3().to_array(), hi.as_ivec3().to_array()) {
                let low = DVec3::from_array(cell.map(f64::from));
                let inner = triangle_meets_box(g, low + margin, low + 1.0 - margin);
                let outer = triangle_meets_box(g, low - margin, low + 1.0 + margin);
                let is_listed = listed.binary_search(&cell).is_ok();
                assert!(
                    !inner || is_listed,
                    "triangle {t} meets {cell:?} but misses it"
                );
                assert!(
                    outer || !is_listed,
                    "triangle {t} misses {cell:?} but lists it"
                );
            }
            union.extend(listed.iter().map(|c| [c[2], c[1], c[0]]));
        }
        let all = footprint(&lattice, &crossings, &faces);
        let union: Vec<[i32; 3]> = union.into_iter().map(|c| [c[2], c[1], c[0]]).collect();
        assert_eq!(all, union);
    }
}
