//! Synthetic scenes: every frame a closed manifold with the topology its manifest states, the
//! promised topology changes present, consecutive triangulations distinct, rigid ground truth
//! consistent with the surfaces, and the written sequence readable back.

use glam::{Mat4, Vec3};
use std::path::PathBuf;
use surftrack::io::{Format, read_frame};
use surftrack::mesh::IndexedMesh;
use surftrack::synth::{
    Field, Frame, MANIFEST_FILE, Manifest, Scene, SynthError, SynthOptions, generate, plan,
    write_sequence,
};

fn frames(scene: Scene, options: &SynthOptions) -> Vec<Frame> {
    generate(scene, options)
        .unwrap()
        .map(|frame| frame.unwrap())
        .collect()
}

/// Every frame closed, manifold, with the components and genus its truth states.
fn assert_frames_match_truth(scene: Scene, frames: &[Frame]) {
    for frame in frames {
        let index = frame.truth.index;
        frame
            .mesh
            .validate()
            .unwrap_or_else(|e| panic!("{scene} frame {index}: {e}"));
        let topology = frame.mesh.topology();
        assert_eq!(
            (topology.components.len(), topology.total_genus()),
            (frame.truth.components, frame.truth.genus),
            "{scene} frame {index}: (components, genus)"
        );
    }
}

fn topology_sequence(frames: &[Frame]) -> Vec<(usize, i64)> {
    frames
        .iter()
        .map(|f| (f.truth.components, f.truth.genus))
        .collect()
}

#[test]
fn every_frame_of_every_scene_has_its_stated_topology() {
    let options = SynthOptions {
        resolution: 32,
        frames: 12,
    };
    for scene in Scene::ALL {
        assert_frames_match_truth(scene, &frames(scene, &options));
    }
}

#[test]
fn default_sequences_have_their_stated_topology() {
    let options = SynthOptions::default();
    for scene in Scene::ALL {
        let frames = frames(scene, &options);
        assert_eq!(frames.len(), options.frames);
        assert_frames_match_truth(scene, &frames);
    }
}

#[test]
fn scenes_go_through_their_topology_changes() {
    for resolution in [24, 48] {
        let options = SynthOptions {
            resolution,
            frames: 9,
        };
        let sequence = |scene| topology_sequence(&frames(scene, &options));
        let merge = sequence(Scene::Merge);
        assert_eq!(merge.first(), Some(&(2, 0)));
        assert_eq!(merge.last(), Some(&(1, 0)));
        let split = sequence(Scene::Split);
        assert_eq!(split.first(), Some(&(1, 0)));
        assert_eq!(split.last(), Some(&(2, 0)));
        let morph = sequence(Scene::Morph);
        assert_eq!(morph.first(), Some(&(1, 0)));
        assert_eq!(morph.last(), Some(&(1, 1)));
        let droplets = sequence(Scene::Droplets);
        assert_eq!(droplets.first(), Some(&(1, 0)));
        assert_eq!(droplets.last(), Some(&(1, 0)));
        assert!(droplets.iter().any(|&(c, _)| c >= 3), "{droplets:?}");
        for scene in [Scene::Blobs, Scene::Rigid] {
            assert!(sequence(scene).iter().all(|&t| t == (1, 0)));
        }
    }
}

#[test]
fn consecutive_frames_never_share_a_triangulation() {
    let options = SynthOptions {
        resolution: 28,
        frames: 10,
    };
    for scene in Scene::ALL {
        let frames = frames(scene, &options);
        for pair in frames.windows(2) {
            let (a, b) = (&pair[0].mesh, &pair[1].mesh);
            let same_size = a.positions.len() == b.positions.len();
            assert!(
                !(same_size && a.positions == b.positions),
                "{scene} frames {} and {} coincide",
                pair[0].truth.index,
                pair[1].truth.index
            );
            assert_ne!(pair[0].truth.grid.origin, pair[1].truth.grid.origin);
        }
    }
}

#[test]
fn surfaces_stay_within_the_scene_bounds() {
    let options = SynthOptions {
        resolution: 40,
        frames: 16,
    };
    for scene in Scene::ALL {
        let [lo, hi] = scene.bounds();
        for frame in frames(scene, &options) {
            let slack = frame.truth.grid.spacing * 1e-3;
            for p in &frame.mesh.positions {
                assert!(
                    p.cmpge(lo - slack).all() && p.cmple(hi + slack).all(),
                    "{scene} frame {}: {p} outside {lo}..{hi}",
                    frame.truth.index
                );
            }
        }
    }
}

