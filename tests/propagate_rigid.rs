//! The checkerboard carried forward on a tracked `rigid` sequence stays where the ground-truth
//! motion puts the material (issue bar: "the checker pattern on `rigid` stays where ground truth
//! says"): the real tracker, the real event lists, compared with the synth manifest.

use std::path::Path;
use std::process::Command;
use surftrack::eval::{EvalOptions, evaluate};
use surftrack::io::read_frame;
use surftrack::propagate::{
    Channel, DARK, Direction, LIGHT, PropagateOptions, TrackedSequence, propagate,
};
use surftrack::synth::{Scene, SynthOptions, write_sequence};

fn run(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_surftrack"))
        .args(args)
        .output()
        .expect("the surftrack binary runs");
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Where between the dark (0) and light (1) colour a carried colour lies.
fn lightness(c: &[f32]) -> f32 {
    let (num, den) = (0..3).fold((0.0, 0.0), |(n, d), i| {
        let span = LIGHT[i] - DARK[i];
        (n + (c[i] - DARK[i]) * span, d + span * span)
    });
    num / den
}

#[test]
fn the_checker_on_rigid_follows_the_ground_truth() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("rigid");
    let manifest = write_sequence(
        Scene::Rigid,
        &SynthOptions {
            resolution: 40,
            frames: 8,
        },
        &input,
        surftrack::io::Format::Ply,
        false,
    )
    .unwrap();
    let tracked = dir.path().join("tracked");
    let path = |p: &Path| p.to_str().unwrap().to_string();
    run(&[
        "track",
        &path(&input),
        "-o",
        &path(&tracked),
        "--quiet",
        "--backend",
        "cpu",
    ]);
    let carried = dir.path().join("carried");
    let options = PropagateOptions {
        direction: Direction::Forward,
        channels: vec![Channel::checker(5.0)],
        displace: None,
        ply: true,
        obj: false,
    };
    let summary = propagate(&tracked, &carried, &options, false).unwrap();
    let checker = summary.checker.unwrap();
    let delta = summary.start.mean_edge_length;
    let report = evaluate(
        &tracked,
        &EvalOptions {
            input: Some(input.clone()),
            ..EvalOptions::default()
        },
    )
    .unwrap();
    print!("{}", report.table());
    assert_eq!(report.frames.len(), 8);
    assert!(report.frames.iter().all(|f| f.drift.is_some()));
    let sequence = TrackedSequence::open(&tracked).unwrap();
    assert_eq!(sequence.len(), 8);
    let t0 = manifest.frames[0].truth.transform.unwrap();
    println!("frame  vertices  wrong colour %  blended %  farthest wrong vertex from a wall (Δ)");
    for k in 0..sequence.len() {
        let mesh = read_frame(&carried.join(format!("frame_{k:04}.ply")))
            .unwrap()
            .mesh;
        let tk = manifest.frames[k].truth.transform.unwrap();
        let colour = mesh.attributes.iter().find(|a| a.name == "color").unwrap();
        let (mut wrong, mut blended, mut farthest) = (0usize, 0usize, 0.0f32);
        for (p, c) in mesh.positions.iter().zip(colour.values.chunks_exact(3)) {
            let origin = t0.apply(tk.inverse_apply(*p));
            let l = lightness(c);
            if (0.02..0.98).contains(&l) {
                blended += 1;
            }
            // On a wall (up to rounding) either colour is right.
            let ambiguous = checker.wall_distance(origin) < 1e-4 * delta;
            if (l > 0.5) != checker.is_light(origin) && !ambiguous {
                wrong += 1;
                farthest = farthest.max(checker.wall_distance(origin) / delta);
            }
        }
        let n = mesh.positions.len() as f32;
        println!(
            "{k:>5} {:>9} {:>14.2} {:>10.2} {:>10.3}",
            mesh.positions.len(),
            100.0 * wrong as f32 / n,
            100.0 * blended as f32 / n,
            farthest
        );
        assert!(
            (wrong as f32) < 0.03 * n,
            "frame {k}: {wrong} of {n} vertices show the wrong colour"
        );
        assert!(
            farthest < 1.0,
            "frame {k}: a vertex {farthest} Δ inside a cell shows the other colour"
        );
    }
}
