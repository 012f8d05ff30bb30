//! `surftrack track` end to end: a run killed with SIGKILL and resumed gives byte-identical output to
//! an uninterrupted one, and every tracked frame is a closed manifold with its input's topology.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use surftrack::io::read_frame;

fn surftrack() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
}

fn synth(scene: &str, dir: &Path, resolution: &str, frames: &str) {
    let status = surftrack()
        .args(["synth", scene, "-o"])
        .arg(dir)
        .args(["--resolution", resolution, "--frames", frames])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
}

fn track(input: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = surftrack();
    c.arg("track").arg(input).arg("-o").arg(out);
    c.args(["--backend", "cpu", "--quiet"]).args(extra);
    c
}

fn completed(out: &Path) -> usize {
    std::fs::read_to_string(out.join("track.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["completed"].as_u64())
        .unwrap_or(0) as usize
}

fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for sub in ["frames", "events"] {
        let mut names: Vec<_> = std::fs::read_dir(dir.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        names.sort();
        for p in names {
            let name = format!("{sub}/{}", p.file_name().unwrap().to_string_lossy());
            out.push((name, std::fs::read(&p).unwrap()));
        }
    }
    out
}

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
    let (a, b) = (files(&whole), files(&killed));
    assert_eq!(a.len(), b.len());
    for ((na, da), (nb, db)) in a.iter().zip(&b) {
        assert_eq!(na, nb);
        assert!(da == db, "{na} differs after resume");
    }
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
    assert!(String::from_utf8_lossy(&changed.stderr).contains("differ"));
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
