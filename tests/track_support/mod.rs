//! What the `track_*` end-to-end tests share: the binary, a synthetic input, a `track` command with
//! the CPU backend, and the written run's progress and files.

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
