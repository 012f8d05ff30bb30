//! Inside/outside classification on both backends against answers known independently: every
//! corner farther than 1e-6 cell from the surface must carry the winding number that the solid
//! angles of the unsnapped mesh give (and, for primitives, the analytic inside test), the three
//! sweep directions must agree everywhere, and every grid line must return to winding 0.

pub mod grid_support;

use glam::{DVec3, Vec3};
use grid_support::*;
use surftrack::compute::Backend;
use surftrack::compute::parity::run_on_gpu;
use surftrack::grid::{GridFrame, LatticeMesh, Windings, rasterize, sweep};
use surftrack::mesh::IndexedMesh;

/// Corners within this distance (in cells) of the surface may go either way.
const ON_SURFACE: f64 = 1e-6;

fn windings(backend: &Backend, frame: GridFrame, mesh: &IndexedMesh) -> Windings {
    let lattice = LatticeMesh::new(frame, mesh).unwrap();
    let crossings = rasterize(backend, &lattice).unwrap();
    let windings = sweep(backend, &crossings).unwrap();
    assert!(
        windings.unbalanced_lines().is_empty(),
        "lines not returning to winding 0: {:?}",
        &windings.unbalanced_lines()[..windings.unbalanced_lines().len().min(5)]
    );
    windings
}

/// Checks every corner of the mesh's padded box; `analytic(p)` may assert a winding for world point
/// `p` at distance `d` (in cells) from the mesh. Returns how many corners were checked against the
/// references.
fn check(
    backend: &Backend,
    frame: GridFrame,
    mesh: &IndexedMesh,
    analytic: impl Fn(DVec3, f64) -> Option<i32>,
) -> usize {
    let w = windings(backend, frame, mesh);
    let (lo, hi) = cell_box(&frame, mesh, 2);
    let spacing = f64::from(frame.spacing());
    let mut checked = 0;
    for c in box_corners(lo, hi) {
        let got = w.corner(c);
        assert!(got.consistent(), "corner {c:?}: sweeps disagree {got:?}");
        let p = corner_world(&frame, c);
        let d = distance_reference(mesh, p) / spacing;
        if d <= ON_SURFACE {
            continue;
        }
        checked += 1;
        let reference = winding_reference(mesh, p);
        assert_eq!(got.0[0], reference, "corner {c:?} at distance {d:e} cells");
        if let Some(expected) = analytic(p, d) {
            assert_eq!(got.0[0], expected, "corner {c:?}: analytic answer");
        }
        assert_eq!(got.inside(), reference >= 1);
        assert_eq!(got.self_intersecting(), !(0..=1).contains(&reference));
    }
    checked
}

/// Inside a convex mesh: behind every face plane. `None` within `margin` of a plane.
fn convex_inside(mesh: &IndexedMesh, p: DVec3, margin: f64) -> Option<bool> {
    let mut inside = true;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
        let n = (b - a).cross(c - a).normalize();
        let s = n.dot(p - a);
        if s.abs() <= margin {
            return None;
        }
        inside &= s < 0.0;
    }
    Some(inside)
}

fn sphere(backend: &Backend) {
    let frame = GridFrame::new(Vec3::new(0.01, -0.02, 0.03), 0.5).unwrap();
    let center = Vec3::new(0.37, -0.21, 0.13);
    let mesh = IndexedMesh::icosphere(center, 3.3, 3);
    let checked = check(backend, frame, &mesh, |p, _| {
        convex_inside(&mesh, p, 1e-9).map(i32::from)
    });
    assert!(checked > 2000, "{checked}");
}

fn torus(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.31).unwrap();
    let (major, minor) = (2.0f64, 0.8f64);
    let mesh = IndexedMesh::torus(major as f32, minor as f32, 48, 24);
    // The mesh lies between the tube of radius minor·cos(π/24)·cos(π/48) and the tube itself.
    let inner =
        minor * (std::f64::consts::PI / 24.0).cos() * (std::f64::consts::PI / 48.0).cos() - 1e-3;
    check(backend, frame, &mesh, |p, _| {
        let ring = (DVec3::new(p.x, p.y, 0.0).length() - major).hypot(p.z);
        if ring < inner {
            Some(1)
        } else if ring > minor + 1e-6 {
            Some(0)
        } else {
            None
        }
    });
}

fn shell(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.4).unwrap();
    let c = Vec3::new(0.05, 0.11, -0.07);
    let outer = IndexedMesh::icosphere(c, 3.0, 3);
    let inner = flipped(&IndexedMesh::icosphere(c, 1.7, 3));
    let mesh = union(&[outer.clone(), inner.clone()]);
    check(backend, frame, &mesh, |p, _| {
        let a = convex_inside(&outer, p, 1e-9)?;
        let b = convex_inside(&flipped(&inner), p, 1e-9)?;
        Some(i32::from(a && !b))
    });
}

