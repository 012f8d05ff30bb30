//! Faults of a long run (docs/robustness.md): SIGKILL at seeded moments, frame and event files cut
//! short before `--resume`, a full disk, a read-only or vanished output folder, an input frame that
//! disappears or changes after discovery. Every resumed run ends byte-identical to an
//! uninterrupted one, and nothing a run had written is lost.

mod track_support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};
use surftrack::compute::Backend;
use surftrack::fuzz::Rng;
use surftrack::io::discover_sequence;
use surftrack::sequence::{
    FrameFormat, FrameSource, Layout, Output as RunOutput, SequenceError, Start, track_sequence,
};
use surftrack::track::TrackOptions;
use track_support::{assert_same_files, completed, files, synth, track};

fn run(command: &mut Command) -> Output {
    command.output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The uninterrupted run every faulty one is compared with, and its duration.
fn reference(root: &Path, scene: &str, frames: &str) -> (PathBuf, PathBuf, Duration) {
    let input = root.join("in");
    synth(scene, &input, "32", frames);
    let whole = root.join("whole");
    let clock = Instant::now();
    let output = run(&mut track(&input, &whole, &[]));
    assert!(output.status.success(), "{}", stderr(&output));
    (input, whole, clock.elapsed())
}

#[test]
fn sigkill_at_twenty_seeded_moments_resumes_to_identical_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, whole, time) = reference(tmp.path(), "merge", "8");
    let out = tmp.path().join("killed");
    let mut rng = Rng::for_input(26, 0);
    let mut mid_run = 0;
    let mut progress = Vec::new();
    for _ in 0..20 {
        // A killed first frame leaves nothing to resume: that run starts again.
        let extra: &[&str] = if completed(&out) > 0 {
            &["--resume"]
        } else {
            &["--force"]
        };
        let mut child = track(&input, &out, extra)
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let moment = time.mul_f64(rng.below(1000) as f64 / 8000.0);
        std::thread::sleep(moment);
        if child.try_wait().unwrap().is_none() {
            mid_run += 1;
        }
        child.kill().unwrap();
        child.wait().unwrap();
        progress.push(completed(&out));
    }
    eprintln!("{mid_run} of 20 kills mid-run; frames complete after each: {progress:?}");
    assert!(mid_run >= 10, "only {mid_run} of 20 kills landed mid-run");
    let extra: &[&str] = if completed(&out) > 0 {
        &["--resume"]
    } else {
        &["--force"]
    };
    let last = run(&mut track(&input, &out, extra));
    assert!(last.status.success(), "{}", stderr(&last));
    assert_same_files(&whole, &out);
}

#[test]
fn a_frame_or_event_file_cut_short_is_found_and_resume_steps_back_to_it() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, whole, _) = reference(tmp.path(), "merge", "6");
    for (cut, back_to) in [("frames/frame_0005.ply", 5), ("events/0003.events", 3)] {
        let out = tmp.path().join(format!("cut{back_to}"));
        let copy = run(Command::new("cp").arg("-r").arg(&whole).arg(&out));
        assert!(copy.status.success());
        let path = out.join(cut);
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
        let resumed = run(&mut track(&input, &out, &["--resume"]));
        assert!(resumed.status.success(), "{}", stderr(&resumed));
        let warning = stderr(&resumed);
        assert!(warning.contains(cut), "{warning}");
        assert!(
            warning.contains(&format!("resuming from frame {back_to}")),
            "{warning}"
        );
        assert_eq!(completed(&out), 6);
        assert_same_files(&whole, &out);
    }
}

/// Runs `body` with a tmpfs of `size` mounted at `dir` (root only: elsewhere the test says so and
/// checks nothing, as no unprivileged way gives a real ENOSPC).
fn with_tmpfs(dir: &Path, options: &str, body: impl FnOnce()) -> bool {
    std::fs::create_dir_all(dir).unwrap();
    let mounted = Command::new("mount")
        .args(["-t", "tmpfs", "-o", options, "tmpfs"])
        .arg(dir)
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("skipped: cannot mount a tmpfs here (needs root)");
        return false;
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(body));
    let _ = Command::new("umount").arg(dir).status();
    if let Err(panic) = result {
        std::panic::resume_unwind(panic);
    }
    true
}

