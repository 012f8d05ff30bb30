//! Every fine-stage kernel against its CPU twin on the test GPU: the twins' buffers
//! ([`CpuFineSolve`]) and the device's ([`GpuFineSolve`]) go through the same dispatches from the
//! same input, a whole solve, and after each dispatch every buffer is read back and compared.
//!
//! Both sides compute in f64 and sum in the same order, so they can differ only where the device
//! rounds a multiply-add, a division or a square root differently from the CPU; values here are at
//! most a few hundred, so [`TOLERANCE`] allows some thousands of ulps. Every discrete outcome —
//! which step ends the solve, the iteration count — must be identical. Skipped without a GPU
//! adapter (unless `SURFTRACK_REQUIRE_GPU=1`) and on devices without f64 shaders, where the GPU
//! backend runs this stage on the CPU twins.

use glam::{DVec3, Vec3};

use super::correspond::{CoverHit, CoverPairs};
use super::cover::Cover;
use super::fine_solve::{CpuFineSolve, FineSystem, Operand};
use super::gpu::GpuFineSolve;
use super::options::FineOptions;
use super::surface::Surface;
use crate::compute::parity::{ParityReport, run_on_gpu};
use crate::compute::{Backend, Batch, GpuContext};
use crate::kernels::shared::{
    CgState, FineTarget, PHASE_ALPHA, PHASE_BEGIN, PHASE_BETA, PHASE_NORM,
};
use crate::mesh::IndexedMesh;

/// Largest absolute difference allowed in any value.
const TOLERANCE: f64 = 1e-9;

/// SplitMix64, so a failure reproduces exactly.
struct Rng(u64);

impl Rng {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    fn vector(&mut self) -> DVec3 {
        DVec3::new(self.unit(), self.unit(), self.unit())
    }
}

/// A 2,562-vertex sphere (three reduction chunks), correspondences for four vertices in five
/// (targets a fraction of an edge off, normals tilted), a cover pair on every third triangle, and
/// warm displacements.
struct Case {
    surface: Surface,
    cover: Cover,
    targets: Vec<FineTarget>,
    d: Vec<DVec3>,
}

impl Case {
    fn new() -> Self {
        let mesh = IndexedMesh::icosphere(Vec3::new(0.5, -0.25, 2.0), 3.0, 4);
        let surface = Surface::new(&mesh.positions, &mesh.triangles, mesh.mean_edge_length());
        let mut rng = Rng(25);
        let start = &surface.rest;
        let targets = start
            .iter()
            .enumerate()
            .map(|(v, &p)| {
                if v % 5 == 0 {
                    return FineTarget::default();
                }
                let normal = (p.normalize() + rng.vector() * 0.3).normalize();
                FineTarget::new((p + rng.vector() * 0.4).to_array(), normal.to_array())
            })
            .collect();
        let hits = (0..mesh.triangles.len())
            .step_by(3)
            .map(|t| {
                let w = DVec3::new(rng.unit() + 1.5, rng.unit() + 1.5, rng.unit() + 1.5);
                let w = w / w.element_sum();
                let [a, b, c] = mesh.triangles[t].map(|v| mesh.positions[v as usize]);
                let at = a * w.x as f32 + b * w.y as f32 + c * w.z as f32;
                let normal = (at.normalize() + rng.vector().as_vec3() * 0.2).normalize();
                CoverHit {
                    point: at + normal * 0.2 * rng.unit() as f32,
                    normal,
                    triangle: t as u32,
                    barycentric: w.as_vec3(),
                }
            })
            .collect();
        let pairs = CoverPairs {
            hits,
            samples: mesh.triangles.len() * 2,
        };
        let cover = Cover::new(&pairs, &surface, start, &FineOptions::default()).unwrap();
        let d = (0..start.len()).map(|_| rng.vector() * 0.1).collect();
        Self {
            surface,
            cover,
            targets,
            d,
        }
    }
}

