//! `eval` on sequences whose answers are known: identical frames, a rigidly moved box, counted
//! splits, a perfect track of a synth scene with ground truth, and broken inputs.

mod propagate_support;

use glam::Vec3;
use propagate_support::{Ops, surftrack, write_events, write_frame, write_sequence};
use std::collections::HashMap;
use std::path::Path;
use surftrack::eval::{EvalError, EvalOptions, evaluate};
use surftrack::events::EventList;
use surftrack::io::{Format, read_frame, write_ply};
use surftrack::mesh::IndexedMesh;
use surftrack::synth::{Scene, SynthOptions, write_sequence as synth_sequence};

/// Writes `meshes` as an input sequence (no ids) into `dir`.
fn write_input(dir: &Path, meshes: &[IndexedMesh]) {
    std::fs::create_dir_all(dir).unwrap();
    for (k, m) in meshes.iter().enumerate() {
        let mut m = m.clone();
        m.ids = None;
        m.attributes.clear();
        write_ply(&dir.join(format!("in_{k:04}.ply")), &m).unwrap();
    }
}

/// Writes `meshes` as a tracked sequence with no events (every vertex kept).
fn write_tracked(dir: &Path, meshes: &[IndexedMesh]) {
    for (k, m) in meshes.iter().enumerate() {
        let mut m = m.clone();
        if m.ids.is_none() {
            m.ids = Some((0..m.positions.len() as u64).collect());
        }
        write_frame(dir, k, &m);
        if k > 0 {
            write_events(dir, k, &EventList::new());
        }
    }
}

fn options(input: &Path) -> EvalOptions {
    EvalOptions {
        input: Some(input.to_path_buf()),
        ..EvalOptions::default()
    }
}

