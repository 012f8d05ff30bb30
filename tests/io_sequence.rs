//! Sequence discovery: numeric order, patterns, gaps, and refusing ambiguous directories.

mod data_support;
use std::fs;
use std::path::{Path, PathBuf};
use surftrack::io::{IoError, discover_sequence};

fn touch(dir: &Path, names: &[&str]) {
    for name in names {
        fs::write(dir.join(name), b"").unwrap();
    }
}

fn numbers(frames: &[(i64, PathBuf)]) -> Vec<i64> {
    frames.iter().map(|(n, _)| *n).collect()
}

#[test]
fn directory_frames_are_ordered_numerically_with_gaps() {
    let dir = tempfile::tempdir().unwrap();
    touch(
        dir.path(),
        &[
            "frame_10.obj",
            "frame_9.obj",
            "frame_8.obj",
            "frame_13.obj",
            "notes.txt",
            ".frame_11.obj",
        ],
    );
    let sequence = discover_sequence(dir.path()).unwrap();
    assert_eq!(numbers(&sequence.frames), [8, 9, 10, 13]);
    assert_eq!(sequence.frames[1].1, dir.path().join("frame_9.obj"));
    assert_eq!(sequence.gaps, [(11, 12)]);
    assert_eq!(sequence.stride, 1);
    assert_eq!(sequence.gap_ranges(), ["11..=12"]);
    assert_eq!(sequence.pattern, "frame_*.obj");
}

#[test]
fn a_cache_written_every_nth_frame_has_gaps_only_on_its_stride() {
    let dir = tempfile::tempdir().unwrap();
    touch(
        dir.path(),
        &["f_0000.ply", "f_0003.ply", "f_0006.ply", "f_0009.ply"],
    );
    let sequence = discover_sequence(dir.path()).unwrap();
    assert_eq!(sequence.stride, 3);
    assert!(sequence.gaps.is_empty());

    touch(dir.path(), &["f_0021.ply", "f_0030.ply"]);
    let sequence = discover_sequence(dir.path()).unwrap();
    assert_eq!(sequence.stride, 3);
    assert_eq!(sequence.gaps, [(12, 18), (24, 27)]);
    assert_eq!(
        sequence.gap_ranges(),
        ["12..=18 (numbered every 3)", "24..=27 (numbered every 3)"]
    );

    // One frame off the stride makes it 1 again: every other number is then missing.
    touch(dir.path(), &["f_0031.ply"]);
    let sequence = discover_sequence(dir.path()).unwrap();
    assert_eq!(sequence.stride, 1);
    assert_eq!(sequence.gaps[0], (1, 2));
}

#[test]
fn fixed_width_patterns_match_zero_padded_numbers() {
    let dir = tempfile::tempdir().unwrap();
    touch(
        dir.path(),
        &[
            "fluid_0001.obj",
            "fluid_0002.obj",
            "fluid_0004.obj",
            "fluid_10000.obj",
            "fluid_001.obj",
            "fluid_00003.obj",
            "fluid_0005.ply",
            "other_0003.obj",
        ],
    );
    let sequence = discover_sequence(&dir.path().join("fluid_####.obj")).unwrap();
    assert_eq!(numbers(&sequence.frames), [1, 2, 4, 10000]);
    assert_eq!(sequence.gaps, [(3, 3), (5, 9999)]);

    // Without a width, fluid_0001 and fluid_001 are both frame 1.
    let error = discover_sequence(&dir.path().join("fluid_*.obj")).unwrap_err();
    assert!(
        matches!(error, IoError::DuplicateFrame { frame: 1, .. }),
        "{error}"
    );
}

#[test]
fn glob_patterns_and_compound_extensions() {
    let dir = tempfile::tempdir().unwrap();
    touch(
        dir.path(),
        &[
            "mesh_3.bobj.gz",
            "mesh_1.bobj.gz",
            "mesh_2.bobj.gz",
            "mesh_x.bobj.gz",
        ],
    );
    let sequence = discover_sequence(&dir.path().join("mesh_*.bobj.gz")).unwrap();
    assert_eq!(numbers(&sequence.frames), [1, 2, 3]);
    assert!(sequence.gaps.is_empty());
    assert_eq!(sequence.pattern, "mesh_#.bobj.gz");
}

#[test]
fn ambiguous_or_empty_inputs_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let error = discover_sequence(dir.path()).unwrap_err();
    assert!(matches!(error, IoError::NoFrames { .. }), "{error}");

    touch(dir.path(), &["a_1.obj", "a_2.obj", "b_1.obj", "c_1.ply"]);
    let error = discover_sequence(dir.path()).unwrap_err();
    match &error {
        IoError::MixedSequences { patterns, .. } => {
            assert_eq!(patterns, &["a_*.obj", "b_*.obj", "c_*.ply"]);
        }
        other => panic!("{other}"),
    }
    assert!(
        error.to_string().contains("a_*.obj, b_*.obj, c_*.ply"),
        "{error}"
    );

    touch(dir.path(), &["a_01.obj"]);
    let error = discover_sequence(&dir.path().join("a_*.obj")).unwrap_err();
    assert!(
        matches!(error, IoError::DuplicateFrame { frame: 1, .. }),
        "{error}"
    );

    for pattern in ["z_*.obj", "a_*_*.obj", "a_*.stl"] {
        let error = discover_sequence(&dir.path().join(pattern)).unwrap_err();
        assert!(
            matches!(error, IoError::NoFrames { .. } | IoError::BadPattern { .. }),
            "{pattern}: {error}"
        );
    }
    let error = discover_sequence(&dir.path().join("nothing.obj")).unwrap_err();
    assert!(matches!(error, IoError::NotFound { .. }), "{error}");
}

#[test]
fn a_single_file_is_a_sequence_of_one() {
    let dir = tempfile::tempdir().unwrap();
    touch(dir.path(), &["shot_0042.ply", "shot.ply"]);
    let sequence = discover_sequence(&dir.path().join("shot_0042.ply")).unwrap();
    assert_eq!(numbers(&sequence.frames), [42]);
    let sequence = discover_sequence(&dir.path().join("shot.ply")).unwrap();
    assert_eq!(numbers(&sequence.frames), [0]);
}

#[test]
fn the_dambreak_frames_form_one_gapless_sequence() {
    let Some(dir) = data_support::dambreak() else {
        return;
    };
    let sequence = discover_sequence(&dir).unwrap();
    assert_eq!(sequence.pattern, "fluid_mesh_####.bobj.gz");
    assert_eq!(numbers(&sequence.frames), (0..45).collect::<Vec<_>>());
    assert!(sequence.gaps.is_empty());
}
