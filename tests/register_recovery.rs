//! Registration recovers known motions of independently re-meshed shapes (issue 5, bar 2).
#![allow(dead_code)]

use glam::{Quat, Vec3};
use surftrack::compute::Backend;
use surftrack::grid::{ScalarGrid, marching_cubes};
use surftrack::mesh::{IndexedMesh, Mesh, NormalWeighting};
use surftrack::project::{Bvh, ProjectOptions, Status, closest_points, project};
use surftrack::register::{RegisterOptions, RegistrationReport, register};
use surftrack::synth::{Ball, Field, RigidTransform};

/// The `rigid` scene's featured box in object space.
fn featured_box(transform: RigidTransform) -> Field {
    Field::FeaturedBox {
        half_extents: [0.55, 0.35, 0.3],
        rounding: 0.08,
        bump: Ball {
            center: [0.55, 0.0, 0.0],
            radius: 0.16,
        },
        notch: Ball {
            center: [-0.2, 0.0, 0.3],
            radius: 0.18,
        },
        transform,
    }
}

/// Marching cubes of `field` over `[lo, hi]` with cells of `spacing`, the grid shifted by `jitter`
/// cells so that two calls never share a triangulation.
fn extract(
    field: impl Fn(Vec3) -> f32 + Sync,
    lo: Vec3,
    hi: Vec3,
    spacing: f32,
    jitter: Vec3,
) -> IndexedMesh {
    let origin = lo - spacing * (Vec3::splat(2.0) + jitter);
    let dims = ((hi - origin) / spacing).ceil().as_uvec3() + glam::UVec3::splat(3);
    let grid = ScalarGrid::from_fn(
        origin,
        spacing,
        [dims.x as usize, dims.y as usize, dims.z as usize],
        field,
    )
    .unwrap();
    marching_cubes(&grid, 0.0)
}

/// Distance of each registered vertex from its ground-truth material point, in mean edge lengths:
/// the truth is the source vertex moved by the known map, then snapped to the nearest point of the
/// target (the two triangulations approximate the surface independently; snapping removes that
/// discretization offset, which is not the registration's error).
fn errors(moved: &[Vec3], truth: &[Vec3], bvh: &Bvh, unit: f32) -> Vec<f32> {
    let snapped = closest_points(&Backend::Cpu, bvh, truth, f32::INFINITY).unwrap();
    moved
        .iter()
        .zip(&snapped)
        .map(|(p, c)| p.distance(c.point) / unit)
        .collect()
}

fn summary(name: &str, e: &[f32]) -> (f32, f32) {
    let mut s = e.to_vec();
    s.sort_by(f32::total_cmp);
    let q = |f: f32| s[((s.len() - 1) as f32 * f) as usize];
    let mean = s.iter().sum::<f32>() / s.len() as f32;
    println!(
        "{name}: mean {mean:.4} median {:.4} p90 {:.4} p99 {:.4} max {:.4} (mean edge lengths)",
        q(0.5),
        q(0.9),
        q(0.99),
        q(1.0)
    );
    (mean, q(1.0))
}

fn print_report(report: &RegistrationReport) {
    for (k, stage) in report.coarse.stages.iter().enumerate() {
        let energies: Vec<String> = stage
            .iterations
            .iter()
            .map(|i| format!("{:.4e}", i.energy))
            .collect();
        if let Some(last) = stage.iterations.last() {
            println!(
                "  last: fit {:.4e} rigid {:.4e} smooth {:.4e} kept {} pruned {}",
                last.fit, last.rigid, last.smooth, last.kept, last.pruned
            );
        }
        println!(
            "stage {k} α_reg {} start {:.4e} converged {} [{}]",
            stage.alpha_reg,
            stage.energy_start,
            stage.converged,
            energies.join(", ")
        );
    }
    for r in &report.fine.rounds {
        println!(
            "fine: kept {} pruned {} E {:.4e} → {:.4e} cg {} residual {:.2e}",
            r.kept, r.pruned, r.energy_before, r.energy, r.cg_iterations, r.residual
        );
    }
    println!(
        "nodes {} unknowns {} nnz {} factor nnz {} | setup {:?} coarse {:?} (setup {:?}, {:?}) fine {:?} total {:?}",
        report.coarse.nodes,
        report.coarse.unknowns,
        report.coarse.matrix_nonzeros,
        report.coarse.factor_nonzeros,
        report.setup_time,
        report.coarse_time,
        report.coarse.setup,
        report.coarse.times,
        report.fine_time,
        report.total_time
    );
}

