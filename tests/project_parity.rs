//! The GPU kernels against their CPU twins on the benchmark workload (a 100k-triangle synthetic
//! frame, 100k source vertices), the CPU path against an f64 brute force, and the CPU path's
//! independence from the thread count.
//!
//! Backends may round differently, so a line through a shared edge can hit either neighbour;
//! such disagreements must stay below 0.01% of the queries and are all listed. Where both pick
//! the same triangle the hit points agree within 1e-5 mean edge lengths.

#[path = "project_support/metaballs.rs"]
mod metaballs;
#[path = "project_support/workload.rs"]
mod workload;

use std::sync::OnceLock;

use glam::Vec3;
use surftrack::compute::Backend;
use surftrack::compute::parity::{ParityReport, run_on_gpu};
use surftrack::mesh::IndexedMesh;
use surftrack::project::{Bvh, Correspondence, ProjectOptions, Status, closest_points, project};
use workload::workload;

struct Workload {
    target: IndexedMesh,
    bvh: Bvh,
    points: Vec<Vec3>,
    normals: Vec<Vec3>,
}

fn shared() -> &'static Workload {
    static WORKLOAD: OnceLock<Workload> = OnceLock::new();
    WORKLOAD.get_or_init(|| {
        let (target, points, normals) = workload();
        let bvh = Bvh::build(&target).unwrap();
        Workload {
            target,
            bvh,
            points,
            normals,
        }
    })
}

/// Queries whose triangle (or miss) differs, listed in full; their share must stay below 1e-4.
/// Returns the indices where both sides hit the same triangle.
fn compare_triangles(what: &str, gpu: &[Correspondence], cpu: &[Correspondence]) -> Vec<usize> {
    assert_eq!(gpu.len(), cpu.len(), "{what}: lengths");
    let mut same = Vec::new();
    let mut listing = Vec::new();
    for (i, (g, c)) in gpu.iter().zip(cpu).enumerate() {
        if g.hit_triangle() == c.hit_triangle() {
            same.push(i);
        } else {
            listing.push(format!(
                "  [{i}] gpu {:?} triangle {:?} t {} at {} | cpu {:?} triangle {:?} t {} at {}",
                g.status(),
                g.hit_triangle(),
                g.distance,
                g.point,
                c.status(),
                c.hit_triangle(),
                c.distance,
                c.point
            ));
        }
    }
    let share = listing.len() as f64 / gpu.len().max(1) as f64;
    eprintln!(
        "{what}: {} of {} queries hit different triangles ({:.4}%)\n{}",
        listing.len(),
        gpu.len(),
        100.0 * share,
        listing.join("\n")
    );
    assert!(
        share <= 1e-4,
        "{what}: {} of {} queries disagree on the triangle:\n{}",
        listing.len(),
        gpu.len(),
        listing.join("\n")
    );
    same
}

fn pick<T: Copy>(
    values: impl Fn(&Correspondence) -> T,
    all: &[Correspondence],
    at: &[usize],
) -> Vec<T> {
    at.iter().map(|&i| values(&all[i])).collect()
}

#[test]
fn gpu_projection_matches_cpu_on_a_100k_triangle_frame() {
    run_on_gpu(|gpu| {
        let w = shared();
        assert!(w.target.triangles.len() >= 100_000 && w.points.len() >= 100_000);
        let options = ProjectOptions::default();
        let on_gpu = project(gpu, &w.bvh, &w.points, &w.normals, &options).unwrap();
        let on_cpu = project(&Backend::Cpu, &w.bvh, &w.points, &w.normals, &options).unwrap();
        let misses = on_cpu.iter().filter(|c| c.status() == Status::Miss).count();
        assert!(
            misses * 100 < on_cpu.len(),
            "{misses} misses: the frames should overlap"
        );
        let same = compare_triangles("projection", &on_gpu, &on_cpu);
        let tol = 1e-5 * f64::from(w.bvh.mean_edge_length());
        let points = ParityReport::gpu_vs_cpu(
            "hit points",
            &pick(|c| c.point, &on_gpu, &same),
            &pick(|c| c.point, &on_cpu, &same),
        );
        eprintln!(
            "hit points: max |gpu - cpu| = {:.2e} mean edge lengths over {} queries",
            points.max_abs_diff() / f64::from(w.bvh.mean_edge_length()),
            same.len()
        );
        points.assert_max_abs_lt(tol);
        ParityReport::gpu_vs_cpu(
            "t",
            &pick(|c| c.distance, &on_gpu, &same),
            &pick(|c| c.distance, &on_cpu, &same),
        )
        .assert_max_abs_lt(tol);
        ParityReport::gpu_vs_cpu(
            "normals",
            &pick(|c| c.normal, &on_gpu, &same),
            &pick(|c| c.normal, &on_cpu, &same),
        )
        .assert_max_abs_lt(1e-4);
        ParityReport::gpu_vs_cpu(
            "barycentric",
            &pick(|c| c.barycentric, &on_gpu, &same),
            &pick(|c| c.barycentric, &on_cpu, &same),
        )
        .assert_max_abs_lt(1e-4);
        // Statuses may differ only where the normal sits on the 60° threshold to within rounding.
        let flipped: Vec<usize> = same
            .iter()
            .copied()
            .filter(|&i| on_gpu[i].status() != on_cpu[i].status())
            .filter(|&i| (on_cpu[i].normal.dot(w.normals[i].normalize()) - 0.5).abs() > 1e-5)
            .collect();
        assert!(
            flipped.is_empty(),
            "statuses differ away from the threshold at {flipped:?}"
        );
    });
}

