//! `constrain_topology` on a 100k-vertex frame of the `merge` scene: classification (with region
//! growth), cut + fill + stitch (with assembly and the exact verification of the result), and the
//! whole call, on the frame where the two spheres merge; the whole call on a frame without a
//! topology change; and, for the share of a frame's time, Φ of the same frame (the grid's
//! narrow-band distance, which the caller computes once per pass).
//!
//! The tracked mesh stands in for registration's result: the previous frame's surface with every
//! vertex moved to its nearest point on the target, so its two spheres meet where the target's
//! merged, and the pass `ConstrainTopology(M, Φ(M))` performs the merge. Setup (synthesis,
//! projection, Φ) stays outside the timed closures.
//!
//! The share of a frame's time (paper §6: negligible next to registration) is measured once, in the
//! setup, on the real thing: the tracker started on the frame before the merge and stepped onto the
//! merge frame, with the stage times it reports (too long a step to sample ten times).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use surftrack::compute::Backend;
use surftrack::grid::GridFrame;
use surftrack::mesh::{IndexedMesh, Mesh};
use surftrack::project::{Bvh, closest_points};
use surftrack::sequence::{FrameSource, track_sequence};
use surftrack::synth::{Scene, SynthOptions, extract, plan};
use surftrack::topology::{Field, TopologyOptions, TopologyReport, constrain_topology};
use surftrack::track::TrackOptions;

/// Cells across the scene: frames of about 100k vertices.
const RESOLUTION: usize = 256;
/// Frames over the scene: the spheres move well under a cell per frame.
const FRAMES: usize = 200;

/// `mesh` with every vertex on its nearest point of `target` (most of the way where all the way
/// would make a triangle degenerate).
fn registered(mesh: &IndexedMesh, target: &IndexedMesh) -> IndexedMesh {
    let bvh = Bvh::build(target).expect("target is a closed surface");
    let near = closest_points(&Backend::Cpu, &bvh, &mesh.positions, f32::INFINITY)
        .expect("the CPU backend always runs");
    [1.0f32, 0.99, 0.95, 0.9]
        .iter()
        .map(|&blend| {
            let mut m = mesh.clone();
            for (p, n) in m.positions.iter_mut().zip(&near) {
                *p += blend * (n.point - *p);
            }
            m
        })
        .find(|m| m.validate().is_ok())
        .unwrap_or_else(|| mesh.clone())
}

/// The tracked mesh and Θ of frame `j`'s first pass.
fn pass(frames: &[IndexedMesh], j: usize, frame: GridFrame) -> (Mesh, Field) {
    let m = registered(&frames[j - 1], &frames[j]);
    let theta = Field::signed_distance(&Backend::Cpu, frame, &m).expect("Φ of a valid mesh");
    (
        Mesh::from_indexed(&m).expect("registered mesh is valid"),
        theta,
    )
}

fn run(mesh: &Mesh, theta: &Field) -> TopologyReport {
    let mut m = mesh.clone();
    constrain_topology(&mut m, theta, &TopologyOptions::default()).expect("never fails")
}

/// Times one part of the call, as the report measures it.
fn part(mesh: &Mesh, theta: &Field, iters: u64, of: fn(&TopologyReport) -> Duration) -> Duration {
    (0..iters).map(|_| of(&run(mesh, theta))).sum()
}

fn bench(c: &mut Criterion) {
    let options = SynthOptions {
        resolution: RESOLUTION,
        frames: FRAMES,
    };
    let truths = plan(Scene::Merge, &options).expect("valid options");
    let merge = truths
        .iter()
        .position(|t| t.components == 1)
        .expect("the spheres merge");
    let steady = merge / 2;
    let frames: Vec<IndexedMesh> = truths
        .iter()
        .map(|t| {
            let keep = [steady - 1, steady, merge - 1, merge].contains(&t.index);
            if keep {
                extract(t).expect("synth frame")
            } else {
                IndexedMesh::default()
            }
        })
        .collect();
    let frame = GridFrame::for_mesh(&frames[merge], 1.0).expect("frame has edges");
    let (merging, phi_merging) = pass(&frames, merge, frame);
    let (still, phi_still) = pass(&frames, steady, frame);
    let report = run(&merging, &phi_merging);
    eprintln!(
        "merge frame {merge}: {} vertices, {:?}, {} of them replaced ({:.2}%), region {} cells",
        merging.vertex_count(),
        report.resampling,
        report.deleted,
        100.0 * report.replaced_fraction(),
        report.region_cells
    );

    frame_share(&frames, merge);

    let mut group = c.benchmark_group("topology");
    group.sample_size(10);
    group.warm_up_time(Duration::from_secs(1));
    group.measurement_time(Duration::from_secs(3));
    group.bench_function("merge_frame/classify", |b| {
        b.iter_custom(|iters| part(&merging, &phi_merging, iters, |r| r.classify))
    });
    group.bench_function("merge_frame/cut_fill_stitch", |b| {
        b.iter_custom(|iters| part(&merging, &phi_merging, iters, |r| r.rebuild))
    });
    group.bench_function("merge_frame/whole_call", |b| {
        b.iter_custom(|iters| {
            (0..iters)
                .map(|_| {
                    let mut m = merging.clone();
                    let start = Instant::now();
                    let r = constrain_topology(
                        &mut m,
                        black_box(&phi_merging),
                        &TopologyOptions::default(),
                    );
                    let elapsed = start.elapsed();
                    black_box(r.expect("never fails"));
                    elapsed
                })
                .sum()
        })
    });
    group.bench_function("steady_frame/whole_call", |b| {
        b.iter_custom(|iters| {
            (0..iters)
                .map(|_| {
                    let mut m = still.clone();
                    let start = Instant::now();
                    let r = constrain_topology(
                        &mut m,
                        black_box(&phi_still),
                        &TopologyOptions::default(),
                    );
                    let elapsed = start.elapsed();
                    black_box(r.expect("never fails"));
                    elapsed
                })
                .sum()
        })
    });
    let indexed = merging.to_indexed();
    group.bench_function("merge_frame/phi", |b| {
        b.iter(|| Field::signed_distance(&Backend::Cpu, frame, black_box(&indexed)))
    });
    group.finish();
}

/// One step of the tracker onto the merge frame: the topology passes' share of the frame's time.
fn frame_share(frames: &[IndexedMesh], merge: usize) {
    let backend = Backend::Cpu;
    let report = track_sequence::<()>(
        FrameSource::Meshes(&frames[merge - 1..=merge]),
        &backend,
        &TrackOptions::default(),
        None,
        |_| {},
    )
    .expect("tracking never fails");
    let log = &report.frames[1];
    let t = &log.times;
    let topology = t.topology_self + t.topology_target;
    eprintln!(
        "tracker step onto merge frame {merge} ({} vertices, topology changed: {}): \
         frame {:.0} ms = registration {:.0} + improvement {:.0} + topology passes {:.0} \
         (Φ(M), Φ(T) and both calls) + residual {:.0}; topology share {:.1}%",
        log.vertices,
        log.topology_changed,
        t.total,
        t.register,
        t.improve,
        topology,
        t.residual,
        100.0 * topology / t.total
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
