//! Tracking a real splash meshed by a dual mesher (`tests/data/dfsph_surface_nets`: surface nets of
//! a DFSPH dam break), whose parts touch at non-manifold vertices and edges on every frame after
//! the first. The reader splits them apart in place, so every frame tracks: each tracked frame is
//! a closed manifold with the components and Euler characteristics of the frame as read, within one
//! input edge length of it, with most vertices carried over. Before the split the run stopped at
//! the first non-manifold frame.

use std::path::Path;
use surftrack::compute::Backend;
use surftrack::eval::surface_distances;
use surftrack::io::{discover_sequence, read_frame};
use surftrack::mesh::IndexedMesh;
use surftrack::sequence::{FrameSource, Progress, track_sequence};
use surftrack::track::TrackOptions;

fn euler(mesh: &IndexedMesh) -> Vec<i64> {
    let mut e: Vec<i64> = mesh.topology().components.iter().map(|c| c.euler).collect();
    e.sort_unstable();
    e
}

#[test]
fn a_splash_whose_parts_touch_tracks_through_its_merge() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/dfsph_surface_nets");
    let paths: Vec<_> = discover_sequence(&dir)
        .unwrap()
        .frames
        .into_iter()
        .map(|(_, p)| p)
        .collect();
    assert_eq!(paths.len(), 10);
    let mut split = 0;
    let mut tracked = Vec::new();
    track_sequence::<()>(
        FrameSource::Files(&paths),
        &Backend::Cpu,
        &TrackOptions::default(),
        None,
        |progress| {
            if let Progress::Frame { tracker, log, .. } = progress {
                tracked.push((tracker.world_mesh(), log.carried));
            }
        },
    )
    .unwrap();
    assert_eq!(tracked.len(), paths.len());
    let mut carried = Vec::new();
    for (k, (out, share)) in tracked.iter().enumerate() {
        let frame = read_frame(&paths[k]).unwrap();
        split += frame.repairs.split_vertices;
        let input = frame.mesh;
        out.validate().unwrap_or_else(|e| panic!("frame {k}: {e}"));
        assert_eq!(euler(out), euler(&input), "frame {k}: components' χ");
        let distance = surface_distances(&Backend::Cpu, out, &input).unwrap();
        assert!(
            distance.hausdorff() <= input.mean_edge_length(),
            "frame {k}: Hausdorff {} Δ",
            distance.hausdorff() / input.mean_edge_length()
        );
        carried.extend(*share);
    }
    assert!(
        split >= 100,
        "{split} vertices split: the frames must touch"
    );
    eprintln!("carried over per frame: {carried:?}");
    let mean = carried.iter().sum::<f64>() / carried.len() as f64;
    assert!(
        carried.iter().all(|&c| c >= 0.7),
        "a frame kept under 70% of its vertices: {carried:?}"
    );
    assert!(mean >= 0.85, "mean carried-over share {mean}: {carried:?}");
}
