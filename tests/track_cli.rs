//! `surftrack track` end to end: a run killed with SIGKILL and resumed gives byte-identical output to
//! an uninterrupted one, and every tracked frame is a closed manifold with its input's topology.

mod track_support;

use std::process::Stdio;
use std::time::{Duration, Instant};
use surftrack::io::{ReadOptions, read_frame, read_frame_with, write_ply};
use track_support::{assert_same_files, completed, files, roll_back, surftrack, synth, track};

#[test]
fn a_killed_run_resumes_to_identical_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    synth("merge", &input, "40", "10");
    let whole = tmp.path().join("whole");
    assert!(track(&input, &whole, &[]).status().unwrap().success());

    let killed = tmp.path().join("killed");
    let mut child = track(&input, &killed, &[])
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while completed(&killed) < 3 && start.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done = completed(&killed);
    assert!(
        (1..10).contains(&done),
        "killed after {done} frames: not mid-run"
    );

    let resumed = track(&input, &killed, &["--resume"]).output().unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_same_files(&whole, &killed);
}

/// Far from the world's origin the tracker works relative to an anchor and writes world
/// coordinates, rounding its state at the end of every frame as the written frame holds it: a run
/// stopped after three frames and resumed writes the same bytes as one run through.
#[test]
fn a_run_far_from_the_origin_resumes_to_identical_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let near = tmp.path().join("near");
    synth("merge", &near, "40", "6");
    let input = tmp.path().join("in");
    std::fs::create_dir(&input).unwrap();
    for entry in std::fs::read_dir(&near).unwrap() {
        let path = entry.unwrap().path();
        let Ok(frame) = read_frame(&path) else {
            continue;
        };
        let mut mesh = frame.mesh;
        mesh.positions
            .iter_mut()
            .for_each(|p| *p += glam::Vec3::new(2048.0, -512.0, 4096.0));
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        write_ply(&input.join(format!("{name}.ply")), &mesh).unwrap();
    }
    let whole = tmp.path().join("whole");
    assert!(track(&input, &whole, &[]).status().unwrap().success());
    let state: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(whole.join("track.json")).unwrap()).unwrap();
    assert_ne!(state["anchor"], serde_json::json!([0.0, 0.0, 0.0]));

    // The same run rolled back to three complete frames, as if it had been killed.
    let stopped = tmp.path().join("stopped");
    assert!(track(&input, &stopped, &[]).status().unwrap().success());
    roll_back(&stopped, 3);
    let resumed = track(&input, &stopped, &["--resume"]).output().unwrap();
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(files(&whole).len(), 12);
    assert_same_files(&whole, &stopped);
}

#[test]
fn resume_refuses_different_arguments_and_force_is_needed_to_overwrite() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    synth("rigid", &input, "32", "3");
    let out = tmp.path().join("out");
    assert!(track(&input, &out, &[]).status().unwrap().success());
    let again = track(&input, &out, &[]).output().unwrap();
    assert!(!again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));
    let changed = track(&input, &out, &["--resume", "--min-angle", "12"])
        .output()
        .unwrap();
    assert!(!changed.status.success());
    // The error names the parameter that differs, with both values.
    let said = String::from_utf8_lossy(&changed.stderr);
    assert!(said.contains("min_angle: 10.0 then, 12.0 now"), "{said}");
}

/// A simulation with an inflow writes empty frames until its fluid appears, and one that drains
/// writes them after it is gone. Those at the ends are left out with a warning: the run tracks
/// from the first frame with a surface to the last, byte for byte as it tracks those frames alone,
/// and `eval` against the whole folder lines its frames up the same way.
#[test]
fn empty_frames_at_either_end_are_left_out() {
    let tmp = tempfile::tempdir().unwrap();
    let source = tmp.path().join("synth");
    synth("merge", &source, "32", "4");
    let input = tmp.path().join("in");
    std::fs::create_dir(&input).unwrap();
    for k in 0..7 {
        let path = input.join(format!("merge_{k:04}.ply"));
        match k {
            2..=5 => std::fs::copy(source.join(format!("merge_{:04}.ply", k - 2)), &path)
                .map(|_| ())
                .unwrap(),
            _ => std::fs::write(&path, b"").unwrap(),
        }
    }
    let (alone, padded) = (tmp.path().join("alone"), tmp.path().join("padded"));
    assert!(track(&source, &alone, &[]).status().unwrap().success());
    let run = track(&input, &padded, &[]).output().unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(
        stderr.contains("input frames 0..=1 are empty (no fluid yet); tracking starts at frame 2"),
        "{stderr}"
    );
    assert!(
        stderr
            .contains("input frames 6..=6 are empty (the fluid is gone); tracking ends at frame 5"),
        "{stderr}"
    );
    assert_eq!(completed(&padded), 4);
    assert_same_files(&alone, &padded);
    let eval = surftrack()
        .arg("eval")
        .arg(&padded)
        .arg("--input")
        .arg(&input)
        .output()
        .unwrap();
    assert!(
        eval.status.success(),
        "{}",
        String::from_utf8_lossy(&eval.stderr)
    );

    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    for k in 0..2 {
        std::fs::write(empty.join(format!("merge_{k:04}.ply")), b"").unwrap();
    }
    let run = track(&empty, &tmp.path().join("none"), &[])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("all 2 frames are empty"), "{stderr}");
    assert!(!tmp.path().join("none").exists());
}

