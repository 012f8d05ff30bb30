//! Numeric garbage in input frames, by the policy of docs/robustness.md: non-finite and far-flung
//! coordinates, empty frames and a first frame with a hole are refused naming the file; duplicate
//! vertices and zero-area faces are repaired and counted; a later frame with a hole is used as a
//! target with a warning naming it (or stops the run, naming it, where its own surface would have
//! to be copied in); a gap in the numbering is tracked across with a warning.
//! Nothing is written silently wrong: a refused frame stops the run before its output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn surftrack() -> Command {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
}

/// A four-frame OBJ sequence in `dir/in`.
fn sequence(dir: &Path) -> PathBuf {
    let input = dir.join("in");
    let status = surftrack()
        .args(["synth", "rigid", "-o"])
        .arg(&input)
        .args(["--resolution", "24", "--frames", "4", "--format", "obj"])
        .stdout(Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    std::fs::remove_file(input.join("manifest.json")).unwrap();
    input
}

fn frame(input: &Path, k: usize) -> PathBuf {
    input.join(format!("rigid_{k:04}.obj"))
}

fn track(input: &Path, out: &Path, extra: &[&str]) -> Output {
    surftrack()
        .arg("track")
        .arg(input)
        .arg("-o")
        .arg(out)
        .args(["--backend", "cpu", "--quiet"])
        .args(extra)
        .output()
        .unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The `v` and `f` lines of an OBJ frame.
fn parts(path: &Path) -> (Vec<String>, Vec<String>) {
    let text = std::fs::read_to_string(path).unwrap();
    let pick = |tag: &str| {
        text.lines()
            .filter(|l| l.starts_with(tag))
            .map(str::to_string)
            .collect()
    };
    (pick("v "), pick("f "))
}

fn write(path: &Path, vertices: &[String], faces: &[String]) {
    let mut text = vertices.join("\n");
    text.push('\n');
    text.push_str(&faces.join("\n"));
    text.push('\n');
    std::fs::write(path, text).unwrap();
}

/// Frame 2 edited by `edit`: the run stops at frame 2 with `reason`, naming the file, after
/// writing frames 0 and 1 only.
fn refused_at_frame_2(edit: impl FnOnce(&mut Vec<String>, &mut Vec<String>), reason: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let input = sequence(tmp.path());
    let path = frame(&input, 2);
    let (mut vertices, mut faces) = parts(&path);
    edit(&mut vertices, &mut faces);
    write(&path, &vertices, &faces);
    let out = tmp.path().join("out");
    let run = track(&input, &out, &[]);
    assert!(!run.status.success(), "{reason}: accepted");
    let message = stderr(&run);
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(reason), "{message}");
    assert!(out.join("frames/frame_0001.ply").is_file());
    assert!(!out.join("frames/frame_0002.ply").exists());
}

#[test]
fn non_finite_and_far_flung_coordinates_are_refused_naming_the_file() {
    for (value, reason) in [
        ("nan", "non-finite coordinate"),
        ("inf", "non-finite coordinate"),
        ("-inf", "non-finite coordinate"),
        ("1e30", "garbage coordinate"),
    ] {
        refused_at_frame_2(|vertices, _| vertices[5] = format!("v {value} 0 0"), reason);
    }
}

#[test]
fn empty_frames_and_frames_without_a_surface_are_refused() {
    refused_at_frame_2(
        |vertices, faces| {
            vertices.clear();
            faces.clear();
        },
        "file is empty",
    );
    refused_at_frame_2(|_, faces| faces.clear(), "no faces");
    refused_at_frame_2(
        |vertices, _| {
            let first = vertices[0].clone();
            for v in vertices.iter_mut() {
                v.clone_from(&first);
            }
        },
        "every face is degenerate",
    );
}

#[test]
fn duplicate_vertices_and_zero_area_faces_are_repaired_and_counted() {
    let tmp = tempfile::tempdir().unwrap();
    let input = sequence(tmp.path());
    // Frame 1 as a triangle soup (every face with its own three vertices), plus one face whose
    // corners are collinear.
    let path = frame(&input, 1);
    let (vertices, faces) = parts(&path);
    let mut soup = Vec::new();
    let mut soup_faces = Vec::new();
    for face in &faces {
        let corners: Vec<usize> = face
            .split_whitespace()
            .skip(1)
            .map(|c| c.split('/').next().unwrap().parse().unwrap())
            .collect();
        for &c in &corners {
            soup.push(vertices[c - 1].clone());
        }
        let n = soup.len();
        soup_faces.push(format!("f {} {} {}", n - 2, n - 1, n));
    }
    soup.extend(["v 0 0 0".to_string(), "v 1 0 0".into(), "v 2 0 0".into()]);
    let n = soup.len();
    soup_faces.push(format!("f {} {} {}", n - 2, n - 1, n));
    write(&path, &soup, &soup_faces);

    let inspect = surftrack()
        .arg("inspect")
        .arg("--json")
        .arg(&path)
        .output()
        .unwrap();
    assert!(inspect.status.success(), "{}", stderr(&inspect));
    let report: serde_json::Value = serde_json::from_slice(&inspect.stdout).unwrap();
    let welded = report[0]["welded_vertices"].as_u64().unwrap() as usize;
    assert_eq!(welded, 3 * faces.len() - vertices.len());
    assert_eq!(report[0]["dropped_faces"], 1);
    assert_eq!(
        report[0]["vertices"].as_u64().unwrap() as usize,
        vertices.len()
    );

    let run = track(&input, &tmp.path().join("out"), &[]);
    assert!(run.status.success(), "{}", stderr(&run));
}

#[test]
fn a_hole_is_refused_in_the_first_frame_and_named_in_a_later_one() {
    let tmp = tempfile::tempdir().unwrap();
    let input = sequence(tmp.path());
    for k in [0, 2] {
        let path = frame(&input, k);
        let (vertices, mut faces) = parts(&path);
        faces.pop();
        write(&path, &vertices, &faces);
    }
    let first = track(&input, &tmp.path().join("first"), &[]);
    assert!(!first.status.success());
    let message = stderr(&first);
    assert!(
        message.contains(&frame(&input, 0).display().to_string()),
        "{message}"
    );
    assert!(message.contains("not a closed 2-manifold"), "{message}");

    // Frame 2 (now the second frame) has the hole. With the default --fidelity input the tracker
    // would copy the input's own surface there, which it cannot: the run stops naming the file
    // before writing that frame. With --fidelity grid the frame is only a target, and the run
    // goes on with the warning.
    std::fs::remove_file(frame(&input, 0)).unwrap();
    let hole = frame(&input, 2).display().to_string();
    let out = tmp.path().join("input");
    let stopped = track(&input, &out, &[]);
    assert!(!stopped.status.success());
    let message = stderr(&stopped);
    assert!(
        message.contains(&format!("error: {hole}: frame 1")),
        "{message}"
    );
    assert!(message.contains("using it as a target anyway"), "{message}");
    assert!(out.join("frames/frame_0000.ply").is_file());
    assert!(!out.join("frames/frame_0001.ply").exists());

    let out = tmp.path().join("grid");
    let later = track(&input, &out, &["--fidelity", "grid"]);
    assert!(later.status.success(), "{}", stderr(&later));
    let warning = stderr(&later);
    assert!(warning.contains(&hole), "{warning}");
    assert!(warning.contains("using it as a target anyway"), "{warning}");
    for k in 0..3 {
        let tracked = surftrack::io::read_frame(&out.join(format!("frames/frame_{k:04}.ply")))
            .unwrap()
            .mesh;
        assert_eq!(tracked.validate(), Ok(()), "tracked frame {k}");
    }
}

#[test]
fn a_gap_in_the_numbering_is_tracked_across_with_a_warning() {
    let tmp = tempfile::tempdir().unwrap();
    let input = sequence(tmp.path());
    std::fs::remove_file(frame(&input, 2)).unwrap();
    let out = tmp.path().join("out");
    let run = track(&input, &out, &[]);
    assert!(run.status.success(), "{}", stderr(&run));
    let warning = stderr(&run);
    assert!(
        warning.contains("input frames 2..=2 are missing"),
        "{warning}"
    );
    let state: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("track.json")).unwrap()).unwrap();
    assert_eq!(state["completed"], 3);
    assert_eq!(state["input"][2], frame(&input, 3).display().to_string());
}
