//! Tracking the second real fluid sequence (`tests/data/droppool_mpm_taichi`: MLS-MPM drops
//! falling into a pool, from another solver than the shared dam break) through the first merge:
//! every frame is a closed manifold with the input's components and Euler characteristics, within
//! one input edge length of it, with 99% of its triangles at 10° or more — and the tracker keeps
//! most of its vertices from frame to frame, which a tracker that copied its input every frame
//! would not (it would carry over none). The GPU path tracks it as the CPU path does, bit for bit,
//! and the same frames scaled by a power of two track to the same result, scaled.

use std::path::Path;
use surftrack::compute::Backend;
use surftrack::compute::parity::run_on_gpu;
use surftrack::eval::{surface_distances, triangle_quality};
use surftrack::events::EventList;
use surftrack::io::{discover_sequence, read_frame};
use surftrack::mesh::IndexedMesh;
use surftrack::sequence::{FrameSource, Progress, track_sequence};
use surftrack::track::TrackOptions;

/// Frames 0–5: three components, the first drop merging with the pool at frame 3.
const COUNT: usize = 6;

fn euler(mesh: &IndexedMesh) -> Vec<i64> {
    let mut e: Vec<i64> = mesh.topology().components.iter().map(|c| c.euler).collect();
    e.sort_unstable();
    e
}

/// The first `COUNT` frames' files.
fn frame_paths() -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/droppool_mpm_taichi");
    let sequence = discover_sequence(&dir).unwrap();
    sequence.frames[..COUNT]
        .iter()
        .map(|(_, p)| p.clone())
        .collect()
}

/// The first `COUNT` frames, read.
fn inputs() -> Vec<IndexedMesh> {
    frame_paths()
        .iter()
        .map(|p| read_frame(p).unwrap().mesh)
        .collect()
}

/// `meshes` with every position mapped by `f`.
fn moved(meshes: &[IndexedMesh], f: impl Fn(glam::Vec3) -> glam::Vec3) -> Vec<IndexedMesh> {
    meshes
        .iter()
        .map(|m| {
            let mut m = m.clone();
            m.positions.iter_mut().for_each(|p| *p = f(*p));
            m
        })
        .collect()
}

/// Every tracked frame with its events and carried-over share, tracked on `backend`.
fn track(
    paths: &[std::path::PathBuf],
    backend: &Backend,
) -> Vec<(IndexedMesh, EventList, Option<f64>)> {
    track_from(FrameSource::Files(paths), backend)
}

/// [`track`] from any source of frames.
fn track_from(
    source: FrameSource,
    backend: &Backend,
) -> Vec<(IndexedMesh, EventList, Option<f64>)> {
    let mut tracked = Vec::new();
    track_sequence::<()>(
        source,
        backend,
        &TrackOptions::default(),
        None,
        |progress| {
            if let Progress::Frame {
                tracker,
                events,
                log,
            } = progress
            {
                tracked.push((tracker.world_mesh(), events.clone(), log.carried));
            }
        },
    )
    .unwrap();
    tracked
}

#[test]
fn drops_merging_into_a_pool_keep_their_vertices() {
    let paths = frame_paths();
    let tracked = track(&paths, &Backend::Cpu);
    let mut carried = Vec::new();
    for (k, (out, _, share)) in tracked.iter().enumerate() {
        let input = read_frame(&paths[k]).unwrap().mesh;
        out.validate().unwrap_or_else(|e| panic!("frame {k}: {e}"));
        assert_eq!(euler(out), euler(&input), "frame {k}: components' χ");
        let delta = input.mean_edge_length();
        let distance = surface_distances(&Backend::Cpu, out, &input).unwrap();
        assert!(
            distance.hausdorff() <= delta,
            "frame {k}: Hausdorff {} Δ",
            distance.hausdorff() / delta
        );
        let quality = triangle_quality(out, 10.0);
        assert!(quality.above_threshold >= 0.99, "frame {k}: {quality:?}");
        carried.extend(*share);
    }
    eprintln!("carried over per frame: {carried:?}");
    assert_eq!(carried.len(), COUNT - 1);
    let mean = carried.iter().sum::<f64>() / carried.len() as f64;
    assert!(
        carried.iter().all(|&c| c >= 0.7),
        "a frame kept under 70% of its vertices: {carried:?}"
    );
    assert!(mean >= 0.9, "mean carried-over share {mean}: {carried:?}");
}

