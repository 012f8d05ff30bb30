//! The commands a new user types first, run as the binary: `demo`, `bench` on two frames, and
//! `track --backend gpu` against `--backend cpu` (same frames and events, byte for byte).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn surftrack() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
}

fn run(command: &mut Command) -> String {
    let out = command.stderr(Stdio::inherit()).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{command:?} failed:\n{stdout}");
    stdout
}

/// Every file below `dir` with its bytes, by path relative to `dir`, sorted.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        out.push((name, std::fs::read(&path).unwrap()));
    }
    out.sort();
    out
}

#[test]
fn demo_runs_and_writes_its_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    let stdout = run(surftrack()
        .args(["demo", "--resolution", "24", "--frames", "5", "-o"])
        .arg(&out));
    assert!(stdout.contains("surftrack track"), "{stdout}");
    let tracked: Vec<_> = walk(&out)
        .into_iter()
        .filter(|p| p.extension().is_some_and(|e| e == "events"))
        .collect();
    assert!(!tracked.is_empty(), "the demo wrote no event lists");
    for scene in ["merge", "split"] {
        let chart = out.join(scene).join("eval.png");
        assert!(chart.is_file(), "no chart {}", chart.display());
        assert!(stdout.contains(&chart.display().to_string()), "{stdout}");
    }
    assert!(out.join("merge/waves/frame_0000.ply").is_file());
}

fn walk(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            out.extend(walk(&path));
        } else {
            out.push(path);
        }
    }
    out
}

/// Three frames of synth `scene` at resolution 24, written under `dir`.
fn small_synth(scene: &str, dir: &Path) -> PathBuf {
    let input = dir.join("in");
    run(surftrack()
        .args(["synth", scene, "--resolution", "24", "--frames", "3", "-o"])
        .arg(&input));
    input
}

#[test]
fn bench_times_two_frames_of_a_given_sequence() {
    let dir = tempfile::tempdir().unwrap();
    let input = small_synth("blobs", dir.path());
    let stdout = run(surftrack()
        .args(["bench", "--frames", "2", "--input"])
        .arg(&input));
    let row = stdout
        .lines()
        .find(|l| l.contains("cpu"))
        .unwrap_or_else(|| panic!("no CPU row in:\n{stdout}"));
    // The last time column is the frame's total.
    let total = row
        .split_whitespace()
        .filter_map(|t| t.strip_suffix("ms"))
        .next_back()
        .and_then(|t| t.parse::<f64>().ok());
    assert!(total.is_some_and(|t| t > 0.0), "{row}");
}

#[test]
fn bench_json_gives_the_stage_figures_of_every_run() {
    let dir = tempfile::tempdir().unwrap();
    let input = small_synth("merge", dir.path());
    let stdout = run(surftrack()
        .args(["bench", "--frames", "3", "--json", "--input"])
        .arg(&input));
    let report: serde_json::Value =
        serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("{e} in:\n{stdout}"));
    let cpu = report["runs"]
        .as_array()
        .and_then(|runs| {
            runs.iter()
                .find(|r| r["backend"].as_str().is_some_and(|b| b.starts_with("cpu")))
        })
        .unwrap_or_else(|| panic!("no CPU run in:\n{stdout}"));
    assert_eq!(cpu["frames_timed"], 2);
    assert!(cpu["vertices"].as_u64().is_some_and(|v| v > 0));
    let t = &cpu["ms_per_frame"];
    let stage = |name: &str| {
        t[name]
            .as_f64()
            .unwrap_or_else(|| panic!("no {name} in {t}"))
    };
    let stages: f64 = [
        "register",
        "improve",
        "topology_self",
        "topology_target",
        "reconcile",
        "residual",
    ]
    .iter()
    .map(|s| stage(s))
    .sum();
    // The stages are parts of the frame, timed inside it; the fine stage is part of registration.
    assert!(stages > 0.0 && stages <= stage("total") * 1.0001, "{t}");
    assert!(
        stage("register_fine") > 0.0 && stage("register_fine") <= stage("register"),
        "{t}"
    );
    assert!(
        report["peak_memory_mib"].as_f64().is_some_and(|m| m > 0.0),
        "{stdout}"
    );
    // The CPU path spends part of each frame in the stages the GPU path runs as kernels, and
    // moves nothing to a device; the GPU path moves bytes both ways.
    assert!(
        cpu["gpu_share"]
            .as_f64()
            .is_some_and(|s| s > 0.0 && s < 1.0),
        "{cpu}"
    );
    assert!(cpu["bytes_per_frame"].is_null(), "{cpu}");
    let gpu = report["runs"].as_array().and_then(|runs| {
        runs.iter()
            .find(|r| r["backend"].as_str().is_some_and(|b| b.starts_with("gpu")))
    });
    if let Some(gpu) = gpu {
        let moved = gpu["bytes_per_frame"].as_array();
        assert!(
            moved.is_some_and(|m| m.iter().all(|b| b.as_u64().is_some_and(|b| b > 0))),
            "{gpu}"
        );
    }
}

#[test]
fn track_on_the_gpu_writes_what_the_cpu_writes() {
    surftrack::compute::parity::run_on_gpu(|_| {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in");
        run(surftrack()
            .args([
                "synth",
                "merge",
                "--resolution",
                "28",
                "--frames",
                "4",
                "-o",
            ])
            .arg(&input));
        let out = |backend: &str| {
            let out = dir.path().join(backend);
            run(surftrack()
                .arg("track")
                .arg(&input)
                .args(["--quiet", "--backend", backend, "-o"])
                .arg(&out));
            out
        };
        let (cpu, gpu) = (out("cpu"), out("gpu"));
        for sub in ["frames", "events"] {
            assert!(
                files(&cpu.join(sub)) == files(&gpu.join(sub)),
                "{sub}/ differs between the backends"
            );
        }
    });
}