/// Compares every buffer and the state; returns the largest difference.
fn compare(step: &str, gpu: &CpuFineSolve, cpu: &CpuFineSolve) -> f64 {
    let reports = [
        ParityReport::gpu_vs_cpu(&format!("{step}: fit"), &gpu.fit, &cpu.fit),
        ParityReport::gpu_vs_cpu(
            &format!("{step}: preconditioner"),
            &gpu.preconditioner,
            &cpu.preconditioner,
        ),
        ParityReport::gpu_vs_cpu(&format!("{step}: b"), &gpu.b, &cpu.b),
        ParityReport::gpu_vs_cpu(&format!("{step}: terms"), &gpu.terms, &cpu.terms),
        ParityReport::gpu_vs_cpu(&format!("{step}: partials"), &gpu.partials, &cpu.partials),
        ParityReport::gpu_vs_cpu(&format!("{step}: moved"), &gpu.moved, &cpu.moved),
        ParityReport::gpu_vs_cpu(&format!("{step}: ad"), &gpu.ad, &cpu.ad),
        ParityReport::gpu_vs_cpu(&format!("{step}: d"), &gpu.d, &cpu.d),
        ParityReport::gpu_vs_cpu(&format!("{step}: r"), &gpu.r, &cpu.r),
        ParityReport::gpu_vs_cpu(&format!("{step}: z"), &gpu.z, &cpu.z),
        ParityReport::gpu_vs_cpu(&format!("{step}: p"), &gpu.p, &cpu.p),
    ];
    let mut largest = 0.0f64;
    for report in reports {
        largest = largest.max(report.max_abs_diff());
        report.assert_max_abs_lt(TOLERANCE);
    }
    let scalars = |s: &CgState| [s.b_norm, s.rz, s.alpha, s.beta, s.residual];
    ParityReport::gpu_vs_cpu(
        &format!("{step}: b_norm, rz, alpha, beta, residual"),
        &scalars(&gpu.state),
        &scalars(&cpu.state),
    )
    .assert_max_abs_lt(TOLERANCE);
    assert_eq!(
        (gpu.state.iterations, gpu.state.done),
        (cpu.state.iterations, cpu.state.done),
        "{step}: iterations and end"
    );
    largest
}

/// Runs one step on both sides and compares.
fn step(
    name: &str,
    context: &GpuContext,
    (gpu, cpu): (&GpuFineSolve, &mut CpuFineSolve),
    on_gpu: impl FnOnce(&GpuFineSolve, &mut Batch) -> Result<(), crate::compute::ComputeError>,
    on_cpu: impl FnOnce(&mut CpuFineSolve),
) -> f64 {
    let mut batch = context.batch();
    on_gpu(gpu, &mut batch).unwrap();
    batch.submit().unwrap();
    on_cpu(cpu);
    compare(name, &gpu.read_all(context).unwrap(), cpu)
}

