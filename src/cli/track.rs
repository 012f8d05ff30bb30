//! `surftrack track INPUT -o OUT`: Algorithm 1 over a frame sequence, writing tracked frames, event
//! lists, a resumable `track.json` and a JSON summary (layout in `docs/output_layout.md`).

use super::CliError;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::Instant;
use surftrack::compute::{Backend, BackendChoice};
use surftrack::events::file::encode;
use surftrack::io::{
    ObjOptions, atomic_write, discover_sequence, prepare_output_dir, read_frame, write_obj,
    write_ply,
};
use surftrack::mesh::IndexedMesh;
use surftrack::register::FineOptions;
use surftrack::topology::subgrid::Fidelity;
use surftrack::track::{
    FrameLog, MAX_DISTANCE, Motion, TRACK_MAX_DEVIATION, TrackOptions, Tracker,
};

/// Version of `track.json`.
const STATE_VERSION: u32 = 1;
const STATE_FILE: &str = "track.json";

#[derive(Debug, Args)]
pub struct TrackArgs {
    /// Input frames: a directory, or a pattern like `fluid_####.bobj.gz` or `frame_*.ply`.
    pub input: PathBuf,
    /// Output directory.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Where correspondence projection runs: auto (a hardware GPU if there is one), cpu or gpu.
    #[arg(long, value_enum, default_value_t = BackendChoice::Auto)]
    pub backend: BackendChoice,
    /// Tracked frame format.
    #[arg(long, value_enum, default_value_t = MeshFormat::Ply)]
    pub format: MeshFormat,
    /// Continue an interrupted run in OUT from its last complete frame.
    #[arg(long)]
    pub resume: bool,
    /// Write into an existing non-empty output directory.
    #[arg(long, conflicts_with = "resume")]
    pub force: bool,
    /// No progress bar and no per-frame log lines.
    #[arg(long, short)]
    pub quiet: bool,
    /// Stop after this many frames of the input.
    #[arg(long)]
    pub frames: Option<usize>,
    #[command(flatten)]
    pub params: MethodParams,
}

/// The method's parameters with the paper's defaults; lengths in units of the target edge length L.
#[derive(Debug, Clone, Args, Serialize, Deserialize, PartialEq)]
pub struct MethodParams {
    /// Target edge length L (absolute units); default: the first frame's mean edge length.
    #[arg(long)]
    pub edge_length: Option<f32>,
    /// Topology grid spacing Δ in units of L (§4.3).
    #[arg(long, default_value_t = 1.0)]
    pub grid_factor: f32,
    /// Minimum interior angle, degrees (§4.1).
    #[arg(long, default_value_t = 10.0)]
    pub min_angle: f32,
    /// Minimum dihedral angle, degrees (§4.1).
    #[arg(long, default_value_t = 45.0)]
    pub min_dihedral: f32,
    /// Longest : shortest edge ratio (§4.1).
    #[arg(long, default_value_t = 4.0)]
    pub edge_ratio: f32,
    /// Largest distance, in units of L, one collapse or flip may move the surface (§4.1). Looser than
    /// a lone improvement's default: the next frame's registration fits the surface to its target
    /// again, and slivers left by topology patches need room to be removed.
    #[arg(long, default_value_t = TRACK_MAX_DEVIATION)]
    pub max_deviation: f32,
    /// Deformation-graph node spacing in units of L (§4.2).
    #[arg(long, default_value_t = 4.0)]
    pub node_spacing: f32,
    /// Correspondences whose normals differ by more than this many degrees are pruned (§4.2).
    #[arg(long, default_value_t = 60.0)]
    pub max_normal_angle: f32,
    /// α_fit of the coarse stage (§4.2).
    #[arg(long, default_value_t = 0.1)]
    pub alpha_fit: f64,
    /// Initial α_reg of the coarse stage, divided by 10 at each relaxation (§4.2).
    #[arg(long, default_value_t = 1000.0)]
    pub alpha_reg: f64,
    /// Fine-stage correspondence cut-off σ in units of L (§4.2).
    #[arg(long, default_value_t = 1.5)]
    pub sigma: f64,
    /// Weight of the fine stage's cover term, which lets target regions no source normal ray
    /// reaches pull their nearest source points (0: the paper's one-sided fit).
    #[arg(long, default_value_t = FineOptions::default().cover_weight)]
    #[serde(default = "without_cover")]
    pub cover_weight: f64,
    /// How the mesh follows each frame: `register` (the paper's §4.2) or `project` (each vertex to
    /// its closest point on the frame: the baseline of the paper's Fig. 9).
    #[arg(long, value_enum, default_value_t = MotionArg::Register)]
    pub motion: MotionArg,
    /// Only topology differences deeper than this many cells re-sample the mesh (§4.3).
    #[arg(long, default_value_t = 1)]
    pub depth: u32,
    /// Farthest, in units of L, the tracked surface may lie from the input after the topology
    /// steps: a component that does not come this close, or whose topology the grid cannot give
    /// it, is replaced by the input's own.
    #[arg(long, default_value_t = MAX_DISTANCE)]
    pub max_distance: f32,
    /// What the tracked mesh must match: `input` (every frame has the input's components and Euler
    /// characteristics within --max-distance; a component the grid cannot make so is replaced by
    /// the input's, and loses its coherence) or `grid` (the topology the grid resolves, paper §4.3;
    /// sheets, tunnels and bridges thinner than a cell may differ from the input's).
    #[arg(long, value_enum, default_value_t = FidelityArg::Input)]
    pub fidelity: FidelityArg,
}

