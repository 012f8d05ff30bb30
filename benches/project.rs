//! Correspondence projection on the workload of issue 4: a 100k-triangle synthetic target frame
//! and 100k source vertices with their normals (200k normal rays, both directions).
//!
//! - `project/build`: `Bvh::build` (SAH tree, leaf-ordered triangles, normals, pseudo-normals,
//!   mean edge length) for 100k and 300k triangles, on one thread and on all.
//! - `project/rays`: `project` (one line query per point, both directions at once) on one thread
//!   and on all; `cast_ray_1_thread` casts the 200k rays one direction at a time, like a
//!   single-ray tracer; the GPU variants with and without the per-call transfers.
//! - `project/closest_point`: `closest_points` for the 100k source vertices.
//!
//! Throughput counts rays (two per projected point) or queries. Pipelines and the BVH upload
//! happen before timing. Without a GPU adapter only the CPU is measured.

#[path = "../tests/project_support/mod.rs"]
mod project_support;

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use surftrack::compute::{Backend, BackendChoice};
use surftrack::project::{Bvh, GpuBvh, GpuQueries, ProjectOptions, closest_points, project};

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn gpu() -> Option<Backend> {
    match Backend::select(BackendChoice::Gpu) {
        Ok(backend) => Some(backend),
        Err(error) => {
            eprintln!("GPU variants skipped: {error}");
            None
        }
    }
}

fn bench(c: &mut Criterion) {
    let threads = rayon::current_num_threads();
    let single = pool(1);
    let (target, points, normals) = project_support::workload();
    let gpu = gpu();

    let mut group = c.benchmark_group("project/build");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
    let large = project_support::metaballs(305, 0.0, 0.0);
    for mesh in [&target, &large] {
        let n = mesh.triangles.len();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("1_thread", n), mesh, |b, mesh| {
            b.iter(|| single.install(|| Bvh::build(black_box(mesh)).expect("bvh")))
        });
        group.bench_with_input(
            BenchmarkId::new(format!("{threads}_threads"), n),
            mesh,
            |b, mesh| b.iter(|| Bvh::build(black_box(mesh)).expect("bvh")),
        );
    }
    group.finish();

    let bvh = Bvh::build(&target).expect("bvh");
    let options = ProjectOptions::default();
    let rays = 2 * points.len();
    let mut group = c.benchmark_group("project/rays");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(rays as u64));
    group.bench_function(BenchmarkId::new("cpu_1_thread", rays), |b| {
        b.iter(|| {
            single.install(|| project(&Backend::Cpu, &bvh, black_box(&points), &normals, &options))
        })
    });
    group.bench_function(
        BenchmarkId::new(format!("cpu_{threads}_threads"), rays),
        |b| b.iter(|| project(&Backend::Cpu, &bvh, black_box(&points), &normals, &options)),
    );
    group.bench_function(BenchmarkId::new("cast_ray_1_thread", rays), |b| {
        b.iter(|| {
            let mut hits = 0usize;
            for (&p, &n) in points.iter().zip(&normals) {
                hits += usize::from(bvh.cast_ray(black_box(p), n, f32::INFINITY).is_some());
                hits += usize::from(bvh.cast_ray(black_box(p), -n, f32::INFINITY).is_some());
            }
            hits
        })
    });
    if let Some(backend) = &gpu
        && let Some(context) = backend.gpu()
    {
        let resident = GpuBvh::upload(context, &bvh).expect("upload");
        let job = GpuQueries::project(context, &bvh, &points, &normals, &options).expect("upload");
        job.dispatch(context, &resident).expect("dispatch");
        job.read(context).expect("read");
        project(backend, &bvh, &points, &normals, &options).expect("warm");
        group.bench_function(BenchmarkId::new("gpu_with_transfer", rays), |b| {
            b.iter(|| project(backend, &bvh, black_box(&points), &normals, &options))
        });
        group.bench_function(BenchmarkId::new("gpu_kernel", rays), |b| {
            b.iter(|| {
                job.dispatch(context, &resident).expect("dispatch");
                context.wait().expect("wait")
            })
        });
    }
    group.finish();

    let mut group = c.benchmark_group("project/closest_point");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(points.len() as u64));
    let n = points.len();
    group.bench_function(BenchmarkId::new("cpu_1_thread", n), |b| {
        b.iter(|| {
            single
                .install(|| closest_points(&Backend::Cpu, &bvh, black_box(&points), f32::INFINITY))
        })
    });
    group.bench_function(BenchmarkId::new(format!("cpu_{threads}_threads"), n), |b| {
        b.iter(|| closest_points(&Backend::Cpu, &bvh, black_box(&points), f32::INFINITY))
    });
    if let Some(backend) = &gpu
        && let Some(context) = backend.gpu()
    {
        let resident = GpuBvh::upload(context, &bvh).expect("upload");
        let job =
            GpuQueries::closest_points(context, &bvh, &points, f32::INFINITY).expect("upload");
        job.dispatch(context, &resident).expect("dispatch");
        job.read(context).expect("read");
        closest_points(backend, &bvh, &points, f32::INFINITY).expect("warm");
        group.bench_function(BenchmarkId::new("gpu_with_transfer", n), |b| {
            b.iter(|| closest_points(backend, &bvh, black_box(&points), f32::INFINITY))
        });
        group.bench_function(BenchmarkId::new("gpu_kernel", n), |b| {
            b.iter(|| {
                job.dispatch(context, &resident).expect("dispatch");
                context.wait().expect("wait")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