#[test]
fn gpu_closest_points_match_cpu_on_a_100k_triangle_frame() {
    run_on_gpu(|gpu| {
        let w = shared();
        let points = &w.points[..50_000];
        let on_gpu = closest_points(gpu, &w.bvh, points, f32::INFINITY).unwrap();
        let on_cpu = closest_points(&Backend::Cpu, &w.bvh, points, f32::INFINITY).unwrap();
        let tol = 1e-5 * f64::from(w.bvh.mean_edge_length());
        // Equidistant triangles (around a shared vertex or edge) may be chosen differently, but
        // the nearest point and the distance are the same.
        ParityReport::gpu_vs_cpu(
            "closest points",
            &pick(|c| c.point, &on_gpu, &(0..points.len()).collect::<Vec<_>>()),
            &pick(|c| c.point, &on_cpu, &(0..points.len()).collect::<Vec<_>>()),
        )
        .assert_max_abs_lt(tol);
        let gpu_d: Vec<f32> = on_gpu.iter().map(|c| c.distance).collect();
        let cpu_d: Vec<f32> = on_cpu.iter().map(|c| c.distance).collect();
        ParityReport::gpu_vs_cpu("signed distances", &gpu_d, &cpu_d).assert_max_abs_lt(tol);
    });
}

/// The nearest hit of the line by brute force over all triangles (Möller–Trumbore in f64).
fn brute_force_line(mesh: &IndexedMesh, p: Vec3, n: Vec3) -> Option<(f64, u32)> {
    let (p, n) = (p.as_dvec3(), n.normalize().as_dvec3());
    let mut best: Option<(f64, u32)> = None;
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = tri.map(|v| mesh.positions[v as usize].as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let h = n.cross(e2);
        let det = e1.dot(h);
        if det.abs() < 1e-300 {
            continue;
        }
        let s = p - a;
        let u = s.dot(h) / det;
        let q = s.cross(e1);
        let v = n.dot(q) / det;
        if u < -1e-9 || v < -1e-9 || u + v > 1.0 + 1e-9 {
            continue;
        }
        let d = e2.dot(q) / det;
        if best.is_none_or(|(bd, _)| d.abs() < bd.abs()) {
            best = Some((d, t as u32));
        }
    }
    best
}

#[test]
fn cpu_projection_matches_brute_force() {
    let w = shared();
    // 300 queries spread evenly over the source mesh's vertex order.
    let sample: Vec<usize> = (0..300).map(|k| k * w.points.len() / 300).collect();
    let points: Vec<Vec3> = sample.iter().map(|&i| w.points[i]).collect();
    let normals: Vec<Vec3> = sample.iter().map(|&i| w.normals[i]).collect();
    let found = project(
        &Backend::Cpu,
        &w.bvh,
        &points,
        &normals,
        &ProjectOptions::default(),
    )
    .unwrap();
    let tol = 1e-5 * f64::from(w.bvh.mean_edge_length());
    for (k, c) in found.iter().enumerate() {
        let expected = brute_force_line(&w.target, points[k], normals[k]);
        let Some((t, triangle)) = expected else {
            assert_eq!(c.status(), Status::Miss, "query {k}");
            continue;
        };
        assert_ne!(
            c.status(),
            Status::Miss,
            "query {k}: brute force hits {triangle} at {t}"
        );
        assert!(
            (f64::from(c.distance) - t).abs() < tol,
            "query {k}: t {} vs brute force {t} (triangle {} vs {triangle})",
            c.distance,
            c.triangle
        );
        let exact = points[k].as_dvec3() + normals[k].normalize().as_dvec3() * t;
        assert!(exact.distance(c.point.as_dvec3()) < tol, "query {k}: point");
    }
}

#[test]
fn cpu_results_do_not_depend_on_the_thread_count() {
    let w = shared();
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let bvh = Bvh::build(&w.target).unwrap();
                let projected = project(
                    &Backend::Cpu,
                    &bvh,
                    &w.points,
                    &w.normals,
                    &ProjectOptions::default(),
                )
                .unwrap();
                let nearest =
                    closest_points(&Backend::Cpu, &bvh, &w.points[..20_000], f32::INFINITY)
                        .unwrap();
                (
                    bvh.nodes().to_vec(),
                    bvh.triangles().to_vec(),
                    projected,
                    nearest,
                )
            })
    };
    let one = in_pool(1);
    let three = in_pool(3);
    assert!(one.0 == three.0, "BVH nodes differ between 1 and 3 threads");
    assert!(
        one.1 == three.1,
        "triangle order differs between 1 and 3 threads"
    );
    let bits = |c: &[Correspondence]| -> Vec<u8> { bytemuck::cast_slice(c).to_vec() };
    assert!(
        bits(&one.2) == bits(&three.2),
        "projections differ between 1 and 3 threads"
    );
    assert!(
        bits(&one.3) == bits(&three.3),
        "closest points differ between 1 and 3 threads"
    );
}
