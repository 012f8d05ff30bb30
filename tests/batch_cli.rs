//! `surftrack batch` end to end on small synthetic caches: a broken cache fails alone and is
//! reported, the others give the bytes `track` gives; a rerun skips what is done; a farm index
//! runs one cache; a task killed mid-cache resumes to the same bytes; bad input is refused before
//! anything is written.

mod batch_support;

use batch_support::{batch, frame_files, json, manifest, surftrack, synth, tracked_bytes};
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// Three caches in `root`, the second with a frame that is not a PLY file; returns the manifest.
fn three_caches(root: &Path) -> std::path::PathBuf {
    synth("merge", &root.join("shotA/cache"), 24, 4);
    synth("blobs", &root.join("shotB/cache"), 24, 4);
    synth("split", &root.join("shotC/cache"), 24, 4);
    let broken = frame_files(&root.join("shotB/cache"))[2].clone();
    std::fs::write(&broken, "not a mesh\n").unwrap();
    let path = root.join("caches.txt");
    manifest(
        &path,
        &[
            "# three shots",
            "shotA/cache",
            "",
            "shotB/cache",
            "shotC/cache/",
        ],
    );
    path
}

#[test]
fn a_broken_cache_fails_alone_and_a_rerun_skips_the_done_ones() {
    let tmp = tempfile::tempdir().unwrap();
    let list = three_caches(tmp.path());
    let out = tmp.path().join("out");

    let first = batch(&list, &out, &["--jobs", "2"]).output().unwrap();
    assert!(!first.status.success(), "one cache failed: non-zero exit");
    let report = json(&out.join("batch.json"));
    let caches = report["caches"].as_array().unwrap();
    let names: Vec<&str> = caches.iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["shotA-cache", "shotB-cache", "shotC-cache"]);
    let states: Vec<&str> = caches
        .iter()
        .map(|c| c["status"].as_str().unwrap())
        .collect();
    assert_eq!(states, ["done", "failed", "done"]);
    assert_eq!(
        (report["done"].as_u64(), report["failed"].as_u64()),
        (Some(2), Some(1))
    );
    let error = caches[1]["error"].as_str().unwrap();
    assert!(error.contains("shotB/cache/blobs_0002.ply"), "{error}");
    assert_eq!(caches[1]["frames"], 2, "frames 0 and 1 were tracked");
    for done in [&caches[0], &caches[2]] {
        assert_eq!(done["frames"], 4);
        assert!(done["error"].is_null());
        let coherence = done["coherence"].as_f64().unwrap();
        assert!(coherence > 0.0 && coherence <= 1.0, "{coherence}");
    }
    let table = String::from_utf8_lossy(&first.stdout);
    assert!(
        table.contains("2 done, 1 failed, 0 unfinished of 3 caches"),
        "{table}"
    );
    let failed_row = table
        .lines()
        .find(|l| l.starts_with("shotB-cache "))
        .unwrap();
    assert!(failed_row.contains("failed") && failed_row.contains("blobs_0002.ply"));

    // The batch's caches are what `track` makes of them, whatever ran beside them.
    let alone = tmp.path().join("alone");
    let tracked = surftrack()
        .arg("track")
        .arg(tmp.path().join("shotC/cache"))
        .arg("-o")
        .arg(&alone)
        .args(["--backend", "cpu", "--quiet"])
        .status()
        .unwrap();
    assert!(tracked.success());
    assert!(tracked_bytes(&alone) == tracked_bytes(&out.join("shotC-cache")));

    let statuses = |name: &str| std::fs::read(out.join(name).join("status.json")).unwrap();
    let before = (statuses("shotA-cache"), statuses("shotC-cache"));
    let second = batch(&list, &out, &["--jobs", "2"]).output().unwrap();
    assert!(!second.status.success(), "the broken cache fails again");
    let log = String::from_utf8_lossy(&second.stdout);
    assert!(log.contains("shotA-cache: done before, skipped"), "{log}");
    assert!(log.contains("shotC-cache: done before, skipped"), "{log}");
    assert_eq!(
        before,
        (statuses("shotA-cache"), statuses("shotC-cache")),
        "not run again"
    );
    assert_eq!(json(&out.join("batch.json"))["done"], 2);
}

