//! Carrying values through hand-built tracked sequences (real mesh mutations, their journal as event
//! lists, written in the on-disk layout): the properties of paper §4.6 that do not need a tracker.

mod propagate_support;

use propagate_support::{Ops, channel, start_mesh, write_events, write_frame, write_sequence};
use std::path::Path;
use surftrack::events::EventList;
use surftrack::mesh::{Attribute, IndexedMesh};
use surftrack::propagate::{
    Channel, Direction, PropagateError, PropagateOptions, TrackedSequence, carry, propagate,
};

/// Every frame `carry` produces, in visiting order.
fn carried(dir: &Path, direction: Direction, channels: &[Attribute]) -> Vec<(usize, IndexedMesh)> {
    let sequence = TrackedSequence::open(dir).unwrap();
    let start = sequence
        .read_frame(direction.start(sequence.len()))
        .unwrap();
    let mut out = Vec::new();
    carry(&sequence, direction, start, channels, |k, mesh| {
        out.push((k, mesh));
        Ok(())
    })
    .unwrap();
    out
}

fn constant(name: &str, n: usize, value: &[f32]) -> Attribute {
    Attribute {
        name: name.to_string(),
        components: value.len(),
        values: value
            .iter()
            .copied()
            .cycle()
            .take(n * value.len())
            .collect(),
    }
}

#[test]
fn forward_carries_what_the_mesh_interpolates_itself() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 5, Ops::All, 120, 7);
    let (truth0, _) = channel(&frames[0], "truth");
    let start = Attribute {
        name: "carried".to_string(),
        ..truth0.clone()
    };
    let out = carried(dir.path(), Direction::Forward, &[start]);
    assert_eq!(
        out.iter().map(|(k, _)| *k).collect::<Vec<_>>(),
        [0, 1, 2, 3, 4]
    );
    for (k, mesh) in &out {
        assert_eq!(mesh.ids, frames[*k].ids, "frame {k}");
        let (_, got) = channel(mesh, "carried");
        let (_, want) = channel(&frames[*k], "truth");
        for (v, (g, w)) in got.iter().zip(&want).enumerate() {
            for c in 0..3 {
                assert!(
                    (g[c] - w[c]).abs() <= 1e-5,
                    "frame {k} vertex {v}: {g:?} vs {w:?}"
                );
            }
        }
    }
    assert!(out[4].1.positions.len() != frames[0].positions.len());
}