/// `--fidelity`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum FidelityArg {
    Input,
    Grid,
}

/// The cover weight of a run recorded before the flag existed: it ran without the term, so
/// `--resume` asks for `--cover-weight 0` to continue it unchanged.
fn without_cover() -> f64 {
    0.0
}

/// `--motion`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum MotionArg {
    Register,
    Project,
}

impl MethodParams {
    fn options(&self) -> TrackOptions {
        let mut o = TrackOptions {
            edge_length: self.edge_length,
            grid_factor: self.grid_factor,
            ..TrackOptions::default()
        };
        o.improve.min_angle_degrees = self.min_angle;
        o.improve.min_dihedral_degrees = self.min_dihedral;
        o.improve.edge_ratio = self.edge_ratio;
        o.improve.max_deviation = self.max_deviation;
        o.register.graph.spacing = self.node_spacing;
        o.register.max_angle_degrees = self.max_normal_angle;
        o.register.coarse.alpha_fit = self.alpha_fit;
        o.register.coarse.alpha_reg_start = self.alpha_reg;
        o.register.fine.sigma = self.sigma;
        o.register.fine.cover_weight = self.cover_weight;
        o.topology.depth = self.depth;
        o.max_distance = self.max_distance;
        o.fidelity = match self.fidelity {
            FidelityArg::Input => Fidelity::Input,
            FidelityArg::Grid => Fidelity::Grid,
        };
        o.motion = match self.motion {
            MotionArg::Register => Motion::Register,
            MotionArg::Project => Motion::Project,
        };
        o
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum MeshFormat {
    Ply,
    Obj,
}

/// `track.json`: what was asked, and how far the run got (see `docs/output_layout.md`).
#[derive(Debug, Serialize, Deserialize)]
struct State {
    version: u32,
    input: Vec<PathBuf>,
    format: MeshFormat,
    params: MethodParams,
    edge_length: f32,
    completed: usize,
    next_id: u64,
    frames: Vec<FrameLog>,
}

/// The end-of-run summary.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    frames: usize,
    seconds: f64,
    backend: String,
    edge_length: f32,
    total_events: usize,
    topology_changes: usize,
    max_residual: f64,
    per_frame: &'a [FrameLog],
}

pub fn frame_path(out: &Path, k: usize, format: MeshFormat) -> PathBuf {
    let ext = match format {
        MeshFormat::Ply => "ply",
        MeshFormat::Obj => "obj",
    };
    out.join("frames").join(format!("frame_{k:04}.{ext}"))
}

pub fn events_path(out: &Path, k: usize) -> PathBuf {
    out.join("events").join(format!("{k:04}.events"))
}

pub fn run(args: &TrackArgs) -> Result<(), CliError> {
    let started = Instant::now();
    let sequence = discover_sequence(&args.input)?;
    for (from, to) in &sequence.gaps {
        eprintln!("warning: input frames {from}..={to} are missing; tracking across the gap");
    }
    let mut input: Vec<PathBuf> = sequence.frames.into_iter().map(|(_, p)| p).collect();
    if let Some(n) = args.frames {
        input.truncate(n);
    }
    let backend = Backend::select(args.backend)?;
    let options = args.params.options();
    let state_path = args.out.join(STATE_FILE);

    let (mut tracker, mut state) = if args.resume {
        resume(args, &state_path, &input, &options)?
    } else {
        prepare_output_dir(&args.out, args.force)?;
        let first = read_frame(&input[0])?.mesh;
        if let Err(e) = first.validate() {
            return Err(CliError::InvalidMesh {
                path: input[0].clone(),
                source: e,
            });
        }
        let (tracker, events, log) = Tracker::start(&first, &backend, &options)?;
        let mut state = State {
            version: STATE_VERSION,
            input: input.clone(),
            format: args.format,
            params: args.params.clone(),
            edge_length: tracker.edge_length(),
            completed: 0,
            next_id: 0,
            frames: Vec::new(),
        };
        let bar = progress_bar(input.len(), 0, true);
        commit_frame(
            &args.out, &tracker, &events, log, &mut state, &bar, args.quiet,
        )?;
        (tracker, state)
    };

    let bar = progress_bar(input.len(), state.completed, args.quiet);
    bar.set_draw_target(if args.quiet {
        ProgressDrawTarget::hidden()
    } else {
        ProgressDrawTarget::stderr()
    });
    for (k, path) in input.iter().enumerate().skip(state.completed) {
        bar.set_message(format!("frame {k}: reading"));
        let target = read_frame(path)?.mesh;
        if let Err(e) = target.validate() {
            bar.println(format!(
                "warning: {}: {e}; using it as a target anyway (only its voxelization and projection are used)",
                path.display()
            ));
        }
        bar.set_message(format!("frame {k}: tracking"));
        let (events, log) = tracker.step(&backend, k, &target)?;
        commit_frame(
            &args.out, &tracker, &events, log, &mut state, &bar, args.quiet,
        )?;
        bar.inc(1);
    }
    bar.finish_and_clear();

    let summary = Summary {
        frames: state.completed,
        seconds: started.elapsed().as_secs_f64(),
        backend: backend.to_string(),
        edge_length: state.edge_length,
        total_events: state
            .frames
            .iter()
            .map(|f| {
                let e = &f.events;
                e.split_edge + e.split_face + e.collapse + e.patch_created + e.patch_deleted
            })
            .sum(),
        topology_changes: state.frames.iter().filter(|f| f.topology_changed).count(),
        max_residual: state
            .frames
            .iter()
            .map(|f| f.residual_max)
            .fold(0.0, f64::max),
        per_frame: &state.frames,
    };
    let json = serde_json::to_vec_pretty(&summary)?;
    atomic_write(&args.out.join("summary.json"), |w| w.write_all(&json))?;
    if !args.quiet {
        println!(
            "tracked {} frames in {:.1} s on {} -> {} (summary.json)",
            summary.frames,
            summary.seconds,
            summary.backend,
            args.out.display()
        );
    }
    Ok(())
}

/// Reloads the last complete frame and checks the run is the same one.
fn resume(
    args: &TrackArgs,
    state_path: &Path,
    input: &[PathBuf],
    options: &TrackOptions,
) -> Result<(Tracker, State), CliError> {
    let bad = |message: String| CliError::Manifest {
        path: state_path.to_path_buf(),
        message,
    };
    let text = std::fs::read_to_string(state_path).map_err(|e| {
        bad(format!(
            "cannot resume: {e} (was the run started with -o {}?)",
            args.out.display()
        ))
    })?;
    let state: State =
        serde_json::from_str(&text).map_err(|e| bad(format!("not a track state: {e}")))?;
    if state.version != STATE_VERSION {
        return Err(bad(format!(
            "state version {} is not {STATE_VERSION}",
            state.version
        )));
    }
    if state.input != input || state.params != args.params || state.format != args.format {
        return Err(bad(
            "the input frames or parameters differ from the interrupted run's; resume with the same arguments".into(),
        ));
    }
    if state.completed == 0 {
        return Err(bad(
            "no frame was completed; start the run again without --resume".into(),
        ));
    }
    let last = frame_path(&args.out, state.completed - 1, state.format);
    let mesh = read_frame(&last)?.mesh;
    let tracker = Tracker::resume(&mesh, state.next_id, state.edge_length, options)?;
    Ok((tracker, state))
}

/// Writes frame `state.completed` (mesh, then events), then advances `track.json`; each write is
/// atomic, so a crash leaves either the old or the new state, never a torn one.
fn commit_frame(
    out: &Path,
    tracker: &Tracker,
    events: &surftrack::events::EventList,
    log: FrameLog,
    state: &mut State,
    bar: &ProgressBar,
    quiet: bool,
) -> Result<(), CliError> {
    let k = state.completed;
    for dir in [out.join("frames"), out.join("events")] {
        std::fs::create_dir_all(&dir).map_err(|source| CliError::Create {
            path: dir.clone(),
            source,
        })?;
    }
    let mesh: IndexedMesh = tracker.mesh().to_indexed();
    let path = frame_path(out, k, state.format);
    match state.format {
        MeshFormat::Ply => write_ply(&path, &mesh)?,
        MeshFormat::Obj => write_obj(&path, &mesh, &ObjOptions::default())?,
    }
    let bytes = encode(events);
    atomic_write(&events_path(out, k), |w| w.write_all(&bytes))?;
    if !quiet {
        bar.suspend(|| println!("{}", log_line(&log)));
    }
    state.frames.push(log);
    state.completed = k + 1;
    state.next_id = tracker.mesh().next_id();
    let json = serde_json::to_vec_pretty(state)?;
    atomic_write(&out.join(STATE_FILE), |w| w.write_all(&json))?;
    Ok(())
}

fn log_line(log: &FrameLog) -> String {
    let e = &log.events;
    let t = &log.times;
    let r = &log.reconciled;
    format!(
        "frame {:4}: {:7} verts | split {} face {} collapse {} patch +{} -{} | components +{} -{} replaced {} grafted {} | residual {:.3} L (max {:.2}){} | register {:.0} improve {:.0} topology {:.0}+{:.0} reconcile {:.0} total {:.0} ms",
        log.frame,
        log.vertices,
        e.split_edge,
        e.split_face,
        e.collapse,
        e.patch_created,
        e.patch_deleted,
        r.inserted,
        r.deleted,
        r.replaced,
        r.grafted,
        log.residual_mean,
        log.residual_max,
        if log.registration_converged {
            ""
        } else {
            " not converged"
        },
        t.register,
        t.improve,
        t.topology_self,
        t.topology_target,
        t.reconcile,
        t.total
    )
}

fn progress_bar(total: usize, done: usize, quiet: bool) -> ProgressBar {
    let bar = ProgressBar::new(total as u64);
    if quiet {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar.set_position(done as u64);
    if let Ok(style) =
        ProgressStyle::with_template("{bar:30} {pos}/{len} frames  {per_sec}  ETA {eta}  {msg}")
    {
        bar.set_style(style);
    }
    bar
}
