//! First checks of constrain_topology on analytic shapes.

use glam::Vec3;
use surftrack::compute::Backend;
use surftrack::grid::{GridFrame, ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::topology::{Field, TopologyOptions, constrain_topology};

fn balls(centers: &[(Vec3, f32)]) -> impl Fn(Vec3) -> f32 + Sync + '_ {
    move |p| {
        centers
            .iter()
            .map(|(c, r)| (p - *c).length() - r)
            .fold(f32::INFINITY, f32::min)
    }
}

fn extract(f: &(dyn Fn(Vec3) -> f32 + Sync), origin: Vec3, spacing: f32, n: usize) -> IndexedMesh {
    let grid = ScalarGrid::from_fn(origin, spacing, [n; 3], f).unwrap();
    marching_cubes(&grid, 0.0)
}

fn euler_list(mesh: &IndexedMesh) -> Vec<i64> {
    let mut e: Vec<i64> = mesh.topology().components.iter().map(|c| c.euler).collect();
    e.sort_unstable();
    e
}

fn run(m: &IndexedMesh, frame: GridFrame, f: &(dyn Fn(Vec3) -> f32 + Sync), lo: i32, hi: i32) {
    let theta = Field::from_fn(frame, [lo; 3], [hi; 3], f).unwrap();
    let reference = {
        let n = (hi - lo + 3) as usize;
        let origin = frame.corner_position([lo - 1; 3]);
        let grid = ScalarGrid::from_fn(origin, frame.spacing(), [n; 3], |p| {
            let g = ((p - frame.origin()) / frame.spacing()).round();
            if g.min_element() < lo as f32 || g.max_element() > hi as f32 {
                frame.spacing()
            } else {
                f(p)
            }
        })
        .unwrap();
        marching_cubes(&grid, 0.0)
    };
    let mut mesh = Mesh::from_indexed(m).unwrap();
    let report = constrain_topology(&mut mesh, &theta, &TopologyOptions::default()).unwrap();
    let out = mesh.to_indexed();
    eprintln!(
        "{:?} seeds {} region {} kept {} deleted {} cut {} patch {} euler {:?} ref {:?}",
        report.resampling,
        report.seed_cells,
        report.region_cells,
        report.kept,
        report.deleted,
        report.cut,
        report.patch,
        report.euler,
        euler_list(&reference)
    );
    if !out.triangles.is_empty() {
        out.validate().unwrap();
    }
    assert_eq!(euler_list(&out), euler_list(&reference));
    report.events.check().unwrap();
}

#[test]
fn merge_two_spheres() {
    let spacing = 0.1;
    let frame = GridFrame::new(Vec3::ZERO, spacing).unwrap();
    let a = [
        (Vec3::new(-0.55, 0.03, 0.01), 0.45),
        (Vec3::new(0.55, 0.0, 0.0), 0.45),
    ];
    let m = extract(
        &balls(&a),
        Vec3::splat(-1.5) + Vec3::new(0.013, 0.027, 0.041),
        0.09,
        36,
    );
    let b = [
        (Vec3::new(-0.4, 0.03, 0.01), 0.45),
        (Vec3::new(0.4, 0.0, 0.0), 0.45),
    ];
    run(&m, frame, &balls(&b), -14, 14);
}

#[test]
fn same_shape_is_untouched() {
    let frame = GridFrame::new(Vec3::ZERO, 0.1).unwrap();
    let a = [(Vec3::new(0.02, 0.03, 0.01), 0.6)];
    let m = extract(
        &balls(&a),
        Vec3::splat(-1.0) + Vec3::new(0.013, 0.027, 0.041),
        0.09,
        24,
    );
    run(&m, frame, &balls(&a), -12, 12);
    let phi = Field::signed_distance(&Backend::Cpu, frame, &m).unwrap();
    let mut mesh = Mesh::from_indexed(&m).unwrap();
    let report = constrain_topology(&mut mesh, &phi, &TopologyOptions::default()).unwrap();
    assert!(!report.changed());
}

#[test]
fn new_component_appears() {
    let frame = GridFrame::new(Vec3::ZERO, 0.1).unwrap();
    let a = [(Vec3::new(-0.5, 0.03, 0.01), 0.4)];
    let m = extract(
        &balls(&a),
        Vec3::splat(-1.5) + Vec3::new(0.013, 0.027, 0.041),
        0.09,
        36,
    );
    let b = [
        (Vec3::new(-0.5, 0.03, 0.01), 0.4),
        (Vec3::new(0.7, 0.0, 0.0), 0.3),
    ];
    run(&m, frame, &balls(&b), -14, 14);
}
