//! Registration cost (issue 5, bar 4) on two consecutive frames of the `blobs` scene, at about 16k
//! and 100k vertices (the second frame is meshed independently and turned by 1/32 of a turn).
//!
//! - `register/graph`: `DeformationGraph::build` (geodesic sampling, nearest nodes, weights).
//! - `register/iteration/<size>`: the sub-steps of one Gauss-Newton iteration at the first
//!   iteration's state: `correspondence` (deformed normals + normal-ray projection, CPU and GPU),
//!   `assembly` (`Jᵀr` and the matrix), `factorization` (faer numeric Cholesky), `solve`
//!   (conjugate gradients preconditioned by that factor), for the default solver (graph-pattern
//!   preconditioner) and for `exact` (`JᵀJ` itself factored, the paper's method).
//! - `register/stage/<size>`: the whole coarse stage (`CoarseSolver::run`; setup, and the rigid
//!   pre-alignment that runs beside the graph build there, excluded), the
//!   whole fine stage (`fine_align` from the source), and `register` end to end (BVH, setup, both
//!   stages); the last two on the CPU and, where an adapter exists, on the GPU (`fine_gpu`,
//!   `register_gpu`: projection and the fine stage's solve there).
//!
//! Setup (graph, pattern, symbolic factorization, BVH, pipelines) stays outside the timed closures.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use surftrack::compute::{Backend, BackendChoice};
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::Bvh;
use surftrack::register::{
    CoarseSolver, DeformationGraph, GraphOptions, LinearSolver, RegisterOptions, Target,
    fine_align, register,
};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

/// Frames 0 and 1 of `blobs` at `resolution` cells across.
fn frames(resolution: usize) -> (IndexedMesh, IndexedMesh) {
    let truths = plan(
        Scene::Blobs,
        &SynthOptions {
            resolution,
            frames: 32,
        },
    )
    .expect("plan");
    (
        extract(&truths[0]).expect("frame 0"),
        extract(&truths[1]).expect("frame 1"),
    )
}

fn exact() -> RegisterOptions {
    let mut options = RegisterOptions::default();
    options.coarse.solver = LinearSolver::Cholesky;
    options
}

fn bench(c: &mut Criterion) {
    let gpu = match Backend::select(BackendChoice::Gpu) {
        Ok(backend) => Some(backend),
        Err(error) => {
            eprintln!("GPU variants skipped: {error}");
            None
        }
    };
    let cpu = Backend::Cpu;
    for (label, resolution) in [("16k", 104), ("100k", 260)] {
        let (source, target) = frames(resolution);
        eprintln!(
            "{label}: source {} vertices, target {} vertices",
            source.positions.len(),
            target.positions.len()
        );
        let bvh = Bvh::build(&target).expect("bvh");

        let mut group = c.benchmark_group("register/graph");
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        group.measurement_time(Duration::from_secs(3));
        group.bench_function(label, |b| {
            b.iter(|| DeformationGraph::build(black_box(&source), &GraphOptions::default()))
        });
        group.finish();

        let mut group = c.benchmark_group(format!("register/iteration/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        group.measurement_time(Duration::from_secs(3));
        for (name, options) in [("", RegisterOptions::default()), ("exact_", exact())] {
            let mut solver = CoarseSolver::new(&cpu, &bvh, &source, &options).expect("setup");
            eprintln!(
                "{label} {name}: {} nodes, {} unknowns",
                solver.node_count(),
                solver.unknowns()
            );
            solver.project().expect("project");
            solver.assemble();
            solver.factor().expect("factor");
            if name.is_empty() {
                group.bench_function("correspondence_cpu", |b| {
                    b.iter(|| solver.project().expect("project"))
                });
                if let Some(gpu) = &gpu {
                    let mut on_gpu =
                        CoarseSolver::new(gpu, &bvh, &source, &options).expect("setup");
                    on_gpu.project().expect("project");
                    group.bench_function("correspondence_gpu", |b| {
                        b.iter(|| on_gpu.project().expect("project"))
                    });
                }
            }
            group.bench_function(format!("{name}assembly"), |b| b.iter(|| solver.assemble()));
            group.bench_function(format!("{name}factorization"), |b| {
                b.iter(|| solver.factor().expect("factor"))
            });
            group.bench_function(format!("{name}solve"), |b| {
                b.iter(|| solver.solve().expect("solve"))
            });
        }
        group.finish();

        let mut group = c.benchmark_group(format!("register/stage/{label}"));
        group.sample_size(10);
        group.warm_up_time(Duration::from_secs(1));
        group.measurement_time(Duration::from_secs(10));
        let options = RegisterOptions::default();
        group.bench_function("coarse", |b| {
            b.iter_batched(
                || CoarseSolver::new(&cpu, &bvh, &source, &options).expect("setup"),
                |mut solver| solver.run().expect("coarse"),
                BatchSize::PerIteration,
            )
        });
        for (name, backend) in [("fine", Some(&cpu)), ("fine_gpu", gpu.as_ref())] {
            let Some(backend) = backend else { continue };
            group.bench_function(name, |b| {
                b.iter(|| fine_align(backend, &bvh, &source, &options).expect("fine"))
            });
        }
        let mesh = Mesh::from_indexed(&source).expect("mesh");
        for (name, backend) in [("register_cpu", Some(&cpu)), ("register_gpu", gpu.as_ref())] {
            let Some(backend) = backend else { continue };
            group.bench_function(name, |b| {
                b.iter_batched(
                    || mesh.clone(),
                    |mut mesh| {
                        register(backend, &mut mesh, Target::Mesh(&target), &options)
                            .expect("register")
                    },
                    BatchSize::PerIteration,
                )
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