fn overlapping_spheres(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 0.35).unwrap();
    let a = IndexedMesh::icosphere(Vec3::new(-0.9, 0.03, 0.02), 2.0, 3);
    let b = IndexedMesh::icosphere(Vec3::new(0.9, -0.05, 0.01), 2.0, 3);
    let mesh = union(&[a.clone(), b.clone()]);
    let w = windings(backend, frame, &mesh);
    let (lo, hi) = cell_box(&frame, &mesh, 2);
    let mut flagged = 0;
    for c in box_corners(lo, hi) {
        let p = corner_world(&frame, c);
        let (Some(in_a), Some(in_b)) = (
            convex_inside(&a, p, 1e-6 * 0.35),
            convex_inside(&b, p, 1e-6 * 0.35),
        ) else {
            continue;
        };
        let got = w.corner(c);
        assert!(got.consistent(), "{c:?}: {got:?}");
        assert_eq!(got.0[0], i32::from(in_a) + i32::from(in_b), "{c:?}");
        assert_eq!(got.self_intersecting(), in_a && in_b, "{c:?}");
        flagged += usize::from(got.self_intersecting());
    }
    assert!(flagged > 50, "{flagged}");
    check(backend, frame, &mesh, |_, _| None);
}

/// A box whose vertices are grid corners and whose faces lie in grid planes: every grid line
/// through its faces runs along triangle edges or through vertices.
fn box_on_grid_planes(backend: &Backend) {
    let frame = GridFrame::new(Vec3::new(0.5, 0.25, -0.75), 0.25).unwrap();
    let (lo, hi) = ([-3, -2, 1], [4, 3, 5]);
    let mesh = grid_box(&frame, lo, hi);
    mesh.validate().unwrap();
    let w = windings(backend, frame, &mesh);
    for c in box_corners([-5, -4, -1], [6, 5, 7]) {
        let got = w.corner(c);
        assert!(got.consistent(), "{c:?}: {got:?}");
        let strictly_inside = (0..3).all(|a| lo[a] < c[a] && c[a] < hi[a]);
        let strictly_outside = (0..3).any(|a| c[a] < lo[a] || c[a] > hi[a]);
        if strictly_inside {
            assert_eq!(got.0[0], 1, "{c:?}");
        }
        if strictly_outside {
            assert_eq!(got.0[0], 0, "{c:?}");
        }
    }
}

/// An octahedron with vertices on grid corners: its faces `|x| + |y| + |z| = 3` contain grid
/// corners, and grid lines pass through its vertices and along none of its edges.
fn octahedron_through_corners(backend: &Backend) {
    let frame = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
    let o = Vec3::new(1.0, -2.0, 3.0);
    let positions = vec![
        o + Vec3::X * 3.0,
        o - Vec3::X * 3.0,
        o + Vec3::Y * 3.0,
        o - Vec3::Y * 3.0,
        o + Vec3::Z * 3.0,
        o - Vec3::Z * 3.0,
    ];
    let triangles = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let mesh = IndexedMesh::new(positions, triangles);
    mesh.validate().unwrap();
    let w = windings(backend, frame, &mesh);
    for c in box_corners([-3, -6, -1], [5, 2, 7]) {
        let got = w.corner(c);
        assert!(got.consistent(), "{c:?}: {got:?}");
        let l1 = (c[0] - 1).abs() + (c[1] + 2).abs() + (c[2] - 3).abs();
        if l1 != 3 {
            assert_eq!(got.0[0], i32::from(l1 < 3), "{c:?}");
        }
    }
}

/// Spheres whose vertices are rounded to quarter cells, shifted and scaled at random: vertices
/// on grid planes, edges through grid lines and slivers everywhere. Exactness shows as balanced
/// lines, agreeing sweeps and the right winding away from the surface.
fn dyadic_spheres(backend: &Backend) {
    let mut rng = Rng(7);
    for _ in 0..6 {
        let frame = GridFrame::new(Vec3::ZERO, 1.0).unwrap();
        let center = Vec3::new(rng.unit() as f32, rng.unit() as f32, rng.unit() as f32) * 4.0;
        let radius = 2.0 + 3.0 * rng.unit() as f32;
        let mut mesh = IndexedMesh::icosphere(center, radius, 2);
        for p in &mut mesh.positions {
            *p = (*p * 4.0).round() / 4.0;
        }
        check(backend, frame, &mesh, |_, _| None);
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
    shell => shell_cpu, shell_gpu;
    overlapping_spheres => overlapping_spheres_cpu, overlapping_spheres_gpu;
    box_on_grid_planes => box_on_grid_planes_cpu, box_on_grid_planes_gpu;
    octahedron_through_corners => octahedron_through_corners_cpu, octahedron_through_corners_gpu;
    dyadic_spheres => dyadic_spheres_cpu, dyadic_spheres_gpu;
}
