//! Narrow-band signed distance on both backends against brute force in f64 on the unsnapped mesh:
//! every corner within the band is present with its distance to 1e-5 cell, the sign is the
//! winding's, and nothing outside the band is stored.

pub mod grid_support;

use glam::Vec3;
use grid_support::*;
use surftrack::compute::Backend;
use surftrack::compute::parity::run_on_gpu;
use surftrack::grid::{
    GridFrame, LatticeMesh, NarrowBand, RasterError, edge_faces, footprint, rasterize,
    signed_distance, sweep,
};
use surftrack::mesh::IndexedMesh;

/// Allowed error of a distance, in cells.
const TOLERANCE: f64 = 1e-5;

fn band(backend: &Backend, frame: GridFrame, mesh: &IndexedMesh, half_width: f32) -> NarrowBand {
    let lattice = LatticeMesh::new(frame, mesh).unwrap();
    let crossings = rasterize(backend, &lattice).unwrap();
    let windings = sweep(backend, &crossings).unwrap();
    let faces = edge_faces(&lattice);
    let cells = footprint(&lattice, &crossings, &faces);
    signed_distance(backend, &lattice, &cells, &windings, half_width).unwrap()
}

fn check(backend: &Backend, frame: GridFrame, mesh: &IndexedMesh, half_width: f32) {
    let band = band(backend, frame, mesh, half_width);
    let spacing = f64::from(frame.spacing());
    let hw = f64::from(half_width);
    let (lo, hi) = cell_box(&frame, mesh, half_width.ceil() as i32 + 1);
    let mut inside = 0;
    for c in box_corners(lo, hi) {
        let p = corner_world(&frame, c);
        let d = distance_reference(mesh, p) / spacing;
        match band.get(c) {
            Some(value) => {
                let got = f64::from(value) / spacing;
                assert!(d <= hw + TOLERANCE, "{c:?} at {d} cells is stored");
                assert!(
                    (got.abs() - d).abs() < TOLERANCE,
                    "{c:?}: |{got}| vs reference {d}"
                );
                if d > 1e-6 {
                    let w = winding_reference(mesh, p);
                    assert_eq!(got < 0.0, w >= 1, "{c:?}: sign of {got} with winding {w}");
                    inside += usize::from(w >= 1);
                }
            }
            None => assert!(d >= hw - TOLERANCE, "{c:?} at {d} cells is missing"),
        }
    }
    assert!(inside > 0);
    assert!(
        band.corners()
            .windows(2)
            .all(|w| { [w[0][2], w[0][1], w[0][0]] < [w[1][2], w[1][1], w[1][0]] })
    );
    assert_eq!(band.values().len(), band.len());
    assert_eq!(band.nearest().len(), band.len());
    for (k, &c) in band.corners().iter().enumerate().step_by(7) {
        let [a, b, cc] = mesh.triangles[band.nearest()[k] as usize]
            .map(|v| mesh.positions[v as usize].as_dvec3());
        let p = corner_world(&frame, c);
        let to_nearest = point_triangle_distance(p, a, b, cc) / spacing;
        assert!((to_nearest - f64::from(band.values()[k].abs()) / spacing).abs() < TOLERANCE);
    }
}

fn sphere(backend: &Backend) {
    let frame = GridFrame::new(Vec3::new(0.01, 0.02, -0.03), 0.4).unwrap();
    let mesh = IndexedMesh::icosphere(Vec3::new(0.3, -0.2, 0.1), 2.3, 3);
    check(backend, frame, &mesh, 3.0);
}

fn torus(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.27).unwrap();
    let mesh = IndexedMesh::torus(1.6, 0.5, 40, 20);
    check(backend, frame, &mesh, 2.5);
}

fn overlapping_spheres(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.35).unwrap();
    let mesh = union(&[
        IndexedMesh::icosphere(Vec3::new(-0.7, 0.03, 0.02), 1.5, 3),
        IndexedMesh::icosphere(Vec3::new(0.7, -0.05, 0.01), 1.5, 3),
    ]);
    check(backend, frame, &mesh, 1.5);
}

fn box_on_grid_planes(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.5).unwrap();
    let mesh = grid_box(&frame, [-2, -1, 0], [3, 2, 4]);
    check(backend, frame, &mesh, 2.0);
}

fn bad_half_width_is_an_error(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.5).unwrap();
    let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 1);
    let lattice = LatticeMesh::new(frame, &mesh).unwrap();
    let crossings = rasterize(backend, &lattice).unwrap();
    let windings = sweep(backend, &crossings).unwrap();
    for bad in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let result = signed_distance(backend, &lattice, &[], &windings, bad);
        assert!(matches!(result, Err(RasterError::Band(_))), "{result:?}");
    }
}

macro_rules! on_both_backends {
    ($($case:ident => $cpu:ident, $gpu:ident;)*) => {$(
        #[test]
        fn $cpu() {
            $case(&Backend::Cpu);
        }

        #[test]
        fn $gpu() {
            run_on_gpu($case);
        }
    )*};
}

on_both_backends! {
    sphere => sphere_cpu, sphere_gpu;
    torus => torus_cpu, torus_gpu;
    overlapping_spheres => overlapping_spheres_cpu, overlapping_spheres_gpu;
    box_on_grid_planes => box_on_grid_planes_cpu, box_on_grid_planes_gpu;
    bad_half_width_is_an_error => bad_half_width_is_an_error_cpu, bad_half_width_is_an_error_gpu;
}
