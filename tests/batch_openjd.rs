//! The shipped Open Job Description template (`docs/farm/surftrack-batch.openjd.yaml`) run locally
//! with `openjd run` (the `openjd-cli` package) on two small caches: one task per cache, then the
//! report, with the bytes a plain `surftrack batch` gives. Skipped with a message when `openjd`
//! is missing; a failure then under `SURFTRACK_REQUIRE_OPENJD=1`, which `.ci/run` sets.

mod batch_support;

use batch_support::{batch, json, manifest, synth, tracked_bytes};
use std::path::Path;
use std::process::Command;

fn openjd_available() -> bool {
    match Command::new("openjd").arg("--version").output() {
        Ok(out) if out.status.success() => true,
        _ if std::env::var("SURFTRACK_REQUIRE_OPENJD").as_deref() == Ok("1") => {
            panic!("openjd is missing and SURFTRACK_REQUIRE_OPENJD=1 (pip install openjd-cli)")
        }
        _ => {
            eprintln!("skipped: openjd is missing (pip install openjd-cli)");
            false
        }
    }
}

#[test]
fn the_openjd_template_tracks_one_cache_per_task_then_reports() {
    if !openjd_available() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    synth("merge", &tmp.path().join("shots/a"), 24, 3);
    synth("split", &tmp.path().join("shots/b"), 24, 3);
    let list = tmp.path().join("caches.txt");
    manifest(&list, &["shots/a", "shots/b"]);
    let out = tmp.path().join("farm");
    let template =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/farm/surftrack-batch.openjd.yaml");
    let param = |name: &str, value: &Path| format!("{name}={}", value.display());
    let run = Command::new("openjd")
        .arg("run")
        .arg(&template)
        .args(["-p", &param("Manifest", &list)])
        .args(["-p", &param("OutputRoot", &out)])
        .args(["-p", "Caches=0-1", "-p", "Backend=cpu"])
        .args([
            "-p",
            &param("Surftrack", Path::new(env!("CARGO_BIN_EXE_surftrack"))),
        ])
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{log}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        log.contains("Running step 'Track'") && log.contains("Running step 'Report'"),
        "{log}"
    );

    let report = json(&out.join("batch.json"));
    assert_eq!(report["done"], 2, "{report}");
    let local = tmp.path().join("local");
    assert!(
        batch(&list, &local, &["--quiet"])
            .status()
            .unwrap()
            .success()
    );
    for name in ["a", "b"] {
        assert_eq!(json(&out.join(name).join("summary.json"))["frames"], 3);
        assert!(
            tracked_bytes(&out.join(name)) == tracked_bytes(&local.join(name)),
            "{name}"
        );
    }
}