#[test]
fn a_full_disk_stops_the_run_cleanly_and_resume_finishes_it() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, whole, _) = reference(tmp.path(), "merge", "6");
    let total: u64 = files(&whole).iter().map(|(_, b)| b.len() as u64).sum();
    let disk = tmp.path().join("disk");
    with_tmpfs(&disk, &format!("size={}", total / 2), || {
        let out = disk.join("out");
        let full = run(&mut track(&input, &out, &[]));
        assert!(!full.status.success());
        let message = stderr(&full);
        assert!(message.contains("No space left on device"), "{message}");
        assert!(message.contains(&out.display().to_string()), "{message}");
        // What was written is whole: every complete frame is the uninterrupted run's, and no
        // temporary file is left.
        let done = completed(&out);
        assert!((1..6).contains(&done), "{done} frames on a half-size disk");
        eprintln!(
            "disk of {} bytes full after {done} of 6 frames: {message}",
            total / 2
        );
        // Files of the frame being written when the disk filled may be there too (each whole).
        let reference = files(&whole);
        let written = files(&out);
        for k in 0..done {
            for name in [
                format!("frames/frame_{k:04}.ply"),
                format!("events/{k:04}.events"),
            ] {
                assert!(written.iter().any(|(n, _)| *n == name), "{name} lost");
            }
        }
        for (name, bytes) in &written {
            let same = reference.iter().find(|(n, _)| n == name);
            assert!(same.is_some_and(|s| &s.1 == bytes), "{name} is not whole");
        }
        // Space freed (the disk grown), the run resumes to the same bytes.
        let grown = Command::new("mount")
            .args(["-o", &format!("remount,size={}", 4 * total)])
            .arg(&disk)
            .status()
            .unwrap();
        assert!(grown.success());
        let resumed = run(&mut track(&input, &out, &["--resume"]));
        assert!(resumed.status.success(), "{}", stderr(&resumed));
        assert_same_files(&whole, &out);
    });
}

#[test]
fn a_read_only_output_folder_is_refused_with_nothing_written() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    synth("rigid", &input, "24", "3");
    let out = tmp.path().join("readonly");
    let check = |out: &Path| {
        let refused = run(&mut track(&input, &out.join("run"), &[]));
        assert!(!refused.status.success());
        let message = stderr(&refused);
        assert!(message.contains(&out.display().to_string()), "{message}");
        assert!(
            message.contains("Read-only") || message.contains("Permission denied"),
            "{message}"
        );
        assert!(!out.join("run").exists());
    };
    let is_root = run(Command::new("id").arg("-u")).stdout == b"0\n";
    if is_root {
        with_tmpfs(&out, "ro,size=1m", || check(&out));
    } else {
        use std::os::unix::fs::PermissionsExt;
        std::fs::create_dir(&out).unwrap();
        std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o555)).unwrap();
        check(&out);
    }
}

#[test]
fn an_output_folder_deleted_mid_run_is_not_made_again() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    synth("merge", &input, "32", "12");
    let out = tmp.path().join("out");
    let child = track(&input, &out, &[])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while completed(&out) < 2 && start.elapsed() < Duration::from_secs(120) {
        std::thread::sleep(Duration::from_millis(2));
    }
    // The run may add a file while the folder is being removed: try until it is gone.
    while out.exists() {
        let _ = std::fs::remove_dir_all(&out);
    }
    let output = child.wait_with_output().unwrap();
    assert!(!output.status.success(), "the run carried on");
    let message = stderr(&output);
    assert!(message.contains(&out.display().to_string()), "{message}");
    assert!(message.contains("disappeared during the run"), "{message}");
    assert!(!out.exists(), "the output folder was made again");
}

#[test]
fn an_input_frame_that_vanishes_or_changes_after_discovery_stops_the_run_at_it() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    synth("merge", &input, "24", "6");
    let paths: Vec<PathBuf> = discover_sequence(&input)
        .unwrap()
        .frames
        .into_iter()
        .map(|(_, p)| p)
        .collect();
    let go = |out: &Path, start: Start| {
        let output = RunOutput {
            layout: Layout::new(out),
            format: FrameFormat::Ply,
            params: &26u32,
            start,
        };
        track_sequence(
            FrameSource::Files(&paths),
            &Backend::Cpu,
            &TrackOptions::default(),
            Some(output),
            |_| {},
        )
    };
    let whole = tmp.path().join("whole");
    go(&whole, Start::Fresh { force: false }).unwrap();

    let original = std::fs::read(&paths[3]).unwrap();
    for (case, damage) in [
        ("vanished", None),
        ("changed", Some(b"ply\nformat".to_vec())),
    ] {
        match &damage {
            None => std::fs::remove_file(&paths[3]).unwrap(),
            Some(bytes) => std::fs::write(&paths[3], bytes).unwrap(),
        }
        let out = tmp.path().join(case);
        let error = go(&out, Start::Fresh { force: false }).unwrap_err();
        assert!(matches!(error, SequenceError::Io(_)), "{case}: {error}");
        assert!(
            error.to_string().contains(&paths[3].display().to_string()),
            "{case}: {error}"
        );
        assert_eq!(completed(&out), 3, "{case}");
        std::fs::write(&paths[3], &original).unwrap();
        go(&out, Start::Resume).unwrap();
        assert_same_files(&whole, &out);
    }
}