/// Real data through every stage the GPU path runs as kernels (correspondences, closest points,
/// the fine stage's solve, rasterization, sweeps, band distances), a merge included: the same
/// vertices, ids, triangles and events as the CPU path, frame by frame.
#[test]
fn the_gpu_path_tracks_the_drop_pool_as_the_cpu_path_does() {
    run_on_gpu(|gpu| {
        let paths = frame_paths();
        let (cpu, gpu) = (track(&paths, &Backend::Cpu), track(&paths, gpu));
        assert_eq!(cpu.len(), COUNT);
        assert_eq!(gpu.len(), COUNT);
        for (k, (c, g)) in cpu.iter().zip(&gpu).enumerate() {
            assert!(c.0 == g.0, "frame {k}: the tracked meshes differ");
            assert!(c.1 == g.1, "frame {k}: the events differ");
        }
    });
}

/// Every distance the tracker uses is relative to the mesh's own scale (its edge length, the grid
/// spacing derived from it), so scaling the input scales the result. By a power of two every
/// product and quotient scales exactly in floating point: the tracked frames are the unscaled
/// ones scaled, bit for bit, with the same ids, triangles and events, through a merge.
#[test]
fn scaling_the_input_by_a_power_of_two_scales_the_tracked_frames_exactly() {
    let inputs = inputs();
    let reference = track_from(FrameSource::Meshes(&inputs), &Backend::Cpu);
    assert_eq!(reference.len(), COUNT);
    for scale in [4.0f32, 0.125] {
        let scaled = moved(&inputs, |p| p * scale);
        let tracked = track_from(FrameSource::Meshes(&scaled), &Backend::Cpu);
        assert_eq!(tracked.len(), COUNT);
        for (k, (r, t)) in reference.iter().zip(&tracked).enumerate() {
            let mut expected = r.0.clone();
            expected.positions.iter_mut().for_each(|p| *p *= scale);
            assert!(
                t.0 == expected,
                "scale {scale}, frame {k}: the tracked meshes differ"
            );
            assert!(t.1 == r.1, "scale {scale}, frame {k}: the events differ");
        }
    }
}

/// A cache far from the world's origin (here 4,096 units away on every axis, 32 times the frames'
/// size) tracks as it does near it: the tracker works relative to an anchor near the first frame
/// and writes world coordinates. Single precision there rounds the input by 5·10⁻⁴ L, so the
/// result is not the same bit for bit, but every frame is valid, of the input's topology, close to
/// the same size as near the origin, and carries 70% or more (tracked in world coordinates, frame 3
/// re-sampled everything: 0%).
#[test]
fn far_from_the_origin_the_drop_pool_tracks_as_near_it() {
    let inputs = inputs();
    let shifted = moved(&inputs, |p| p + glam::Vec3::splat(4096.0));
    let near = track_from(FrameSource::Meshes(&inputs), &Backend::Cpu);
    let far = track_from(FrameSource::Meshes(&shifted), &Backend::Cpu);
    assert_eq!(far.len(), COUNT);
    for (k, ((out, _, share), (reference, ..))) in far.iter().zip(&near).enumerate() {
        let input = &shifted[k];
        out.validate().unwrap_or_else(|e| panic!("frame {k}: {e}"));
        assert_eq!(euler(out), euler(input), "frame {k}: components' χ");
        let distance = surface_distances(&Backend::Cpu, out, input).unwrap();
        assert!(
            distance.hausdorff() <= input.mean_edge_length(),
            "frame {k}"
        );
        let (n, m) = (out.positions.len() as f64, reference.positions.len() as f64);
        assert!(
            (n - m).abs() <= 0.02 * m,
            "frame {k}: {n} vertices against {m}"
        );
        assert!(
            share.is_none_or(|c| c >= 0.7),
            "frame {k} carried {share:?}"
        );
    }
}

/// A cache whose triangles all face inward (a mesher with the opposite convention, a scene
/// mirrored on one axis) tracks as its outward twin, bit for bit: tracked as it was, its Φ(M) read
/// the mesh as its own complement and every frame was re-sampled whole (0% carried).
#[test]
fn a_cache_facing_inward_tracks_as_its_outward_twin() {
    let inputs = inputs();
    let inward: Vec<IndexedMesh> = inputs
        .iter()
        .map(|m| {
            let mut m = m.clone();
            m.triangles.iter_mut().for_each(|t| t.swap(1, 2));
            m
        })
        .collect();
    let reference = track_from(FrameSource::Meshes(&inputs), &Backend::Cpu);
    let turned = track_from(FrameSource::Meshes(&inward), &Backend::Cpu);
    assert_eq!(turned.len(), COUNT);
    for (k, (r, t)) in reference.iter().zip(&turned).enumerate() {
        assert!(t.0 == r.0, "frame {k}: the tracked meshes differ");
        assert!(t.1 == r.1, "frame {k}: the events differ");
    }
}
