//! `surftrack bench`: per-frame time of every stage of Algorithm 1 on a ~16k- and a ~100k-vertex
//! synthetic sequence, CPU and GPU paths side by side in one run (so the ratio is meaningful on a
//! shared machine), and the process's peak memory. `--input` times a real sequence instead;
//! `--resolution` chooses other sizes (up to production frames); `--json` prints the same figures
//! as one JSON document for scripts and dashboards.

use super::CliError;
use clap::Args;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Duration;
use surftrack::compute::{Backend, BackendChoice, kernel_time};
use surftrack::io::{discover_sequence, read_frame};
use surftrack::mesh::IndexedMesh;
use surftrack::sequence::{FrameSource, Progress, track_sequence};
use surftrack::synth::{Scene, SynthOptions, generate};
use surftrack::track::{StageTimes, TrackOptions};

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Scene to track (its resolution is chosen to give each size).
    #[arg(long, default_value = "blobs")]
    scene: Scene,
    /// Frames timed (the first initializes the tracker; the rest are timed).
    #[arg(long, default_value_t = 4)]
    frames: usize,
    /// Length of the synthetic sequence the timed frames open, which sets the motion per frame (a
    /// scene's whole motion spans its sequence: `blobs` turns once, so 32 frames turn 11.25° each,
    /// 4 frames 90°). The default is `surftrack synth`'s.
    #[arg(long, default_value_t = SynthOptions::default().frames)]
    sequence_frames: usize,
    /// Only the ~16k-vertex size.
    #[arg(long)]
    small_only: bool,
    /// Grid resolution of a synthetic size to time (repeat for several), instead of the scene's
    /// ~16k and ~100k sizes; `blobs` at 820 gives ~1M-vertex frames.
    #[arg(long = "resolution", value_name = "N")]
    resolutions: Vec<usize>,
    /// Time this sequence (directory or pattern, its first --frames frames) instead of the
    /// synthetic ones.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Time only this backend (cpu, gpu, or auto's choice); by default the CPU path and, where
    /// there is an adapter, the GPU path side by side.
    #[arg(long, value_enum)]
    backend: Option<BackendChoice>,
    /// Print the figures as one JSON document on stdout instead of the table.
    #[arg(long)]
    json: bool,
}

/// Mean time of each stage per timed frame of one sequence on one backend.
#[derive(Debug, Serialize)]
struct Row {
    sequence: String,
    vertices: usize,
    backend: String,
    frames_timed: usize,
    /// Share of the frame's time spent in the stages the GPU path runs as kernels (projection,
    /// closest points, triangle bounds, rasterization, sweeps, narrow-band distance, the fine
    /// stage's solve), on this backend (see `compute::kernel_time`). On the CPU path: the most of a frame a GPU can speed up.
    gpu_share: f64,
    /// Bytes uploaded to and read back from the device per timed frame (GPU path only).
    bytes_per_frame: Option<[u64; 2]>,
    ms_per_frame: StageTimes,
}

/// What `--json` prints.
#[derive(Debug, Serialize)]
struct Report {
    runs: Vec<Row>,
    /// Peak resident set size of the whole run (`VmHWM`), absent where the platform has none.
    peak_memory_mib: Option<f64>,
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
    let backends = match args.backend {
        Some(choice) => vec![Backend::select(choice)?],
        None => {
            let mut backends = vec![Backend::Cpu];
            match Backend::select(BackendChoice::Gpu) {
                Ok(gpu) => backends.push(gpu),
                Err(e) => eprintln!("GPU path not measured: {e}"),
            }
            backends
        }
    };
    if !args.json {
        println!(
            "{:<10} {:>8} {:<28} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>12}",
            "sequence",
            "verts",
            "backend",
            "register",
            "improve",
            "topo M",
            "topo T",
            "reconcile",
            "residual",
            "total",
            "gpu share",
            "MB up/down"
        );
    }
    let print = |row: &Row| {
        if !args.json {
            print_row(row);
        }
    };
    let frames = args.frames.max(2);
    let mut runs = Vec::new();
    if let Some(input) = &args.input {
        let (sequence, _) = discover_sequence(input)?.without_empty_ends()?;
        let meshes: Vec<IndexedMesh> = sequence
            .frames
            .iter()
            .take(frames)
            .map(|(_, path)| read_frame(path).map(|f| f.mesh))
            .collect::<Result<_, _>>()?;
        runs.extend(time(&sequence.pattern, &meshes, &backends, print)?);
    } else {
        let sizes = if !args.resolutions.is_empty() {
            &args.resolutions[..]
        } else if args.small_only {
            &resolutions(args.scene)[..1]
        } else {
            &resolutions(args.scene)[..]
        };
        for &resolution in sizes {
            let options = SynthOptions {
                resolution,
                frames: args.sequence_frames.max(frames),
            };
            let meshes: Vec<IndexedMesh> = generate(args.scene, &options)?
                .take(frames)
                .map(|f| f.map(|f| f.mesh))
                .collect::<Result<_, _>>()?;
            runs.extend(time(args.scene.name(), &meshes, &backends, print)?);
        }
    }
    let peak_memory_mib = peak_memory_mib();
    if args.json {
        let report = Report {
            runs,
            peak_memory_mib,
        };
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        match peak_memory_mib {
            Some(mib) => println!("peak memory (VmHWM): {mib:.0} MiB"),
            None => println!("peak memory: not available on this platform"),
        }
    }
    Ok(())
}

