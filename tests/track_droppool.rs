//! Tracking the second real fluid sequence (`tests/data/droppool_mpm_taichi`: MLS-MPM drops
//! falling into a pool, from another solver than the shared dam break) through the first merge:
//! every frame is a closed manifold with the input's components and Euler characteristics, within
//! one input edge length of it, with 99% of its triangles at 10° or more — and the tracker keeps
//! most of its vertices from frame to frame, which a tracker that copied its input every frame
//! would not (it would carry over none).

use std::path::Path;
use surftrack::compute::Backend;
use surftrack::eval::{surface_distances, triangle_quality};
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

#[test]
fn drops_merging_into_a_pool_keep_their_vertices() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/droppool_mpm_taichi");
    let sequence = discover_sequence(&dir).unwrap();
    let paths: Vec<_> = sequence.frames[..COUNT]
        .iter()
        .map(|(_, p)| p.clone())
        .collect();
    let mut tracked: Vec<(IndexedMesh, Option<f64>)> = Vec::new();
    track_sequence::<()>(
        FrameSource::Files(&paths),
        &Backend::Cpu,
        &TrackOptions::default(),
        None,
        |progress| {
            if let Progress::Frame { tracker, log, .. } = progress {
                tracked.push((tracker.mesh().to_indexed(), log.carried));
            }
        },
    )
    .unwrap();
    let mut carried = Vec::new();
    for (k, (out, share)) in tracked.iter().enumerate() {
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
