//! `triangle_bounds` on both backends: analytic answers, edge cases, and bit-identical agreement
//! between the GPU kernel and its CPU twin.
//!
//! Each case is a `fn(&Backend)`; `_cpu` runs it on the CPU, `_gpu` on the test GPU (skipped
//! without an adapter unless `SURFTRACK_REQUIRE_GPU=1`).

use glam::Vec3;
use surftrack::compute::parity::{ParityReport, run_on_gpu};
use surftrack::compute::{Backend, ComputeError};
use surftrack::kernels::shared::Aabb;
use surftrack::project::triangle_bounds;

/// SplitMix64: a small deterministic generator, so failures reproduce exactly.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [-1, 1).
    fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }

    fn below(&mut self, n: u32) -> u32 {
        (self.next_u64() % u64::from(n)) as u32
    }
}

/// Random positions over several orders of magnitude, and triangles over them.
fn triangle_soup(seed: u64, positions: usize, triangles: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut rng = Rng(seed);
    let points = (0..positions)
        .map(|i| {
            let scale = [1e-3, 1.0, 1e3][i % 3];
            Vec3::new(rng.unit(), rng.unit(), rng.unit()) * scale
        })
        .collect();
    let n = positions as u32;
    let tris = (0..triangles)
        .map(|_| [rng.below(n), rng.below(n), rng.below(n)])
        .collect();
    (points, tris)
}

/// The box of each triangle, computed one coordinate at a time without glam's vector min/max.
fn reference(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Aabb> {
    triangles
        .iter()
        .map(|t| {
            let corner = |pick: fn(f32, f32) -> f32| {
                let p = t.map(|v| positions[v as usize].to_array());
                Vec3::from_array(std::array::from_fn(|k| {
                    pick(pick(p[0][k], p[1][k]), p[2][k])
                }))
            };
            Aabb::new(corner(f32::min), corner(f32::max))
        })
        .collect()
}

fn bounds(backend: &Backend, positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Aabb> {
    triangle_bounds(backend, positions, triangles)
        .unwrap_or_else(|e| panic!("triangle_bounds on {backend}: {e}"))
}

fn random_soup_matches_reference(backend: &Backend) {
    let (positions, triangles) = triangle_soup(1, 50_000, 100_000);
    let got = bounds(backend, &positions, &triangles);
    for (t, (tri, b)) in triangles.iter().zip(&got).enumerate().step_by(97) {
        for &v in tri {
            let p = positions[v as usize];
            assert!(
                b.min.cmple(p).all() && p.cmple(b.max).all(),
                "triangle {t}: {p} outside {b:?}"
            );
        }
    }
    ParityReport::compare(
        "random soup",
        ("backend", &got),
        ("reference", &reference(&positions, &triangles)),
    )
    .assert_identical();
}

/// The backend agrees bit for bit with the CPU twin run on a single thread: GPU parity on the GPU,
/// thread-count independence on the CPU.
fn agrees_with_single_threaded_cpu(backend: &Backend) {
    let (positions, triangles) = triangle_soup(2, 30_000, 100_003);
    let got = bounds(backend, &positions, &triangles);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let cpu = pool.install(|| bounds(&Backend::Cpu, &positions, &triangles));
    ParityReport::compare(
        "soup",
        (backend_name(backend), &got),
        ("cpu, 1 thread", &cpu),
    )
    .assert_identical();
}

fn backend_name(backend: &Backend) -> &'static str {
    match backend {
        Backend::Cpu => "cpu",
        Backend::Gpu(_) => "gpu",
    }
}

fn empty_input_gives_empty_output(backend: &Backend) {
    assert!(bounds(backend, &[], &[]).is_empty());
    assert!(bounds(backend, &[Vec3::ONE, Vec3::ZERO], &[]).is_empty());
}

fn single_triangle_has_its_analytic_box(backend: &Backend) {
    let positions = [
        Vec3::new(1.0, -2.0, 0.5),
        Vec3::new(-3.0, 4.0, 0.25),
        Vec3::new(2.0, 1.0, -7.0),
        Vec3::splat(100.0),
    ];
    let got = bounds(backend, &positions, &[[0, 1, 2]]);
    let expected = [Aabb::new(
        Vec3::new(-3.0, -2.0, -7.0),
        Vec3::new(2.0, 4.0, 0.5),
    )];
    ParityReport::compare("one triangle", ("backend", &got), ("analytic", &expected))
        .assert_identical();
    let got = bounds(backend, &positions, &[[3, 3, 3], [2, 0, 1]]);
    let expected = [
        Aabb::new(Vec3::splat(100.0), Vec3::splat(100.0)),
        expected[0],
    ];
    ParityReport::compare(
        "degenerate first",
        ("backend", &got),
        ("analytic", &expected),
    )
    .assert_identical();
}

fn out_of_range_index_is_an_error(backend: &Backend) {
    let positions = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let result = triangle_bounds(backend, &positions, &[[0, 1, 2], [0, 3, 1], [9, 0, 0]]);
    assert_eq!(
        result,
        Err(ComputeError::IndexOutOfRange {
            triangle: 1,
            vertex: 3,
            count: 3
        })
    );
}

/// More triangles than one dispatch row of 65 535 workgroups × 64 covers, so the GPU grid wraps
/// into a second dimension; every triangle (the last ones especially) must still be written.
fn dispatch_split_covers_every_triangle(backend: &Backend) {
    let count = 65_535 * 64 + 1000;
    let (positions, triangles) = triangle_soup(3, 4096, count);
    let got = bounds(backend, &positions, &triangles);
    let cpu = bounds(&Backend::Cpu, &positions, &triangles);
    ParityReport::compare(
        "4.2 M triangles",
        (backend_name(backend), &got),
        ("cpu", &cpu),
    )
    .assert_identical();
}

macro_rules! on_both_backends {
    ($($case:ident => $cpu:ident, $gpu:ident;)*) => {$(
        #[test]
        fn $cpu() {
            $case(&Backend::Cpu);
        }

        #[test]
        fn $gpu() {
            run_on_gpu($case);
        }
    )*};
}

on_both_backends! {
    random_soup_matches_reference => random_soup_matches_reference_cpu, random_soup_matches_reference_gpu;
    agrees_with_single_threaded_cpu => agrees_with_single_threaded_cpu_cpu, agrees_with_single_threaded_cpu_gpu;
    empty_input_gives_empty_output => empty_input_gives_empty_output_cpu, empty_input_gives_empty_output_gpu;
    single_triangle_has_its_analytic_box => single_triangle_has_its_analytic_box_cpu, single_triangle_has_its_analytic_box_gpu;
    out_of_range_index_is_an_error => out_of_range_index_is_an_error_cpu, out_of_range_index_is_an_error_gpu;
    dispatch_split_covers_every_triangle => dispatch_split_covers_every_triangle_cpu, dispatch_split_covers_every_triangle_gpu;
}