#[test]
fn a_farm_index_runs_one_cache_and_the_report_assembles_them() {
    let tmp = tempfile::tempdir().unwrap();
    synth("merge", &tmp.path().join("a"), 24, 3);
    synth("split", &tmp.path().join("b"), 24, 3);
    let list = tmp.path().join("caches.txt");
    manifest(&list, &["a", "b"]);
    let out = tmp.path().join("out");

    let second = batch(
        &list,
        &out,
        &["--propagate", "--forward --checker", "--eval"],
    )
    .env("SLURM_ARRAY_TASK_ID", "1")
    .output()
    .unwrap();
    assert!(second.status.success(), "{second:?}");
    assert!(!out.join("a").exists(), "only the second cache ran");
    assert!(
        !out.join("batch.json").exists(),
        "a task writes only its cache's folder"
    );
    assert_eq!(json(&out.join("b/status.json"))["status"], "done");
    assert_eq!(json(&out.join("b/summary.json"))["frames"], 3);
    assert!(out.join("b/eval.json").is_file());
    assert!(out.join("b/propagated/frame_0002.ply").is_file());

    let early = batch(&list, &out, &["--report"]).output().unwrap();
    assert!(!early.status.success(), "the first cache is still pending");
    assert_eq!(
        json(&out.join("batch.json"))["caches"][0]["status"],
        "pending"
    );

    let first = batch(
        &list,
        &out,
        &["--propagate", "--forward --checker", "--eval"],
    )
    .env("JOB_COMPLETION_INDEX", "0")
    .status()
    .unwrap();
    assert!(first.success());
    let report = batch(&list, &out, &["--report"]).output().unwrap();
    assert!(report.status.success());
    assert_eq!(json(&out.join("batch.json"))["done"], 2);
}

#[test]
fn a_task_killed_mid_cache_resumes_to_identical_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    synth("merge", &tmp.path().join("shot"), 40, 12);
    let list = tmp.path().join("caches.txt");
    manifest(&list, &["shot"]);
    let whole = tmp.path().join("whole");
    assert!(
        batch(&list, &whole, &["--index", "0"])
            .status()
            .unwrap()
            .success()
    );

    let killed = tmp.path().join("killed");
    let mut task = batch(&list, &killed, &["--index", "0"])
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let completed = || {
        std::fs::read_to_string(killed.join("shot/track.json"))
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
            .and_then(|v| v["completed"].as_u64())
            .unwrap_or(0)
    };
    let start = Instant::now();
    while completed() < 3 && start.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(5));
    }
    task.kill().unwrap();
    task.wait().unwrap();
    let done = completed();
    assert!(
        (1..12).contains(&done),
        "killed after {done} frames: not mid-cache"
    );
    assert_eq!(json(&killed.join("shot/status.json"))["status"], "running");

    let rerun = batch(&list, &killed, &["--index", "0"]).output().unwrap();
    assert!(rerun.status.success(), "{rerun:?}");
    assert!(tracked_bytes(&whole.join("shot")) == tracked_bytes(&killed.join("shot")));
}

#[test]
fn bad_input_is_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    synth("merge", &tmp.path().join("a"), 24, 2);
    let list = tmp.path().join("caches.txt");
    let out = tmp.path().join("out");

    manifest(&list, &["a", "# again:", "./a/"]);
    let repeated = batch(&list, &out, &[]).output().unwrap();
    assert!(!repeated.status.success());
    let message = String::from_utf8_lossy(&repeated.stderr);
    assert!(
        message.contains(&format!("{}:3:", list.display())) && message.contains("line 1"),
        "{message}"
    );
    assert!(!out.exists());

    manifest(&list, &["a"]);
    let index = batch(&list, &out, &["--index", "1"]).output().unwrap();
    assert!(!index.status.success());
    assert!(String::from_utf8_lossy(&index.stderr).contains("index 1 is past its last cache"));
    let variable = batch(&list, &out, &[])
        .env("SLURM_ARRAY_TASK_ID", "first")
        .output()
        .unwrap();
    assert!(!variable.status.success());
    assert!(String::from_utf8_lossy(&variable.stderr).contains("SLURM_ARRAY_TASK_ID=first"));
    assert!(!out.exists());

    // A folder the batch did not make is someone's output: kept unless --force.
    std::fs::create_dir_all(out.join("a")).unwrap();
    std::fs::write(out.join("a/notes.txt"), "mine").unwrap();
    let foreign = batch(&list, &out, &[]).output().unwrap();
    assert!(!foreign.status.success());
    assert!(String::from_utf8_lossy(&foreign.stderr).contains("holds no batch status file"));
    assert!(!out.join("a/status.json").exists() && !out.join("batch.json").exists());
    assert!(batch(&list, &out, &["--force"]).status().unwrap().success());
    assert_eq!(
        std::fs::read_to_string(out.join("a/notes.txt")).unwrap(),
        "mine"
    );
}