/// The surface of the box `[0, 1]³` as an `n × n` grid of squares per side, each cut in two,
/// oriented outwards.
fn grid_box(n: i32) -> IndexedMesh {
    let mut index: HashMap<[i32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for axis in 0..3 {
        for side in [0, n] {
            let (i, j) = ((axis + 1) % 3, (axis + 2) % 3);
            for u in 0..n {
                for v in 0..n {
                    let mut corner = |du: i32, dv: i32| {
                        let mut c = [0; 3];
                        c[axis] = side;
                        c[i] = u + du;
                        c[j] = v + dv;
                        *index.entry(c).or_insert_with(|| {
                            positions.push(Vec3::from_array(c.map(|x| x as f32 / n as f32)));
                            positions.len() as u32 - 1
                        })
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                    // (i, j, axis) is right-handed, so (0,0)→(1,0)→(1,1) faces +axis.
                    if side == n {
                        triangles.extend([[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
                    } else {
                        triangles.extend([[q[0], q[2], q[1]], [q[0], q[3], q[2]]]);
                    }
                }
            }
        }
    }
    IndexedMesh::new(positions, triangles)
}

#[test]
fn identical_frames_are_at_distance_zero_and_fully_coherent() {
    let dir = tempfile::tempdir().unwrap();
    let sphere = IndexedMesh::icosphere(Vec3::new(1.0, 2.0, 3.0), 0.5, 2);
    let frames = vec![sphere.clone(), sphere.clone(), sphere];
    write_input(&dir.path().join("in"), &frames);
    write_tracked(dir.path(), &frames);
    let report = evaluate(dir.path(), &options(&dir.path().join("in"))).unwrap();
    assert_eq!(report.frames.len(), 3);
    for f in &report.frames {
        assert!(f.hausdorff < 1e-5 && f.mean_distance < 1e-6, "{f:?}");
        assert_eq!(f.defect, None);
        assert_eq!((f.components, f.euler), (f.input_components, f.input_euler));
        assert_eq!((f.components, f.euler), (1, 2));
        assert_eq!(f.quality.above_threshold, 1.0);
        assert_eq!(
            f.quality.min_angle_histogram.iter().sum::<usize>(),
            f.triangles
        );
        assert_eq!(f.coherence, (f.frame > 0).then_some(1.0));
        assert_eq!(f.drift, None);
    }
    assert!(report.summary.failing_frames.is_empty());
    assert_eq!(report.summary.mean_coherence, Some(1.0));
    assert!(report.table().contains("every frame is closed"));
}

#[test]
fn a_moved_box_is_exactly_as_far_as_it_moved() {
    let dir = tempfile::tempdir().unwrap();
    let input = grid_box(6);
    input.validate().unwrap();
    let shift = 0.04;
    let mut tracked = input.clone();
    tracked.positions.iter_mut().for_each(|p| p.x += shift);
    write_input(&dir.path().join("in"), std::slice::from_ref(&input));
    write_tracked(dir.path(), &[tracked]);
    let report = evaluate(dir.path(), &options(&dir.path().join("in"))).unwrap();
    let f = &report.frames[0];
    let delta = input.mean_edge_length();
    assert!((f.delta - delta).abs() < 1e-6);
    for d in [f.hausdorff, f.tracked_to_input, f.input_to_tracked] {
        assert!((d * delta - shift).abs() < 1e-5, "{f:?}");
    }
    assert!(f.mean_distance > 0.0 && f.mean_distance < f.hausdorff);
    assert!(f.hausdorff < 1.0 && report.summary.failing_frames.is_empty());
}

#[test]
fn coherence_is_the_fraction_of_vertices_carried_over() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 4, Ops::Refine, 40, 13);
    write_input(&dir.path().join("in"), &frames);
    let report = evaluate(dir.path(), &options(&dir.path().join("in"))).unwrap();
    for k in 1..4 {
        let want = frames[k - 1].positions.len() as f64 / frames[k].positions.len() as f64;
        assert_eq!(report.frames[k].coherence, Some(want));
        assert!(report.frames[k].hausdorff < 1e-5);
    }
    let mean = report.summary.mean_coherence.unwrap();
    assert!(mean < 1.0 && mean > 0.9);

    let frames = write_sequence(&dir.path().join("all"), 3, Ops::All, 40, 14);
    write_input(&dir.path().join("all_in"), &frames);
    let report = evaluate(
        &dir.path().join("all"),
        &options(&dir.path().join("all_in")),
    )
    .unwrap();
    for k in 1..3 {
        let previous: Vec<u64> = frames[k - 1].ids.clone().unwrap();
        let ids = frames[k].ids.as_ref().unwrap();
        let kept = ids.iter().filter(|id| previous.contains(id)).count();
        assert_eq!(
            report.frames[k].coherence,
            Some(kept as f64 / ids.len() as f64)
        );
    }
}

#[test]
fn drift_against_the_ground_truth_of_a_synth_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("rigid");
    let manifest = synth_sequence(
        Scene::Rigid,
        &SynthOptions {
            resolution: 24,
            frames: 3,
        },
        &input,
        Format::Ply,
        false,
    )
    .unwrap();
    let transforms: Vec<_> = manifest
        .frames
        .iter()
        .map(|f| f.truth.transform.unwrap())
        .collect();
    let first = read_frame(&input.join(&manifest.frames[0].file))
        .unwrap()
        .mesh;
    let diagonal = surftrack::propagate::Bounds::of(&first.positions)
        .unwrap()
        .diagonal();
    let mut tracked: Vec<IndexedMesh> = transforms
        .iter()
        .map(|t| {
            let mut m = first.clone();
            m.positions
                .iter_mut()
                .for_each(|p| *p = t.apply(transforms[0].inverse_apply(*p)));
            m
        })
        .collect();
    write_tracked(&dir.path().join("perfect"), &tracked);
    let report = evaluate(&dir.path().join("perfect"), &options(&input)).unwrap();
    assert_eq!(report.manifest, Some(input.join("manifest.json")));
    for f in &report.frames {
        let d = f.drift.unwrap();
        assert!(d.max_percent < 1e-3, "{d:?}");
        assert_eq!(d.survivors, 1.0);
        assert!(f.hausdorff < 1.0, "frame {}: {}", f.frame, f.hausdorff);
    }

    tracked[2]
        .positions
        .iter_mut()
        .for_each(|p| p.z += 0.01 * diagonal);
    write_tracked(&dir.path().join("off"), &tracked);
    let report = evaluate(&dir.path().join("off"), &options(&input)).unwrap();
    let last = report.summary.final_drift.unwrap();
    assert!((last.mean_percent - 1.0).abs() < 1e-3 && (last.max_percent - 1.0).abs() < 1e-3);
    assert!(
        report
            .table()
            .contains("drift from ground truth: last frame 1.000% mean")
    );
}

#[test]
fn mismatched_topology_and_missing_input_are_reported() {
    let dir = tempfile::tempdir().unwrap();
    let one = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 2);
    let mut two = one.clone();
    let n = one.positions.len() as u32;
    two.positions
        .extend(one.positions.iter().map(|p| *p + Vec3::new(3.0, 0.0, 0.0)));
    two.triangles
        .extend(one.triangles.iter().map(|t| t.map(|v| v + n)));
    write_input(&dir.path().join("in"), &[one.clone(), one]);
    write_tracked(dir.path(), &[two.clone(), two]);
    let report = evaluate(dir.path(), &options(&dir.path().join("in"))).unwrap();
    assert_eq!(report.summary.topology_mismatches, 2);
    assert_eq!(report.summary.failing_frames, vec![0, 1]);
    assert!(report.table().contains("topology unlike the input's"));
    assert_eq!(
        (
            report.frames[0].components,
            report.frames[0].input_components
        ),
        (2, 1)
    );
    assert_eq!(
        (report.frames[0].euler, report.frames[0].input_euler),
        (4, 2)
    );

    std::fs::remove_file(dir.path().join("in/in_0001.ply")).unwrap();
    let err = evaluate(dir.path(), &options(&dir.path().join("in"))).unwrap_err();
    assert!(
        matches!(
            err,
            EvalError::TooFewInputFrames {
                tracked: 2,
                input: 1
            }
        ),
        "{err}"
    );
    let err = evaluate(dir.path(), &EvalOptions::default()).unwrap_err();
    assert!(matches!(err, EvalError::NoInput { .. }), "{err}");
}

#[test]
fn the_command_prints_a_table_and_writes_json() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 3, Ops::All, 30, 1);
    let input = dir.path().join("in");
    write_input(&input, &frames);
    let inputs: Vec<String> = (0..3)
        .map(|k| input.join(format!("in_{k:04}.ply")).display().to_string())
        .collect();
    std::fs::write(
        dir.path().join("track.json"),
        serde_json::json!({ "version": 1, "completed": 3, "input": inputs }).to_string(),
    )
    .unwrap();
    let tracked = dir.path().to_str().unwrap();
    let out = surftrack(&["eval", tracked]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("haus Δ") && stdout.contains("coher%"),
        "{stdout}"
    );
    assert_eq!(
        stdout.lines().filter(|l| l.ends_with("  ok")).count(),
        3,
        "{stdout}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("eval.json")).unwrap()).unwrap();
    assert_eq!(json["frames"].as_array().unwrap().len(), 3);
    assert_eq!(json["summary"]["frames"], 3);

    let out = surftrack(&[
        "eval",
        tracked,
        "--json",
        "-",
        "--min-angle",
        "89",
        "--strict",
    ]);
    assert!(!out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        json["summary"]["failing_frames"].as_array().unwrap().len(),
        3
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("3 of 3 tracked frames fail"));
}

