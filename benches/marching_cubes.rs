//! Marching-cubes throughput in cells per second on a metaball field (the field is sampled once,
//! outside the timed closure). Reference on the project's 2-core machine: scikit-image's marching
//! cubes does 70–82 Mcells/s at 256³.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use std::hint::black_box;
use surftrack::grid::{ScalarGrid, marching_cubes};

/// Three blended Gaussian blobs filling the middle of the unit cube.
fn metaballs(n: usize) -> ScalarGrid {
    let centers = [
        Vec3::new(0.38, 0.42, 0.45),
        Vec3::new(0.62, 0.45, 0.55),
        Vec3::new(0.50, 0.62, 0.48),
    ];
    let spacing = 1.0 / (n - 1) as f32;
    ScalarGrid::from_fn(Vec3::ZERO, spacing, [n, n, n], |p| {
        let sum: f32 = centers
            .iter()
            .map(|c| (-(p - *c).length_squared() / 0.02).exp())
            .sum();
        0.5 - sum
    })
    .expect("benchmark grid shape is valid")
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("marching_cubes");
    group.sample_size(20);
    for n in [128usize, 256] {
        let grid = metaballs(n);
        let cells = (n - 1).pow(3) as u64;
        group.throughput(Throughput::Elements(cells));
        group.bench_function(format!("metaballs_{n}"), |b| {
            b.iter(|| marching_cubes(black_box(&grid), 0.0))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
