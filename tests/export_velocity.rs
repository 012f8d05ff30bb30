//! The velocity definition on a hand-made three-frame sequence, and the stream that reads a
//! sequence for it one frame ahead, each frame once.

use glam::Vec3;
use std::cell::RefCell;
use surftrack::apps::{NoIds, VelocityStream};
use surftrack::mesh::IndexedMesh;

const FPS: f32 = 24.0;

fn frame(vertices: &[(u64, [f32; 3])]) -> IndexedMesh {
    let mut mesh = IndexedMesh::new(
        vertices.iter().map(|(_, p)| Vec3::from_array(*p)).collect(),
        Vec::new(),
    );
    mesh.ids = Some(vertices.iter().map(|(id, _)| *id).collect());
    mesh
}

/// Id 1 lives in all three frames, 2 in frames 0 and 1, 3 in frame 0 only, 4 in frames 1 and 2,
/// 5 in frame 2 only; vertex order changes between frames.
fn sequence() -> Vec<IndexedMesh> {
    vec![
        frame(&[
            (1, [0.0, 0.0, 0.0]),
            (2, [1.0, 0.0, 0.0]),
            (3, [5.0, 5.0, 5.0]),
        ]),
        frame(&[
            (2, [1.0, 0.5, 0.0]),
            (4, [2.0, 0.0, 0.0]),
            (1, [0.0, 0.0, 0.25]),
        ]),
        frame(&[
            (5, [9.0, 9.0, 9.0]),
            (1, [0.0, 0.0, 1.0]),
            (4, [2.0, 0.0, -1.0]),
        ]),
    ]
}

fn stream_of(frames: &[IndexedMesh]) -> Vec<Vec<Vec3>> {
    VelocityStream::new(
        |k: usize| Ok::<_, NoIds>(frames[k].clone()),
        frames.len(),
        FPS,
    )
    .map(|f| f.unwrap().velocities)
    .collect()
}

#[test]
fn forward_where_the_id_lives_on_else_backward_else_zero() {
    let v = stream_of(&sequence());
    let by = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * FPS;
    // Frame 0: 1 and 2 move forward; 3 ends here and has no past.
    assert_eq!(v[0], [by(0.0, 0.0, 0.25), by(0.0, 0.5, 0.0), Vec3::ZERO]);
    // Frame 1: 2 ends here, so backward; 4 and 1 forward.
    assert_eq!(
        v[1],
        [by(0.0, 0.5, 0.0), by(0.0, 0.0, -1.0), by(0.0, 0.0, 0.75)]
    );
    // Frame 2, the last: 5 was just born (0); 1 and 4 backward.
    assert_eq!(v[2], [Vec3::ZERO, by(0.0, 0.0, 0.75), by(0.0, 0.0, -1.0)]);
}

#[test]
fn a_lone_frame_has_no_velocity() {
    let frames = &sequence()[..1];
    assert_eq!(stream_of(frames), [vec![Vec3::ZERO; 3]]);
}

#[test]
fn frames_are_read_once_in_order_and_one_ahead() {
    let frames = sequence();
    let reads = RefCell::new(Vec::new());
    let stream = VelocityStream::new(
        |k: usize| {
            reads.borrow_mut().push(k);
            Ok::<_, NoIds>(frames[k].clone())
        },
        frames.len(),
        FPS,
    );
    for item in stream {
        let index = item.unwrap().index;
        let expected: Vec<usize> = (0..(index + 2).min(frames.len())).collect();
        assert_eq!(*reads.borrow(), expected, "after giving out frame {index}");
    }
}

#[test]
fn a_frame_without_ids_ends_the_stream_with_an_error() {
    let mut frames = sequence();
    frames[1].ids = None;
    let results: Vec<_> = VelocityStream::new(
        |k: usize| Ok::<_, NoIds>(frames[k].clone()),
        frames.len(),
        FPS,
    )
    .collect();
    assert_eq!(results.len(), 1);
    let error = results[0].as_ref().unwrap_err();
    assert_eq!(error.frame, 1);
    assert!(error.to_string().contains("no persistent vertex ids"));
}
