//! The fine stage on the GPU backend (its kernels, f64, resident buffers) against the CPU path on
//! synth `merge` frames: the same discrete decisions — correspondences kept and pruned, cover
//! pairs, conjugate-gradient iterations per round, convergence — and positions within 10⁻⁶ mean
//! edge lengths. Both backends solve in f64 and sum in the same order, so they differ only where
//! the device rounds a multiply-add, division or square root differently; the positions are then
//! rounded to f32, so on lavapipe they come out identical.
//!
//! Skipped without a GPU adapter unless `SURFTRACK_REQUIRE_GPU=1`.

use glam::Vec3;
use surftrack::compute::Backend;
use surftrack::compute::parity::run_on_gpu;
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::Bvh;
use surftrack::register::{FineReport, RegisterOptions, Target, fine_align, register};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

/// Positions may differ by this many mean edge lengths of the source.
const TOLERANCE: f64 = 1e-6;

fn frames(first: usize) -> (IndexedMesh, IndexedMesh) {
    let truths = plan(
        Scene::Merge,
        &SynthOptions {
            resolution: 40,
            frames: 16,
        },
    )
    .expect("plan");
    (
        extract(&truths[first]).expect("source"),
        extract(&truths[first + 1]).expect("target"),
    )
}

fn aligned(backend: &Backend, source: &IndexedMesh, bvh: &Bvh) -> (Vec<Vec3>, FineReport) {
    fine_align(backend, bvh, source, &RegisterOptions::default())
        .unwrap_or_else(|e| panic!("fine_align on {backend}: {e}"))
}

/// Asserts equal decisions and positions within `TOLERANCE · unit`; returns the largest
/// difference in units.
fn assert_agree(
    what: &str,
    (gpu, gpu_report): (&[Vec3], &FineReport),
    (cpu, cpu_report): (&[Vec3], &FineReport),
    unit: f32,
) -> f64 {
    assert_eq!(gpu_report.rounds.len(), cpu_report.rounds.len(), "{what}");
    for (k, (g, c)) in gpu_report.rounds.iter().zip(&cpu_report.rounds).enumerate() {
        let decisions = |r: &surftrack::register::FineRound| {
            (r.kept, r.pruned, r.cover, r.cg_iterations, r.converged)
        };
        assert_eq!(decisions(g), decisions(c), "{what}: round {k} decisions");
        let relative = (g.energy - c.energy).abs() / c.energy.abs().max(f64::MIN_POSITIVE);
        assert!(
            relative < 1e-9,
            "{what}: round {k} energy {} vs {}",
            g.energy,
            c.energy
        );
    }
    assert_eq!(gpu.len(), cpu.len(), "{what}: vertex count");
    let largest = gpu
        .iter()
        .zip(cpu)
        .map(|(g, c)| f64::from((*g - *c).abs().max_element() / unit))
        .fold(0.0, f64::max);
    assert!(
        largest < TOLERANCE,
        "{what}: positions differ by up to {largest:e} mean edge lengths"
    );
    largest
}

fn fine_align_agrees(gpu: &Backend) {
    let (source, target) = frames(3);
    let bvh = Bvh::build(&target).expect("bvh");
    let (cpu_positions, cpu_report) = aligned(&Backend::Cpu, &source, &bvh);
    let (gpu_positions, gpu_report) = aligned(gpu, &source, &bvh);
    assert!(
        cpu_report
            .rounds
            .iter()
            .all(|r| r.cg_iterations > 0 && r.cover > 0),
        "the solves iterate and the cover term is exercised: {cpu_report:?}"
    );
    let largest = assert_agree(
        "fine_align",
        (&gpu_positions, &gpu_report),
        (&cpu_positions, &cpu_report),
        source.mean_edge_length(),
    );
    eprintln!("fine_align on {gpu}: largest difference {largest:e} L");
}

#[test]
fn fine_align_gpu_agrees_with_cpu() {
    run_on_gpu(fine_align_agrees);
}

fn registration_agrees(gpu: &Backend) {
    let (source, target) = frames(6);
    let run = |backend: &Backend| {
        let mut mesh = Mesh::from_indexed(&source).expect("mesh");
        let report = register(
            backend,
            &mut mesh,
            Target::Mesh(&target),
            &RegisterOptions::default(),
        )
        .unwrap_or_else(|e| panic!("register on {backend}: {e}"));
        (mesh.to_indexed().positions, report)
    };
    let (cpu_positions, cpu_report) = run(&Backend::Cpu);
    let (gpu_positions, gpu_report) = run(gpu);
    assert_eq!(
        gpu_report.coarse.iterations(),
        cpu_report.coarse.iterations(),
        "coarse iterations"
    );
    let largest = assert_agree(
        "register",
        (&gpu_positions, &gpu_report.fine),
        (&cpu_positions, &cpu_report.fine),
        source.mean_edge_length(),
    );
    eprintln!("register on {gpu}: largest difference {largest:e} L");
}

#[test]
fn registration_gpu_agrees_with_cpu() {
    run_on_gpu(registration_agrees);
}
