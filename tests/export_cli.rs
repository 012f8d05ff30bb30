//! `surftrack export` end to end: velocities of a tracked rigid motion against the analytic motion,
//! PLY frames that read back as the tracked frames plus velocities, carried channels, the refusals,
//! and Pixar's USD (`tests/export_usd_check.py`) reading the USD file.

mod propagate_support;

use glam::{Mat4, Vec3};
use propagate_support::{Ops, channel, ok, surftrack, write_sequence};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use surftrack::export::VELOCITY;
use surftrack::io::{ReadOptions, read_frame_with, write_ply};
use surftrack::mesh::{Attribute, IndexedMesh};
use surftrack::synth::Manifest;

const FPS: f32 = 24.0;

fn refused(output: &Output) -> String {
    assert!(!output.status.success(), "accepted");
    String::from_utf8_lossy(&output.stderr).into_owned()
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Frame `k` of a folder exactly as written (no repair, which could reorder vertices).
fn read(dir: &Path, k: usize) -> IndexedMesh {
    let options = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    read_frame_with(&dir.join(format!("frame_{k:04}.ply")), &options)
        .unwrap()
        .mesh
}

fn velocities(mesh: &IndexedMesh) -> Vec<Vec3> {
    channel(mesh, VELOCITY)
        .1
        .iter()
        .map(|v| Vec3::from_slice(v))
        .collect()
}

/// Issue 23 bar 2: a tracked rigid motion (synth rigid) has, frame by frame, the velocities of the
/// analytic motion of each vertex's material point (`T_{j±1} · T_j⁻¹`, by the same forward or
/// backward rule), within 1% (root mean square of the error over that of the velocity).
#[test]
fn rigid_motion_velocities_match_the_analytic_motion() {
    let tmp = tempfile::tempdir().unwrap();
    let (input, tracked, ply) = (
        tmp.path().join("in"),
        tmp.path().join("tracked"),
        tmp.path().join("ply"),
    );
    let frames = 8;
    ok(&surftrack(&[
        "synth",
        "rigid",
        "-o",
        path(&input),
        "--resolution",
        "40",
        "--frames",
        "8",
    ]));
    ok(&surftrack(&[
        "track",
        path(&input),
        "-o",
        path(&tracked),
        "--backend",
        "cpu",
        "--quiet",
    ]));
    ok(&surftrack(&["export", path(&tracked), "--ply", path(&ply)]));
    let manifest: Manifest =
        serde_json::from_slice(&std::fs::read(input.join("manifest.json")).unwrap()).unwrap();
    let motion: Vec<Mat4> = manifest
        .frames
        .iter()
        .map(|f| Mat4::from_cols_array_2d(&f.truth.transform.unwrap().matrix))
        .collect();
    let meshes: Vec<IndexedMesh> = (0..frames).map(|k| read(&ply, k)).collect();
    let lives = |k: usize, id: u64| meshes[k].ids.as_ref().unwrap().contains(&id);
    for (j, mesh) in meshes.iter().enumerate() {
        let (mut error, mut speed, mut moving) = (0.0f64, 0.0f64, 0);
        for ((p, v), &id) in mesh
            .positions
            .iter()
            .zip(velocities(mesh))
            .zip(mesh.ids.as_ref().unwrap())
        {
            let to = |k: usize| (motion[k] * motion[j].inverse()).transform_point3(*p);
            let truth = if j + 1 < frames && lives(j + 1, id) {
                (to(j + 1) - *p) * FPS
            } else if j > 0 && lives(j - 1, id) {
                (*p - to(j - 1)) * FPS
            } else {
                assert_eq!(v, Vec3::ZERO);
                continue;
            };
            error += f64::from((v - truth).length_squared());
            speed += f64::from(truth.length_squared());
            moving += 1;
        }
        let relative = (error / speed).sqrt();
        eprintln!("frame {j}: {moving} moving vertices, relative velocity error {relative:.4}");
        assert!(
            moving > mesh.positions.len() * 9 / 10,
            "frame {j}: {moving}"
        );
        assert!(relative < 0.01, "frame {j}: relative error {relative}");
    }
}

/// A hand-built tracked sequence (splits, flips, collapses: vertices come and go) with a
/// propagated checker and UVs.
fn tracked_with_channels(dir: &Path) -> (Vec<IndexedMesh>, PathBuf) {
    let frames = write_sequence(dir, 4, Ops::All, 40, 23);
    ok(&surftrack(&[
        "propagate",
        path(dir),
        "--forward",
        "--uv",
        "--projection",
        "planar-z",
    ]));
    (frames, dir.join("propagated"))
}

#[test]
fn ply_frames_read_back_as_the_tracked_frames_with_velocities_and_channels() {
    let tmp = tempfile::tempdir().unwrap();
    let (frames, propagated) = tracked_with_channels(tmp.path());
    let ply = tmp.path().join("ply");
    let stdout = ok(&surftrack(&[
        "export",
        path(tmp.path()),
        "--ply",
        path(&ply),
        "--from",
        path(&propagated),
    ]));
    assert!(stdout.contains("exported 4 frames"), "{stdout}");
    for (k, frame) in frames.iter().enumerate() {
        let exported = read(&ply, k);
        assert_eq!(exported.positions, frame.positions, "frame {k}");
        assert_eq!(exported.triangles, frame.triangles, "frame {k}");
        assert_eq!(exported.ids, frame.ids, "frame {k}");
        let carried = read(&propagated, k);
        for name in ["color", "uv"] {
            assert_eq!(channel(&exported, name).1, channel(&carried, name).1);
        }
        let ids = frame.ids.as_ref().unwrap();
        let next = frames.get(k + 1);
        for (v, (velocity, id)) in velocities(&exported).iter().zip(ids).enumerate() {
            let at = |m: &IndexedMesh| {
                let ids = m.ids.as_ref().unwrap();
                ids.iter().position(|i| i == id).map(|w| m.positions[w])
            };
            let p = frame.positions[v];
            let expected = match (
                next.and_then(at),
                k.checked_sub(1).and_then(|b| at(&frames[b])),
            ) {
                (Some(later), _) => (later - p) * FPS,
                (None, Some(earlier)) => (p - earlier) * FPS,
                (None, None) => Vec3::ZERO,
            };
            assert_eq!(*velocity, expected, "frame {k} id {id}");
        }
    }
}

#[test]
fn outputs_are_not_overwritten_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    write_sequence(tmp.path(), 2, Ops::Refine, 5, 3);
    for (name, starts) in [("out.usda", &b"#usda 1.0"[..]), ("out.usdc", b"PXR-USDC")] {
        let usd = tmp.path().join(name);
        std::fs::write(&usd, "keep").unwrap();
        let error = refused(&surftrack(&[
            "export",
            path(tmp.path()),
            "--usd",
            path(&usd),
        ]));
        assert!(error.contains(name) && error.contains("--force"), "{error}");
        assert_eq!(std::fs::read_to_string(&usd).unwrap(), "keep");
        ok(&surftrack(&[
            "export",
            path(tmp.path()),
            "--usd",
            path(&usd),
            "--force",
        ]));
        assert!(std::fs::read(&usd).unwrap().starts_with(starts), "{name}");
    }

    let ply = tmp.path().join("ply");
    std::fs::create_dir(&ply).unwrap();
    std::fs::write(ply.join("mine.txt"), "keep").unwrap();
    let error = refused(&surftrack(&[
        "export",
        path(tmp.path()),
        "--ply",
        path(&ply),
    ]));
    assert!(error.contains("--force"), "{error}");

    let abc = tmp.path().join("out.abc");
    let error = refused(&surftrack(&[
        "export",
        path(tmp.path()),
        "--usd",
        path(&abc),
    ]));
    assert!(
        error.contains("out.abc") && error.contains(".usdc"),
        "{error}"
    );
    assert!(!abc.exists());
}