fn every_kernel_matches_its_twin(backend: &Backend) {
    let Some(context) = backend.gpu().filter(|c| c.has_f64()) else {
        eprintln!("skipping: {backend} has no f64 shaders; the fine stage runs on the CPU there");
        return;
    };
    let case = Case::new();
    let options = FineOptions::default();
    let system = FineSystem::new(
        &case.surface.adjacency,
        &case.surface.rest,
        case.cover,
        &options,
    )
    .unwrap();
    let gpu = GpuFineSolve::upload(context, &system, &case.d).unwrap();
    let mut cpu = CpuFineSolve::new(&system, &case.d);
    gpu.write_targets(context, &case.targets).unwrap();
    let targets = &case.targets;
    let system = &system;
    let mut largest = [
        step(
            "fine_system",
            context,
            (&gpu, &mut cpu),
            |g, b| g.system(b),
            |c| c.system(system, targets),
        ),
        step(
            "norm",
            context,
            (&gpu, &mut cpu),
            |g, b| g.reduce(b, PHASE_NORM),
            |c| c.reduce(system, PHASE_NORM),
        ),
        step(
            "A d",
            context,
            (&gpu, &mut cpu),
            |g, b| g.apply(b, Operand::D),
            |c| c.apply(system, Operand::D),
        ),
        step(
            "fine_start",
            context,
            (&gpu, &mut cpu),
            |g, b| g.start(b),
            |c| c.start(),
        ),
        step(
            "begin",
            context,
            (&gpu, &mut cpu),
            |g, b| g.reduce(b, PHASE_BEGIN),
            |c| c.reduce(system, PHASE_BEGIN),
        ),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    let mut iterations = 0;
    while cpu.state.done == 0 {
        assert!(
            iterations < options.max_cg_iterations,
            "the solve never ended"
        );
        iterations += 1;
        let name = |what: &str| format!("iteration {iterations}: {what}");
        for difference in [
            step(
                &name("A p"),
                context,
                (&gpu, &mut cpu),
                |g, b| g.apply(b, Operand::P),
                |c| c.apply(system, Operand::P),
            ),
            step(
                &name("alpha"),
                context,
                (&gpu, &mut cpu),
                |g, b| g.reduce(b, PHASE_ALPHA),
                |c| c.reduce(system, PHASE_ALPHA),
            ),
            step(
                &name("fine_update"),
                context,
                (&gpu, &mut cpu),
                |g, b| g.update(b),
                |c| c.update(),
            ),
            step(
                &name("beta"),
                context,
                (&gpu, &mut cpu),
                |g, b| g.reduce(b, PHASE_BETA),
                |c| c.reduce(system, PHASE_BETA),
            ),
            step(
                &name("fine_direction"),
                context,
                (&gpu, &mut cpu),
                |g, b| g.direction(b),
                |c| c.direction(),
            ),
        ] {
            largest = largest.max(difference);
        }
    }
    assert!(
        iterations >= 5,
        "only {iterations} iterations: the case is too easy"
    );
    assert!(cpu.state.residual <= options.tolerance, "converged");
    eprintln!("fine kernels on {backend}: {iterations} iterations, largest difference {largest:e}");
}

#[test]
fn every_fine_kernel_matches_its_cpu_twin_gpu() {
    run_on_gpu(every_kernel_matches_its_twin);
}

/// Whole solves as the stage runs them (the device's in batches of iterations, its kernels idle
/// past the end), two rounds, the second warm-started from the first: the same iteration counts and ends
/// as the twins' at limits that end a solve before, inside and after the first batch, and without
/// any iteration; and `b = 0` (no correspondences, no cover) gives `d = 0` on both.
fn whole_solves_end_where_the_twins_do(backend: &Backend) {
    let Some(context) = backend.gpu().filter(|c| c.has_f64()) else {
        eprintln!("skipping: {backend} has no f64 shaders; the fine stage runs on the CPU there");
        return;
    };
    for (max_iterations, empty) in [
        (0, false),
        (3, false),
        (11, false),
        (200, false),
        (200, true),
    ] {
        let case = Case::new();
        let options = FineOptions {
            max_cg_iterations: max_iterations,
            ..FineOptions::default()
        };
        let (cover, targets) = if empty {
            (
                Cover::default(),
                vec![FineTarget::default(); case.targets.len()],
            )
        } else {
            (case.cover, case.targets)
        };
        let what = format!("max {max_iterations} iterations, empty {empty}");
        let system =
            FineSystem::new(&case.surface.adjacency, &case.surface.rest, cover, &options).unwrap();
        let gpu = GpuFineSolve::upload(context, &system, &case.d).unwrap();
        let mut cpu = CpuFineSolve::new(&system, &case.d);
        for round in 0..2 {
            // The second round's targets lie a little farther out, so its warm start still iterates.
            let targets: Vec<FineTarget> = targets
                .iter()
                .map(|&t| {
                    let mut moved = t;
                    moved.point = t.point.map(|x| x * (1.0 + 0.05 * round as f64));
                    moved
                })
                .collect();
            let (gpu_state, gpu_d) = gpu.solve(context, &targets).unwrap();
            let cpu_state = cpu.solve(&system, &targets);
            assert_eq!(
                (gpu_state.iterations, gpu_state.done),
                (cpu_state.iterations, cpu_state.done),
                "{what}, round {round}"
            );
            // The case needs about 40 iterations: small limits are reached, the default is not.
            let iterations = match (empty, max_iterations) {
                (true, _) => 0,
                (false, max) if max < 20 => max as u32,
                (false, _) => cpu_state.iterations.clamp(1, max_iterations as u32 - 1),
            };
            assert_eq!(cpu_state.iterations, iterations, "{what}, round {round}");
            ParityReport::gpu_vs_cpu(&format!("{what}, round {round}: d"), &gpu_d, &cpu.d)
                .assert_max_abs_lt(TOLERANCE);
            if empty {
                assert!(cpu.d.iter().all(|d| *d == DVec3::ZERO), "{what}: d = 0");
            }
        }
    }
}

#[test]
fn whole_solves_end_where_the_twins_do_gpu() {
    run_on_gpu(whole_solves_end_where_the_twins_do);
}