/// Tracks `frames` on each backend and gives the mean time of each stage per frame after the
/// first (the first only initializes the tracker), handing each row to `print` as it is done.
fn time(
    name: &str,
    frames: &[IndexedMesh],
    backends: &[Backend],
    print: impl Fn(&Row),
) -> Result<Vec<Row>, CliError> {
    let Some(first) = frames.first() else {
        return Ok(Vec::new());
    };
    let mut rows = Vec::new();
    for backend in backends {
        // The counters as the first (untimed) frame completes.
        let mut at_first = (Duration::ZERO, [0u64; 2]);
        let report = track_sequence::<()>(
            FrameSource::Meshes(frames),
            backend,
            &TrackOptions::default(),
            None,
            |progress| {
                if let Progress::Frame { log, .. } = progress
                    && log.frame == 0
                {
                    at_first = (kernel_time::total(), transferred(backend));
                }
            },
        )?;
        let kernels = (kernel_time::total() - at_first.0).as_secs_f64() * 1e3;
        let moved = transferred(backend);
        let mut sum = StageTimes::default();
        for log in report.frames.iter().skip(1) {
            let t = &log.times;
            sum.register += t.register;
            sum.register_fine += t.register_fine;
            sum.improve += t.improve;
            sum.topology_self += t.topology_self;
            sum.topology_target += t.topology_target;
            sum.reconcile += t.reconcile;
            sum.residual += t.residual;
            sum.total += t.total;
        }
        let timed = frames.len() - 1;
        let n = timed.max(1) as f64;
        let row = Row {
            sequence: name.to_string(),
            vertices: first.positions.len(),
            backend: backend.to_string(),
            frames_timed: timed,
            gpu_share: kernels / sum.total.max(f64::MIN_POSITIVE),
            bytes_per_frame: match backend {
                Backend::Cpu => None,
                Backend::Gpu(_) => {
                    Some([0, 1].map(|i| (moved[i] - at_first.1[i]) / timed.max(1) as u64))
                }
            },
            ms_per_frame: StageTimes {
                register: sum.register / n,
                register_fine: sum.register_fine / n,
                improve: sum.improve / n,
                topology_self: sum.topology_self / n,
                topology_target: sum.topology_target / n,
                reconcile: sum.reconcile / n,
                residual: sum.residual / n,
                total: sum.total / n,
            },
        };
        print(&row);
        rows.push(row);
    }
    Ok(rows)
}

fn print_row(row: &Row) {
    let t = &row.ms_per_frame;
    let moved = row.bytes_per_frame.map_or("-".to_string(), |[up, down]| {
        format!("{:.1}/{:.1}", up as f64 / 1e6, down as f64 / 1e6)
    });
    println!(
        "{:<10} {:>8} {:<28} {:>7.0}ms {:>7.0}ms {:>7.0}ms {:>7.0}ms {:>7.0}ms {:>7.0}ms {:>7.0}ms {:>9.2} {:>12}",
        row.sequence,
        row.vertices,
        row.backend,
        t.register,
        t.improve,
        t.topology_self,
        t.topology_target,
        t.reconcile,
        t.residual,
        t.total,
        row.gpu_share,
        moved
    );
}

/// Bytes moved host → device and back so far on `backend` (none on the CPU).
fn transferred(backend: &Backend) -> [u64; 2] {
    match backend {
        Backend::Cpu => [0, 0],
        Backend::Gpu(context) => context.transferred(),
    }
}

/// Peak resident set size of this process, from `/proc/self/status` (Linux).
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}
