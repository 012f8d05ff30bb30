//! `surftrack bench`: per-frame time of every stage of Algorithm 1 on a ~16k- and a ~100k-vertex
//! synthetic sequence, CPU and GPU paths side by side in one run (so the ratio is meaningful on a
//! shared machine), and the process's peak memory.

use super::CliError;
use clap::Args;
use surftrack::compute::{Backend, BackendChoice};
use surftrack::synth::{Scene, SynthOptions, generate};
use surftrack::track::{StageTimes, TrackOptions, Tracker};

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Scene to track (its resolution is chosen to give each size).
    #[arg(long, default_value = "blobs")]
    scene: Scene,
    /// Frames per sequence (the first initializes the tracker; the rest are timed).
    #[arg(long, default_value_t = 4)]
    frames: usize,
    /// Only the ~16k-vertex size.
    #[arg(long)]
    small_only: bool,
}

/// Grid resolutions giving about 16k and 100k vertices per frame for each scene.
fn resolutions(scene: Scene) -> [usize; 2] {
    match scene {
        Scene::Morph => [72, 180],
        Scene::Droplets | Scene::Rigid => [128, 320],
        Scene::Blobs | Scene::Merge | Scene::Split => [104, 260],
    }
}

pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    let mut backends = vec![Backend::Cpu];
    match Backend::select(BackendChoice::Gpu) {
        Ok(gpu) => backends.push(gpu),
        Err(e) => eprintln!("GPU path not measured: {e}"),
    }
    let sizes = if args.small_only {
        &resolutions(args.scene)[..1]
    } else {
        &resolutions(args.scene)[..]
    };
    println!(
        "{:<8} {:>8} {:<28} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}",
        "scene", "verts", "backend", "register", "improve", "topo M", "topo T", "residual", "total"
    );
    for &resolution in sizes {
        let options = SynthOptions {
            resolution,
            frames: args.frames.max(2),
        };
        let frames: Vec<_> = generate(args.scene, &options)?.collect::<Result<_, _>>()?;
        let vertices = frames[0].mesh.positions.len();
        for backend in &backends {
            let track = TrackOptions::default();
            let (mut tracker, _, _) = Tracker::start(&frames[0].mesh, backend, &track)?;
            let mut sum = StageTimes::default();
            for (k, frame) in frames.iter().enumerate().skip(1) {
                let (_, log) = tracker.step(backend, k, &frame.mesh)?;
                let t = log.times;
                sum.register += t.register;
                sum.improve += t.improve;
                sum.topology_self += t.topology_self;
                sum.topology_target += t.topology_target;
                sum.residual += t.residual;
                sum.total += t.total;
            }
            let n = (frames.len() - 1) as f64;
            println!(
                "{:<8} {:>8} {:<28} {:>8.0}ms {:>8.0}ms {:>8.0}ms {:>8.0}ms {:>8.0}ms {:>8.0}ms",
                args.scene.name(),
                vertices,
                backend.to_string(),
                sum.register / n,
                sum.improve / n,
                sum.topology_self / n,
                sum.topology_target / n,
                sum.residual / n,
                sum.total / n
            );
        }
    }
    match peak_memory_mib() {
        Some(mib) => println!("peak memory (VmHWM): {mib:.0} MiB"),
        None => println!("peak memory: not available on this platform"),
    }
    Ok(())
}

/// Peak resident set size of this process, from `/proc/self/status` (Linux).
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}
