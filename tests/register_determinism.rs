//! The CPU registration gives bit-identical positions whatever the thread count: its parallel
//! assembly, projections and conjugate-gradient sums combine partial results in a fixed order.

use surftrack::compute::Backend;
use surftrack::mesh::Mesh;
use surftrack::register::{RegisterOptions, Target, register};
use surftrack::synth::{Scene, SynthOptions, extract, plan};

/// Frames 0 and 1 of `merge` registered in a pool of `threads` threads: every position's bits and
/// the number of Gauss-Newton iterations.
fn registered(threads: usize) -> (Vec<[u32; 3]>, usize) {
    let truths = plan(
        Scene::Merge,
        &SynthOptions {
            resolution: 48,
            frames: 16,
        },
    )
    .expect("plan");
    let source = extract(&truths[0]).expect("frame 0");
    let target = extract(&truths[1]).expect("frame 1");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    pool.install(|| {
        let mut mesh = Mesh::from_indexed(&source).expect("mesh");
        let report = register(
            &Backend::Cpu,
            &mut mesh,
            Target::Mesh(&target),
            &RegisterOptions::default(),
        )
        .expect("register");
        let bits = mesh
            .to_indexed()
            .positions
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect();
        (bits, report.coarse.iterations())
    })
}

#[test]
fn registration_is_bit_identical_on_one_two_and_three_threads() {
    let (one, iterations) = registered(1);
    assert!(iterations > 0, "the coarse stage iterated");
    for threads in [2, 3] {
        let (other, other_iterations) = registered(threads);
        assert_eq!(
            iterations, other_iterations,
            "{threads} threads: iterations"
        );
        let differing = one.iter().zip(&other).filter(|(a, b)| a != b).count();
        assert_eq!(
            differing, 0,
            "{threads} threads: positions differing from one thread"
        );
    }
}