#[test]
fn a_constant_stays_constant_forward_and_backward() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 4, Ops::All, 150, 11);
    let value = [0.7f32, -3.25, 1e3];
    for direction in [Direction::Forward, Direction::Backward] {
        let n = frames[direction.start(frames.len())].positions.len();
        let out = carried(dir.path(), direction, &[constant("c", n, &value)]);
        assert_eq!(out.len(), frames.len());
        for (k, mesh) in &out {
            let (_, values) = channel(mesh, "c");
            assert_eq!(values.len(), frames[*k].positions.len());
            for v in values {
                for (x, c) in v.iter().zip(value) {
                    assert!(
                        (x - c).abs() <= 1e-6 * c.abs(),
                        "{direction:?} frame {k}: {v:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn forward_on_a_static_sequence_is_the_identity() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = start_mesh();
    for k in 0..4 {
        write_frame(dir.path(), k, &mesh);
        if k > 0 {
            write_events(dir.path(), k, &EventList::new());
        }
    }
    let out_dir = dir.path().join("out");
    let options = PropagateOptions {
        direction: Direction::Forward,
        channels: vec![Channel::checker(2.0)],
        displace: None,
        ply: true,
        obj: false,
    };
    let summary = propagate(dir.path(), &out_dir, &options, false).unwrap();
    assert_eq!(summary.vertices, vec![mesh.positions.len(); 4]);
    let first = surftrack::io::read_frame(&out_dir.join("frame_0000.ply"))
        .unwrap()
        .mesh;
    let (_, colours) = channel(&first, "color");
    assert!(colours.iter().any(|c| c[0] > 0.5) && colours.iter().any(|c| c[0] < 0.5));
    for k in 1..4 {
        let frame = surftrack::io::read_frame(&out_dir.join(format!("frame_{k:04}.ply")))
            .unwrap()
            .mesh;
        assert_eq!(frame, first, "frame {k}");
    }
}

#[test]
fn backward_undoes_forward_when_nothing_is_removed() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 4, Ops::Refine, 100, 3);
    let (truth0, _) = channel(&frames[0], "truth");
    let forward = carried(dir.path(), Direction::Forward, std::slice::from_ref(truth0));
    let (last, _) = channel(&forward[3].1, "truth");
    let backward = carried(dir.path(), Direction::Backward, std::slice::from_ref(last));
    assert_eq!(
        backward.iter().map(|(k, _)| *k).collect::<Vec<_>>(),
        [3, 2, 1, 0]
    );
    for (k, mesh) in &backward {
        assert_eq!(mesh.ids, frames[*k].ids);
        let (got, _) = channel(mesh, "truth");
        let (want, _) = channel(&forward[*k].1, "truth");
        assert_eq!(got.values, want.values, "frame {k}");
    }
}

/// Writes a two-frame sequence into `dir`: [`start_mesh`], then the same after `change` of its
/// first edge, which returns the id of the vertex it creates or keeps. Returns the edge's ends'
/// ids, that id and both frames.
fn one_change(
    dir: &Path,
    change: impl FnOnce(&mut surftrack::mesh::Mesh, surftrack::mesh::HalfEdgeId) -> u64,
) -> ((u64, u64), u64, IndexedMesh, IndexedMesh) {
    let start = start_mesh();
    let mut mesh = surftrack::mesh::Mesh::from_indexed(&start).unwrap();
    mesh.record_mutations();
    let h = mesh.edges().next().unwrap();
    let ends = (mesh.id(mesh.origin(h)), mesh.id(mesh.target(h)));
    let result = change(&mut mesh, h);
    write_frame(dir, 0, &start);
    write_events(dir, 1, &EventList::drain(&mut mesh));
    let end = mesh.to_indexed();
    write_frame(dir, 1, &end);
    (ends, result, start, end)
}

#[test]
fn backward_through_a_collapse_gives_both_ends_the_merged_value() {
    let dir = tempfile::tempdir().unwrap();
    let ((ida, idb), merged_id, _, end) = one_change(dir.path(), |mesh, h| {
        let mid = (mesh.position(mesh.origin(h)) + mesh.position(mesh.target(h))) * 0.5;
        let merged = mesh.collapse(h, mid).unwrap();
        mesh.id(merged)
    });
    let ids = end.ids.as_ref().unwrap();
    let values = Attribute {
        name: "s".to_string(),
        components: 1,
        values: ids
            .iter()
            .map(|&id| if id == merged_id { 5.0 } else { 1.0 })
            .collect(),
    };
    let out = carried(dir.path(), Direction::Backward, &[values]);
    let (k, first) = &out[1];
    assert_eq!(*k, 0);
    let (_, got) = channel(first, "s");
    for (id, v) in first.ids.as_ref().unwrap().iter().zip(got) {
        let want = if *id == ida || *id == idb { 5.0 } else { 1.0 };
        assert_eq!(v, [want], "vertex {id}");
    }
}

#[test]
fn a_merge_keeps_the_kept_ends_value_and_gives_it_to_the_removed_end_going_backward() {
    let dir = tempfile::tempdir().unwrap();
    let ((ida, idb), kept, start, end) = one_change(dir.path(), |mesh, h| {
        let kept = mesh.merge(h).unwrap();
        mesh.id(kept)
    });
    assert_eq!(kept, ida, "the origin is kept");
    let value = |id: u64| if id == ida { 5.0 } else { 1.0 };
    // The values `value` gives the frame `ids` carried in `direction`, as (id, value) pairs.
    let run = |direction: Direction, ids: &[u64]| -> Vec<(u64, f32)> {
        let values = Attribute {
            name: "s".to_string(),
            components: 1,
            values: ids.iter().map(|&id| value(id)).collect(),
        };
        let out = carried(dir.path(), direction, &[values]);
        let (_, mesh) = &out[1];
        let (_, got) = channel(mesh, "s");
        let ids = mesh.ids.as_ref().unwrap().iter().copied();
        ids.zip(got.iter().map(|v| v[0])).collect()
    };
    for (id, v) in run(Direction::Forward, start.ids.as_ref().unwrap()) {
        assert_ne!(id, idb, "the removed end is gone");
        assert_eq!(v, value(id), "vertex {id} keeps its value");
    }
    for (id, v) in run(Direction::Backward, end.ids.as_ref().unwrap()) {
        let want = if id == idb { 5.0 } else { value(id) };
        assert_eq!(v, want, "vertex {id}");
    }
}

#[test]
fn broken_sequences_are_reported_with_their_file() {
    let dir = tempfile::tempdir().unwrap();
    write_sequence(dir.path(), 3, Ops::All, 40, 5);
    let n = TrackedSequence::open(dir.path())
        .unwrap()
        .read_frame(0)
        .unwrap()
        .positions
        .len();
    let run = |dir: &Path| {
        let sequence = TrackedSequence::open(dir)?;
        let start = sequence.read_frame(0)?;
        carry(
            &sequence,
            Direction::Forward,
            start,
            &[constant("c", n, &[1.0])],
            |_, _| Ok(()),
        )
    };
    let events = dir.path().join("events/0002.events");
    let mut bytes = std::fs::read(&events).unwrap();
    bytes[40] ^= 0x55;
    std::fs::write(&events, &bytes).unwrap();
    let err = run(dir.path()).unwrap_err();
    assert!(matches!(err, PropagateError::EventFile { .. }), "{err}");
    assert!(err.to_string().contains("0002.events") && err.to_string().contains("checksum"));

    std::fs::remove_file(&events).unwrap();
    let err = run(dir.path()).unwrap_err();
    assert!(err.to_string().contains("0002.events"), "{err}");

    write_events(dir.path(), 2, &EventList::new());
    let err = run(dir.path()).unwrap_err();
    assert!(matches!(err, PropagateError::Inconsistent { .. }), "{err}");
    assert!(err.to_string().contains("frame_0002.ply"), "{err}");

    std::fs::remove_file(dir.path().join("frames/frame_0001.ply")).unwrap();
    let err = TrackedSequence::open(dir.path()).unwrap_err();
    assert!(
        matches!(err, PropagateError::FrameGap { missing: 1, .. }),
        "{err}"
    );

    let empty = tempfile::tempdir().unwrap();
    std::fs::create_dir(empty.path().join("frames")).unwrap();
    assert!(matches!(
        TrackedSequence::open(empty.path()),
        Err(PropagateError::NoFrames { .. })
    ));
}

#[test]
fn track_json_limits_the_sequence_to_completed_frames() {
    let dir = tempfile::tempdir().unwrap();
    write_sequence(dir.path(), 4, Ops::All, 20, 9);
    std::fs::write(
        dir.path().join("track.json"),
        r#"{"version": 1, "completed": 2, "input": ["a.ply", "b.ply", "c.ply", "d.ply"]}"#,
    )
    .unwrap();
    let sequence = TrackedSequence::open(dir.path()).unwrap();
    assert_eq!(sequence.len(), 2);
    assert_eq!(sequence.input().unwrap().len(), 4);
}
