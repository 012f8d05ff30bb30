//! Registration of a body with a spray of droplets around it, each droplet moving its own way.
//! A droplet's part of the Gauss-Newton matrix changes by orders between iterations, so the coarse
//! stage factors each small component of the graph exactly at every solve: conjugate gradients then
//! converge as fast as on the body alone, instead of running to their iteration cap on a kept
//! factor (here, without the exact blocks: 1,372 iterations over 71 steps, solves at the cap; with
//! them: 3 over 62).

use glam::Vec3;
use surftrack::compute::Backend;
use surftrack::grid::{ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::{Bvh, closest_points};
use surftrack::register::{RegisterOptions, Target, register};

/// The body's centre and radius, and the droplets' centres (radius `DROPLET`), in cells.
const BODY: (Vec3, f32) = (Vec3::new(15.0, 6.0, 12.0), 9.0);
const DROPLET: f32 = 1.6;

fn droplets() -> Vec<Vec3> {
    let mut centres = Vec::new();
    for i in 0..5 {
        for j in 0..3 {
            for k in 0..4 {
                centres.push(Vec3::new(
                    3.0 + 6.0 * i as f32,
                    19.0 + 5.0 * j as f32,
                    3.0 + 6.0 * k as f32,
                ));
            }
        }
    }
    centres
}

/// Droplet `i`'s own motion, up to half a cell.
fn motion(i: usize) -> Vec3 {
    let t = i as f32;
    0.5 * Vec3::new((1.3 * t).sin(), (2.1 * t).cos(), (0.7 * t).sin())
}

/// Marching cubes of the body and the droplets, each moved by `moved(index)` (the body is index
/// `usize::MAX`), on a grid shifted by `jitter` cells.
fn spray(moved: impl Fn(usize) -> Vec3 + Sync, jitter: f32) -> IndexedMesh {
    let centres: Vec<Vec3> = droplets()
        .iter()
        .enumerate()
        .map(|(i, c)| *c + moved(i))
        .collect();
    let body = BODY.0 + moved(usize::MAX);
    let field = |p: Vec3| {
        centres
            .iter()
            .map(|c| p.distance(*c) - DROPLET)
            .fold(p.distance(body) - BODY.1, f32::min)
    };
    let origin = Vec3::splat(-4.0 - jitter);
    let grid = ScalarGrid::from_fn(origin, 1.0, [40, 40, 36], field).unwrap();
    marching_cubes(&grid, 0.0)
}

#[test]
fn droplets_moving_their_own_ways_register_without_stalled_solves() {
    let source = spray(|_| Vec3::ZERO, 0.0);
    let target = spray(
        |i| {
            if i == usize::MAX {
                Vec3::new(0.3, 0.0, 0.0)
            } else {
                motion(i)
            }
        },
        0.37,
    );
    assert_eq!(source.topology().components.len(), 61);
    let unit = source.mean_edge_length();
    let mut mesh = Mesh::from_indexed(&source).unwrap();
    let options = RegisterOptions::default();
    let report = register(&Backend::Cpu, &mut mesh, Target::Mesh(&target), &options).unwrap();
    assert!(report.converged(), "{report:#?}");
    let iterations: Vec<_> = report
        .coarse
        .stages
        .iter()
        .flat_map(|s| &s.iterations)
        .collect();
    let cg: usize = iterations.iter().map(|i| i.cg_iterations).sum();
    let cap = options.coarse.max_cg_iterations;
    eprintln!(
        "{} Gauss-Newton iterations, {cg} CG iterations",
        iterations.len()
    );
    assert!(
        iterations.iter().all(|i| i.cg_iterations < cap),
        "a solve ran to the cap of {cap}: {:?}",
        iterations
            .iter()
            .map(|i| i.cg_iterations)
            .collect::<Vec<_>>()
    );
    assert!(
        cg <= 10 * iterations.len(),
        "{cg} CG iterations for {} steps",
        iterations.len()
    );
    // Every vertex ends on the target: the droplets followed their own motions.
    let bvh = Bvh::build(&target).unwrap();
    let moved = mesh.to_indexed().positions;
    let found = closest_points(&Backend::Cpu, &bvh, &moved, f32::INFINITY).unwrap();
    let worst = moved
        .iter()
        .zip(&found)
        .map(|(p, c)| p.distance(c.point) / unit)
        .fold(0.0, f32::max);
    assert!(
        worst <= 0.25,
        "a vertex ends {worst} edge lengths off the target"
    );
}