/// Issue 8 bar 1 on every synth scene (small resolution for CI): every tracked frame is a closed
/// 2-manifold with the input frame's components and Euler characteristic.
#[test]
fn tracked_frames_are_closed_manifolds_with_the_input_topology() {
    for scene in ["blobs", "merge", "split", "droplets", "morph", "rigid"] {
        let tmp = tempfile::tempdir().unwrap();
        let input = tmp.path().join("in");
        synth(scene, &input, "40", "8");
        let out = tmp.path().join("out");
        let run = track(&input, &out, &[]).output().unwrap();
        assert!(
            run.status.success(),
            "{scene}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
        for k in 0..8 {
            let tracked = read_frame(&out.join(format!("frames/frame_{k:04}.ply")))
                .unwrap()
                .mesh;
            let source = read_frame(&input.join(format!("{scene}_{k:04}.ply")))
                .unwrap()
                .mesh;
            assert_eq!(tracked.validate(), Ok(()), "{scene} frame {k}");
            let (t, s) = (tracked.topology(), source.topology());
            let mut te: Vec<i64> = t.components.iter().map(|c| c.euler).collect();
            let mut se: Vec<i64> = s.components.iter().map(|c| c.euler).collect();
            te.sort();
            se.sort();
            assert_eq!(
                te, se,
                "{scene} frame {k}: per-component Euler characteristics"
            );
        }
    }
}

/// The last written frame is the tracker's whole state: resume reads it exactly. Here one of its
/// vertices lies on another, two rings away (a surface touching itself, as a fluid's does before
/// the next frame merges it); a weld on reading would make that point a bow-tie and refuse it.
#[test]
fn resume_reads_the_last_frame_without_welding() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    synth("rigid", &input, "32", "3");
    let out = tmp.path().join("out");
    let whole = track(&input, &out, &[]).output().unwrap();
    assert!(whole.status.success());

    // Roll the run back to two complete frames, as if it had been killed, and move a vertex of
    // the last one onto the nearest vertex it shares no triangle with.
    roll_back(&out, 2);
    let state_path = out.join("track.json");
    let mut state: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&state_path).unwrap()).unwrap();
    let last = out.join("frames/frame_0001.ply");
    let exact = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    let mut mesh = read_frame_with(&last, &exact).unwrap().mesh;
    let v = 0u32;
    let near: std::collections::HashSet<u32> = mesh
        .triangles
        .iter()
        .filter(|t| t.contains(&v))
        .flatten()
        .copied()
        .collect();
    let p = mesh.positions[v as usize];
    let w = (0..mesh.positions.len() as u32)
        .filter(|u| !near.contains(u))
        .min_by(|&a, &b| {
            let da = mesh.positions[a as usize].distance(p);
            let db = mesh.positions[b as usize].distance(p);
            da.total_cmp(&db)
        })
        .unwrap();
    mesh.positions[v as usize] = mesh.positions[w as usize];
    write_ply(&last, &mesh).unwrap();
    // As if the run had written this frame: its size is the one recorded.
    state["written"][1]["frame_bytes"] = std::fs::metadata(&last).unwrap().len().into();
    std::fs::write(&state_path, state.to_string()).unwrap();

    let resumed = track(&input, &out, &["--resume"]).output().unwrap();
    assert!(
        resumed.status.success(),
        "resume failed: {}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    assert_eq!(completed(&out), 3);
    read_frame(&out.join("frames/frame_0002.ply"))
        .unwrap()
        .mesh
        .validate()
        .unwrap();
}
