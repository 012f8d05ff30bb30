//! What the `track_*` end-to-end tests share: the binary, a synthetic input, a `track` command with
//! the CPU backend, and the written run's progress, files and Hausdorff distances. Each test
//! crate uses some of them.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

pub fn surftrack() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
}

/// Writes synth `scene` into `dir`.
pub fn synth(scene: &str, dir: &Path, resolution: &str, frames: &str) {
    let status = surftrack()
        .args(["synth", scene, "-o"])
        .arg(dir)
        .args(["--resolution", resolution, "--frames", frames])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
}

/// `surftrack track INPUT -o OUT --backend cpu --quiet EXTRA…`.
pub fn track(input: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = surftrack();
    c.arg("track").arg(input).arg("-o").arg(out);
    c.args(["--backend", "cpu", "--quiet"]).args(extra);
    c
}

/// Runs `command` quietly; panics unless it succeeds.
pub fn run(command: &mut Command) {
    let status = command
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success(), "{command:?}");
}

/// Each frame's Hausdorff distance to its input in Δ, from the `eval.json` `eval` wrote in `out`.
pub fn hausdorff(out: &Path) -> Vec<f64> {
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("eval.json")).unwrap()).unwrap();
    report["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["hausdorff"].as_f64().unwrap())
        .collect()
}

/// Frames `track.json` records as complete (0 when there is none yet).
pub fn completed(out: &Path) -> usize {
    std::fs::read_to_string(out.join("track.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v["completed"].as_u64())
        .unwrap_or(0) as usize
}

/// Every file under `frames/` and `events/`, hidden ones included, with its bytes.
pub fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for sub in ["frames", "events"] {
        let Ok(entries) = std::fs::read_dir(dir.join(sub)) else {
            continue;
        };
        let mut names: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
        names.sort();
        for p in names {
            let name = format!("{sub}/{}", p.file_name().unwrap().to_string_lossy());
            out.push((name, std::fs::read(&p).unwrap()));
        }
    }
    out
}

/// Asserts that two runs wrote the same files under `frames/` and `events/`, byte for byte.
pub fn assert_same_files(whole: &Path, other: &Path) {
    let (a, b) = (files(whole), files(other));
    let names = |f: &[(String, Vec<u8>)]| f.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&a), names(&b));
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name} differs");
    }
}

/// Rolls the run in `out` back to its first `k` complete frames, as if it had been killed then:
/// `track.json` says so and the later frames' files are gone.
pub fn roll_back(out: &Path, k: usize) {
    let state_path = out.join("track.json");
    let mut state: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&state_path).unwrap()).unwrap();
    let frames = state["completed"].as_u64().unwrap() as usize;
    state["completed"] = k.into();
    state["frames"].as_array_mut().unwrap().truncate(k);
    state["written"].as_array_mut().unwrap().truncate(k);
    state["next_id"] = state["written"][k - 1]["next_id"].clone();
    std::fs::write(&state_path, state.to_string()).unwrap();
    for j in k..frames {
        std::fs::remove_file(out.join(format!("frames/frame_{j:04}.ply"))).unwrap();
        std::fs::remove_file(out.join(format!("events/{j:04}.events"))).unwrap();
    }
}
