//! Per-triangle bounding boxes: the CPU twin against the GPU kernel, in one group so the report
//! shows the ratio. `gpu_with_transfer` is what a caller of `triangle_bounds` pays (upload, kernel,
//! readback); `gpu_kernel` keeps the buffers resident and times the dispatch alone. Pipeline
//! creation happens before timing. Without a GPU adapter only the CPU is measured.

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use surftrack::compute::{Backend, BackendChoice};
use surftrack::project::{GpuTriangleBounds, triangle_bounds};

/// A torus of `2 × rings × segments` triangles with mesh-like index locality.
fn torus(rings: u32, segments: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut positions = Vec::with_capacity((rings * segments) as usize);
    for i in 0..rings {
        let u = i as f32 / rings as f32 * std::f32::consts::TAU;
        for j in 0..segments {
            let v = j as f32 / segments as f32 * std::f32::consts::TAU;
            let r = 1.0 + 0.3 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.3 * v.sin()));
        }
    }
    let index = |i: u32, j: u32| (i % rings) * segments + (j % segments);
    let mut triangles = Vec::with_capacity((2 * rings * segments) as usize);
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    (positions, triangles)
}

fn bench(c: &mut Criterion) {
    let gpu = match Backend::select(BackendChoice::Gpu) {
        Ok(backend) => Some(backend),
        Err(error) => {
            eprintln!("GPU variants skipped: {error}");
            None
        }
    };
    let mut group = c.benchmark_group("triangle_bounds");
    group.sample_size(20);
    for (rings, segments) in [(250, 200), (1000, 500)] {
        let (positions, triangles) = torus(rings, segments);
        let n = triangles.len();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_with_input(BenchmarkId::new("cpu", n), &n, |b, _| {
            b.iter(|| triangle_bounds(&Backend::Cpu, black_box(&positions), &triangles))
        });
        let Some(backend) = &gpu else { continue };
        let Some(context) = backend.gpu() else {
            continue;
        };
        // Compiles and caches the pipeline outside the timed loops.
        let resident = GpuTriangleBounds::upload(context, &positions, &triangles).unwrap();
        resident.dispatch(context).unwrap();
        resident.read(context).unwrap();
        group.bench_with_input(BenchmarkId::new("gpu_with_transfer", n), &n, |b, _| {
            b.iter(|| triangle_bounds(backend, black_box(&positions), &triangles))
        });
        group.bench_with_input(BenchmarkId::new("gpu_kernel", n), &n, |b, _| {
            b.iter(|| {
                resident.dispatch(context).unwrap();
                context.wait().unwrap();
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