/// Registers `source` onto `target`, where the true map is `truth`; returns (registration,
/// projection) error summaries.
fn recover(
    source: &IndexedMesh,
    target: &IndexedMesh,
    truth: impl Fn(Vec3) -> Vec3,
) -> (f32, f32, f32) {
    let unit = source.mean_edge_length();
    println!(
        "source {} vertices, target {} vertices, unit {unit}",
        source.positions.len(),
        target.positions.len()
    );
    let mut mesh = Mesh::from_indexed(source).unwrap();
    let mut options = RegisterOptions::default();
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
    if let Some(v) = env("RELAX") {
        options.coarse.relax_threshold = v;
    }
    if let Some(v) = env("ITERS") {
        options.coarse.max_stage_iterations = v as usize;
    }
    if let Some(v) = env("FLOOR") {
        options.coarse.alpha_reg_floor = v;
    }
    if let Some(v) = env("POINT") {
        options.coarse.point_weight = v;
    }
    if let Some(v) = env("SAMPLE") {
        options.coarse.sample_spacing = v as f32;
    }
    if let Some(v) = env("START") {
        options.coarse.alpha_reg_start = v;
    }
    if let Some(v) = env("SMOOTH") {
        options.coarse.smooth_weight = v;
    }
    if let Some(v) = env("GRAPH") {
        options.graph.spacing = v as f32;
    }
    if let Some(v) = env("FINE") {
        options.fine.rounds = v as usize;
    }
    let report = register(&Backend::Cpu, &mut mesh, target, &options).unwrap();
    print_report(&report);
    let moved = mesh.to_indexed().positions;
    let truths: Vec<Vec3> = source.positions.iter().map(|&p| truth(p)).collect();
    let bvh = Bvh::build(target).unwrap();
    let registered = errors(&moved, &truths, &bvh, unit);
    let (_, max) = summary("registration", &registered);
    let mut worst: Vec<usize> = (0..registered.len()).collect();
    worst.sort_by(|&a, &b| registered[b].total_cmp(&registered[a]));
    for &v in worst.iter().take(6) {
        println!(
            "  vertex {v} at {:?}: error {:.3} moved {:?} truth {:?}",
            source.positions[v], registered[v], moved[v], truths[v]
        );
    }
    for b in 0..16 {
        let lo = -0.8 + 0.1 * b as f32;
        let sel: Vec<f32> = (0..registered.len())
            .filter(|&v| (lo..lo + 0.1).contains(&source.positions[v].x))
            .map(|v| registered[v])
            .collect();
        if !sel.is_empty() {
            println!(
                "  x in [{lo:.1}, {:.1}): mean error {:.3} ({} vertices)",
                lo + 0.1,
                sel.iter().sum::<f32>() / sel.len() as f32,
                sel.len()
            );
        }
    }
    let closest: Vec<Vec3> = closest_points(&Backend::Cpu, &bvh, &source.positions, f32::INFINITY)
        .unwrap()
        .iter()
        .map(|c| c.point)
        .collect();
    let (baseline, _) = summary(
        "closest-point projection",
        &errors(&closest, &truths, &bvh, unit),
    );
    let normals = source.vertex_normals(NormalWeighting::Max);
    let rays = project(
        &Backend::Cpu,
        &bvh,
        &source.positions,
        &normals,
        &ProjectOptions::default(),
    )
    .unwrap();
    let hit: Vec<(Vec3, Vec3)> = rays
        .iter()
        .zip(&truths)
        .filter(|(c, _)| c.status() == Status::Accepted)
        .map(|(c, t)| (c.point, *t))
        .collect();
    let (points, t): (Vec<Vec3>, Vec<Vec3>) = hit.into_iter().unzip();
    summary(
        "normal-ray projection (hits only)",
        &errors(&points, &t, &bvh, unit),
    );
    assert!(report.converged(), "registration did not converge");
    (max, baseline, unit)
}

/// Four blended Gaussian blobs in an asymmetric arrangement: smooth everywhere (marching cubes
/// approximates it to a small fraction of a cell, unlike a sharp crease, which two
/// triangulations round off differently) and without symmetries a rigid motion could hide in.
fn blobs(transform: RigidTransform) -> Field {
    Field::Metaballs {
        centers: vec![
            [-0.35, 0.0, 0.0],
            [0.3, 0.05, 0.0],
            [0.05, 0.3, 0.1],
            [0.1, -0.1, 0.3],
        ],
        width: 0.3,
        threshold: 0.5,
        transform,
    }
}

#[test]
#[ignore = "issue 5: the 0.1-edge-length recovery bar is not met yet"]
fn rigid_motion_is_recovered() {
    let spacing = 0.025;
    let (lo, hi) = (Vec3::splat(-0.9), Vec3::splat(0.9));
    let source_field = blobs(RigidTransform::new(Quat::IDENTITY, Vec3::ZERO));
    let source = extract(
        |p| source_field.value(p),
        lo,
        hi,
        spacing,
        Vec3::new(0.13, 0.41, 0.77),
    );
    let unit = source.mean_edge_length();
    let axis = Vec3::new(0.3, 1.0, 0.5).normalize();
    let pivot = Vec3::new(0.4, -0.3, 0.2);
    let rotation = Quat::from_axis_angle(axis, 20f32.to_radians());
    let shift = 2.0 * unit * Vec3::new(1.0, -0.5, 0.3).normalize();
    let motion = move |p: Vec3| rotation * (p - pivot) + pivot + shift;
    let translation = motion(Vec3::ZERO);
    let target_field = blobs(RigidTransform::new(rotation, translation));
    let target = extract(
        |p| target_field.value(p),
        lo - Vec3::splat(0.4),
        hi + Vec3::splat(0.4),
        spacing,
        Vec3::new(0.61, 0.07, 0.35),
    );
    let (max, baseline, _) = recover(&source, &target, motion);
    assert!(
        max < 0.1,
        "max error {max} mean edge lengths (projection baseline mean {baseline})"
    );
}