#[test]
fn the_pure_share_counts_the_colours_still_on_the_checker() {
    let mut mesh = grid_box(2);
    let n = mesh.positions.len();
    let (light, dark) = (surftrack::propagate::LIGHT, surftrack::propagate::DARK);
    let mut values = Vec::with_capacity(3 * n);
    for v in 0..n {
        let colour = match v % 4 {
            0 | 1 => light,
            2 => dark,
            // Halfway between the two: a smear.
            _ => [0, 1, 2].map(|c| 0.5 * (light[c] + dark[c])),
        };
        values.extend(colour);
    }
    mesh.attributes.push(surftrack::mesh::Attribute {
        name: "color".into(),
        components: 3,
        values,
    });
    let expected = (0..n).filter(|v| v % 4 != 3).count() as f64 / n as f64;
    assert_eq!(surftrack::eval::pure_share(&mesh), Some(expected));
    mesh.attributes.clear();
    assert_eq!(surftrack::eval::pure_share(&mesh), None);
}

#[test]
fn eval_measures_a_propagated_checker_per_frame() {
    let dir = tempfile::tempdir().unwrap();
    let frames = write_sequence(dir.path(), 3, Ops::All, 30, 1);
    let input = dir.path().join("in");
    write_input(&input, &frames);
    let tracked = dir.path().to_str().unwrap();
    let carried = dir.path().join("carried");
    let out = surftrack(&[
        "propagate",
        tracked,
        "--forward",
        "--checker",
        "-o",
        carried.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = surftrack(&[
        "eval",
        tracked,
        "--input",
        input.to_str().unwrap(),
        "--checker",
        carried.to_str().unwrap(),
        "--json",
        "-",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pure: Vec<f64> = json["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["checker_pure"].as_f64().unwrap())
        .collect();
    assert_eq!(pure.len(), 3);
    assert_eq!(pure[0], 1.0, "the start frame is coloured exactly");
    assert!(pure.iter().all(|p| (0.0..=1.0).contains(p)), "{pure:?}");
    assert_eq!(
        json["summary"]["final_checker_pure"].as_f64(),
        Some(pure[2])
    );
}
