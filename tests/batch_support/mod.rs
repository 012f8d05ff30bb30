//! What the `batch_*` tests share: the binary, small synthetic caches, a manifest, and the bytes
//! of a tracked folder.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

pub fn surftrack() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_surftrack"));
    // A test run inside a farm task must not be steered by the task's own index.
    c.env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX");
    c
}

/// Writes the synthetic sequence `scene` into `dir`: small frames (a few hundred vertices).
pub fn synth(scene: &str, dir: &Path, resolution: usize, frames: usize) {
    let status = surftrack()
        .args(["synth", scene, "-o"])
        .arg(dir)
        .args(["--resolution", &resolution.to_string()])
        .args(["--frames", &frames.to_string()])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
}

/// The frame files of the sequence in `dir`, in order.
pub fn frame_files(dir: &Path) -> Vec<PathBuf> {
    let mut frames: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ply"))
        .collect();
    frames.sort();
    frames
}

/// Writes `lines` as the manifest `path`.
pub fn manifest(path: &Path, lines: &[&str]) {
    std::fs::write(path, lines.join("\n") + "\n").unwrap();
}

/// `surftrack batch MANIFEST -o OUT --backend cpu` plus `extra`.
pub fn batch(manifest: &Path, out: &Path, extra: &[&str]) -> Command {
    let mut c = surftrack();
    c.arg("batch").arg(manifest).arg("-o").arg(out);
    c.args(["--backend", "cpu"]).args(extra);
    c
}

/// Every tracked frame and event list of the tracked folder `dir`, by name, with its bytes.
pub fn tracked_bytes(dir: &Path) -> Vec<(String, Vec<u8>)> {
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

pub fn json(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}