/// Distance of `p` from the zero set of `field`, to first order: value over gradient length.
fn distance_to_surface(field: &Field, p: Vec3, step: f32) -> f32 {
    let value = field.value(p);
    let gradient = Vec3::new(
        field.value(p + Vec3::X * step) - field.value(p - Vec3::X * step),
        field.value(p + Vec3::Y * step) - field.value(p - Vec3::Y * step),
        field.value(p + Vec3::Z * step) - field.value(p - Vec3::Z * step),
    ) / (2.0 * step);
    value.abs() / gradient.length()
}

/// Frame j's vertices, carried back by the recorded motion `T_0 · T_j⁻¹`, lie on frame 0's surface.
#[test]
fn rigid_ground_truth_carries_each_frame_onto_the_first() {
    let options = SynthOptions {
        resolution: 40,
        frames: 7,
    };
    for scene in [Scene::Blobs, Scene::Rigid] {
        let frames = frames(scene, &options);
        let first = &frames[0].truth;
        let to_first = Mat4::from_cols_array_2d(&first.transform.unwrap().matrix);
        for frame in &frames[1..] {
            let to_frame = Mat4::from_cols_array_2d(&frame.truth.transform.unwrap().matrix);
            let back = to_first * to_frame.inverse();
            let h = frame.truth.grid.spacing;
            let errors: Vec<f32> = frame
                .mesh
                .positions
                .iter()
                .map(|p| distance_to_surface(&first.field, back.transform_point3(*p), 1e-3) / h)
                .collect();
            let worst = errors.iter().copied().fold(0.0f32, f32::max);
            let mean = errors.iter().sum::<f32>() / errors.len() as f32;
            let at = frame.truth.index;
            assert!(
                mean < 0.02,
                "{scene} frame {at}: mean distance {mean} cells"
            );
            assert!(
                worst < 0.5,
                "{scene} frame {at}: worst distance {worst} cells"
            );
        }
    }
}

#[test]
fn blobs_make_one_full_turn() {
    let options = SynthOptions {
        resolution: 24,
        frames: 8,
    };
    let truths = plan(Scene::Blobs, &options).unwrap();
    let rotation = |i: usize| truths[i].transform.unwrap().rotation();
    assert!(rotation(0).angle_between(glam::Quat::IDENTITY) < 1e-6);
    let step = rotation(0).angle_between(rotation(1));
    assert!((step - std::f32::consts::TAU / 8.0).abs() < 1e-4);
    for i in 1..8 {
        assert!((rotation(i - 1).angle_between(rotation(i)) - step).abs() < 1e-4);
    }
}

fn scratch_dir(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("surftrack-synth-{name}-{}", std::process::id()))
}

fn read_back(path: &std::path::Path) -> IndexedMesh {
    read_frame(path).unwrap().mesh
}

#[test]
fn written_sequence_reads_back_with_its_manifest() {
    let options = SynthOptions {
        resolution: 24,
        frames: 3,
    };
    let dir = scratch_dir("write");
    let _ = std::fs::remove_dir_all(&dir);
    for format in [Format::Obj, Format::Ply, Format::BobjGz] {
        let manifest = write_sequence(Scene::Merge, &options, &dir, format, true).unwrap();
        let text = std::fs::read_to_string(dir.join(MANIFEST_FILE)).unwrap();
        let parsed: Manifest = serde_json::from_str(&text).unwrap();
        assert_eq!(parsed, manifest);
        assert_eq!(manifest.scene, "merge");
        assert_eq!(manifest.frames.len(), 3);
        let generated = frames(Scene::Merge, &options);
        for (record, frame) in manifest.frames.iter().zip(&generated) {
            assert_eq!(record.truth, frame.truth);
            assert!(record.file.ends_with(format.extension()));
            let mesh = read_back(&dir.join(&record.file));
            assert_eq!(mesh.positions.len(), record.vertices);
            assert_eq!(mesh.triangles.len(), record.triangles);
            assert_eq!(mesh.triangles, frame.mesh.triangles);
        }
    }
    assert!(matches!(
        write_sequence(Scene::Merge, &options, &dir, Format::Obj, false),
        Err(SynthError::Io(_))
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_options_are_refused_before_anything_is_written() {
    let dir = scratch_dir("refused");
    for (resolution, frames) in [(8, 10), (5000, 10), (32, 1), (32, 0)] {
        let options = SynthOptions { resolution, frames };
        let result = write_sequence(Scene::Blobs, &options, &dir, Format::Ply, false);
        assert!(
            matches!(
                result,
                Err(SynthError::Resolution { .. } | SynthError::Frames { .. })
            ),
            "{resolution} x {frames}"
        );
        assert!(!dir.exists());
    }
}