/// Hidden files (a temporary output left behind) in `dir`.
fn hidden_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

#[test]
fn a_propagated_folder_of_another_sequence_is_refused_naming_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    write_sequence(&a, 2, Ops::All, 30, 1);
    let (_, propagated) = tracked_with_channels(&b);
    let out = tmp.path().join("out.usda");
    let error = refused(&surftrack(&[
        "export",
        path(&a),
        "--usd",
        path(&out),
        "--from",
        path(&propagated),
    ]));
    assert!(error.contains("frame_0001.ply"), "{error}");
    assert!(!out.exists());
}

/// A failure after frames have been streamed into the USD file leaves nothing: the file is
/// written beside its path under a hidden name and only renamed into place when complete.
#[test]
fn a_failure_midway_leaves_no_usd_file() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, propagated) = tracked_with_channels(tmp.path());
    let third = propagated.join("frame_0002.ply");
    let mut mesh = read(&propagated, 2);
    mesh.attributes.retain(|a| a.name != "uv");
    write_ply(&third, &mesh).unwrap();
    let out_dir = tmp.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    for name in ["out.usda", "out.usdc"] {
        let out = out_dir.join(name);
        let error = refused(&surftrack(&[
            "export",
            path(tmp.path()),
            "--usd",
            path(&out),
            "--from",
            path(&propagated),
        ]));
        assert!(
            error.contains("frame_0002.ply") && error.contains("channels differ"),
            "{error}"
        );
        assert!(!out.exists(), "{name}");
        assert!(
            hidden_files(&out_dir).is_empty(),
            "{:?}",
            hidden_files(&out_dir)
        );
    }
}