/// A knobbly bar along x: blobs on its axis with smaller ones alternating above and below.
fn bar(p: Vec3) -> f32 {
    let mut sum = 0.0;
    for k in 0..7 {
        let x = -0.6 + 0.2 * k as f32;
        sum += (-(p - Vec3::new(x, 0.0, 0.0)).length_squared() / 0.04).exp();
        let side = if k % 2 == 0 { 0.12 } else { -0.12 };
        sum += 0.6 * (-(p - Vec3::new(x + 0.1, side, 0.05)).length_squared() / 0.015).exp();
    }
    0.5 - sum
}

/// Bends the x axis onto a circle of curvature `kappa` (centre at `(0, 1/κ, 0)`), keeping the
/// distance from the axis: arc length along x, offsets in y along the circle's normal.
fn bend(kappa: f32) -> (impl Fn(Vec3) -> Vec3 + Copy, impl Fn(Vec3) -> Vec3 + Copy) {
    let forward = move |p: Vec3| {
        let theta = kappa * p.x;
        let (s, c) = theta.sin_cos();
        Vec3::new(s / kappa - p.y * s, (1.0 - c) / kappa + p.y * c, p.z)
    };
    let inverse = move |q: Vec3| {
        let r = Vec3::new(q.x, q.y - 1.0 / kappa, 0.0);
        let theta = r.x.atan2(-r.y);
        Vec3::new(theta / kappa, 1.0 / kappa - r.truncate().length(), q.z)
    };
    (forward, inverse)
}

#[test]
#[ignore = "issue 5: the 0.1-edge-length recovery bar is not met yet"]
fn smooth_bend_is_recovered() {
    let spacing = 0.02;
    let (lo, hi) = (Vec3::new(-0.9, -0.4, -0.35), Vec3::new(0.9, 0.4, 0.4));
    let source = extract(bar, lo, hi, spacing, Vec3::new(0.31, 0.52, 0.18));
    let (forward, inverse) = bend(0.4);
    let target = extract(
        move |p| bar(inverse(p)),
        lo - Vec3::splat(0.3),
        hi + Vec3::new(0.3, 0.6, 0.3),
        spacing,
        Vec3::new(0.74, 0.26, 0.63),
    );
    let (max, baseline, _) = recover(&source, &target, forward);
    assert!(
        max < 0.1,
        "max error {max} mean edge lengths (projection baseline mean {baseline})"
    );
}

/// A chain of nine pearls along x, of alternating sizes, joined by narrower necks.
fn pearls(p: Vec3) -> f32 {
    let mut sum = 0.0;
    for k in 0..9 {
        let x = -0.64 + 0.16 * k as f32;
        let weight = if k % 2 == 0 { 1.0 } else { 0.8 };
        sum += weight * (-(p - Vec3::new(x, 0.0, 0.0)).length_squared() / 0.006).exp();
        let angle = 1.9 * k as f32;
        let bump = Vec3::new(x + 0.02, 0.065 * angle.cos(), 0.065 * angle.sin());
        sum += 0.5 * (-(p - bump).length_squared() / 0.0012).exp();
    }
    for tip in [Vec3::new(-0.7, 0.035, 0.0), Vec3::new(0.7, 0.0, -0.035)] {
        sum += 0.5 * (-(p - tip).length_squared() / 0.0012).exp();
    }
    0.5 - sum
}

#[test]
fn probe_same_triangulation_bend() {
    let spacing: f32 = std::env::var("H")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0.012);
    let (lo, hi) = (Vec3::new(-0.8, -0.15, -0.15), Vec3::new(0.8, 0.15, 0.15));
    let source = extract(pearls, lo, hi, spacing, Vec3::new(0.31, 0.52, 0.18));
    println!("topology {:?}", source.topology().components.len());
    let (forward, inverse) = bend(
        std::env::var("KAPPA")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(0.4),
    );
    let target = if std::env::var("SAME").is_ok() {
        let mut target = source.clone();
        for p in &mut target.positions {
            *p = forward(*p);
        }
        target
    } else {
        extract(
            move |p| pearls(inverse(p)),
            lo - Vec3::splat(0.2),
            hi + Vec3::new(0.2, 0.3, 0.2),
            spacing,
            Vec3::new(0.74, 0.26, 0.63),
        )
    };
    recover(&source, &target, forward);
}
