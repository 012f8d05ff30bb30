//! Registers frames of one folder onto the next frames of another and prints, per pair, the work
//! the coarse stage did (iterations, factorizations, conjugate-gradient iterations), the final
//! coarse energy, the distances of the registered vertices to the target (in mean edge lengths of
//! the source) and the time, wall and process CPU; then the means. Frame `j − 1` of SOURCES is
//! registered onto frame `j` of TARGETS for `j` from FIRST to LAST by STEP; a frame is the file
//! whose name holds its 4-digit number. With SOURCES a tracked run's `frames/`, this is the
//! tracker's registration; with SOURCES = TARGETS, input frame onto input frame.
//!
//! `cargo run --release --example register_sweep -- runs/db/frames ../shared/data/dambreak_sph_warp 2 44 3`

use std::path::{Path, PathBuf};
use std::time::Instant;

use surftrack::compute::Backend;
use surftrack::io::read_frame;
use surftrack::mesh::Mesh;
use surftrack::project::{Bvh, closest_points};
use surftrack::register::{RegisterOptions, RegistrationReport, Target, register};

/// The file of frame `j` in `dir`: the one whose name holds its 4-digit number.
fn frame(dir: &Path, j: usize) -> Result<PathBuf, Box<dyn std::error::Error>> {
    let tag = format!("{j:04}.");
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)?
        .map(|entry| entry.map(|e| e.path()))
        .collect::<Result<_, _>>()?;
    names.sort();
    names
        .into_iter()
        .find(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.contains(&tag))
        })
        .ok_or_else(|| format!("no frame {j} in {}", dir.display()).into())
}

/// Process CPU time in seconds (user + system), from `/proc/self/stat`; 0 where there is none.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after_name = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<&str> = after_name.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

/// Iterations, factorizations and conjugate-gradient iterations of the coarse stage.
fn work(report: &RegistrationReport) -> (usize, usize, usize) {
    let iterations = report.coarse.stages.iter().flat_map(|s| &s.iterations);
    let factorizations = iterations.clone().map(|i| i.factorizations).sum();
    let cg = iterations.map(|i| i.cg_iterations).sum();
    (report.coarse.iterations(), factorizations, cg)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [sources, targets, first, last, step] = &args[..] else {
        return Err("usage: register_sweep SOURCES TARGETS FIRST LAST STEP".into());
    };
    let (first, last, step): (usize, usize, usize) = (first.parse()?, last.parse()?, step.parse()?);
    let mut sums = [0.0f64; 7];
    let mut worst = 0.0f64;
    let mut count = 0;
    for j in (first.max(1)..=last).step_by(step.max(1)) {
        let source = read_frame(&frame(Path::new(sources), j - 1)?)?.mesh;
        let target = read_frame(&frame(Path::new(targets), j)?)?.mesh;
        let unit = f64::from(source.mean_edge_length());
        let mut mesh = Mesh::from_indexed(&source)?;
        let bvh = Bvh::build(&target)?;
        let (t, c) = (Instant::now(), cpu_seconds());
        let report = register(
            &Backend::Cpu,
            &mut mesh,
            Target::Tree(&bvh),
            &RegisterOptions::default(),
        )?;
        let (wall, cpu) = (t.elapsed().as_secs_f64(), cpu_seconds() - c);
        let points: Vec<_> = mesh.vertices().map(|v| mesh.position(v)).collect();
        let nearest = closest_points(&Backend::Cpu, &bvh, &points, f32::INFINITY)?;
        let distances: Vec<f64> = nearest
            .iter()
            .map(|n| f64::from(n.distance.abs()) / unit)
            .collect();
        let mean = distances.iter().sum::<f64>() / distances.len().max(1) as f64;
        let max = distances.iter().fold(0.0f64, |m, &d| m.max(d));
        let (iterations, factorizations, cg) = work(&report);
        let energy = report
            .coarse
            .stages
            .last()
            .and_then(|s| s.iterations.last())
            .map_or(f64::NAN, |i| i.energy);
        println!(
            "{j:3}  {:6} vertices  its {iterations:3} fact {factorizations:3} cg {cg:4}  E {energy:9.3e}  converged {}  distance mean {mean:.4} max {max:.3}  coarse {:.3} s fine {:.3} s wall {wall:.3} s cpu {cpu:.2} s",
            report.vertices,
            report.converged(),
            report.coarse_time.as_secs_f64(),
            report.fine_time.as_secs_f64(),
        );
        let values = [
            iterations as f64,
            factorizations as f64,
            cg as f64,
            mean,
            report.coarse_time.as_secs_f64(),
            wall,
            cpu,
        ];
        for (s, v) in sums.iter_mut().zip(values) {
            *s += v;
        }
        worst = worst.max(max);
        count += 1;
    }
    let n = count.max(1) as f64;
    let [iterations, factorizations, cg, mean, coarse, wall, cpu] = sums.map(|s| s / n);
    println!(
        "mean of {count}: its {iterations:.1} fact {factorizations:.1} cg {cg:.1}  distance mean {mean:.4} (max {worst:.3})  coarse {coarse:.3} s wall {wall:.3} s cpu {cpu:.3} s"
    );
    Ok(())
}