/// Issue 23 bar 3: OBJ cannot carry ids, so tracking to OBJ is refused before anything is written,
/// with a message that says where OBJ comes from instead.
#[test]
fn track_refuses_obj_up_front() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    ok(&surftrack(&[
        "synth",
        "rigid",
        "-o",
        path(&input),
        "--resolution",
        "24",
        "--frames",
        "2",
    ]));
    let out = tmp.path().join("out");
    let error = refused(&surftrack(&[
        "track",
        path(&input),
        "-o",
        path(&out),
        "--format",
        "obj",
    ]));
    assert!(error.contains("propagate TRACKED --format obj"), "{error}");
    assert!(!out.exists());
}

/// The propagated frames of `propagated` with a six-component `stress` channel added (a primvar
/// of `float[]` with elementSize 6), written to `dir`.
fn with_stress(propagated: &Path, dir: &Path, frames: usize) {
    std::fs::create_dir(dir).unwrap();
    for k in 0..frames {
        let mut mesh = read(propagated, k);
        let values = (0..mesh.positions.len() * 6)
            .map(|i| (i % 97) as f32 * 0.25 + k as f32)
            .collect();
        mesh.attributes.push(Attribute {
            name: "stress".into(),
            components: 6,
            values,
        });
        write_ply(&dir.join(format!("frame_{k:04}.ply")), &mesh).unwrap();
    }
}

/// Issue 23 bar 1 on a small sequence, for both file forms: Pixar's USD opens the export and
/// finds one time sample per frame, the PLY frames' counts, topology, positions and ids,
/// velocities by the definition, and the carried colours and UVs; the `.usda` and the `.usdc` of
/// the same export hold the same metadata and values. Skipped without python3 and `pxr` unless
/// SURFTRACK_REQUIRE_USD=1.
#[test]
fn pixar_usd_reads_the_export() {
    let has_pxr = Command::new("python3")
        .args(["-c", "import numpy, pxr.Usd"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !has_pxr {
        assert!(
            std::env::var_os("SURFTRACK_REQUIRE_USD").is_none(),
            "SURFTRACK_REQUIRE_USD is set but python3 with usd-core (pxr) and numpy is not available"
        );
        eprintln!("skipping: python3 with usd-core (pxr) is not available");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let (_, propagated) = tracked_with_channels(tmp.path());
    let channels = tmp.path().join("channels");
    with_stress(&propagated, &channels, 4);
    let ply = tmp.path().join("ply");
    let forms = ["out.usda", "out.usdc"].map(|name| tmp.path().join(name));
    for (i, usd) in forms.iter().enumerate() {
        let mut args = vec![
            "export",
            path(tmp.path()),
            "--usd",
            path(usd),
            "--from",
            path(&channels),
            "--fps",
            "30",
            "--up-axis",
            "z",
        ];
        if i == 0 {
            args.extend(["--ply", path(&ply)]);
        }
        ok(&surftrack(&args));
    }
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/export_usd_check.py");
    for (usd, other) in [(&forms[0], &forms[1]), (&forms[1], &forms[0])] {
        let check = Command::new("python3")
            .args([
                script,
                path(usd),
                path(&ply),
                "--fps",
                "30",
                "--up-axis",
                "Z",
            ])
            .args(["--expect-color", "--expect-st", "--same-as", path(other)])
            .output()
            .unwrap();
        let stdout = ok(&check);
        assert!(stdout.contains("OK: 4 frames"), "{stdout}");
        assert!(stdout.contains("SAME: 10 attributes"), "{stdout}");
        assert!(
            stdout.contains("same: primvars:stress (typeName float[], variability Sdf.VariabilityVarying, interpolation vertex, elementSize 6; 4 samples)"),
            "{stdout}"
        );
    }
}
