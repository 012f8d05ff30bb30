//! `surftrack track INPUT -o OUT`: Algorithm 1 over a frame sequence, writing tracked frames, event
//! lists, a resumable `track.json` and a JSON summary (layout in `docs/output_layout.md`).

use super::CliError;
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use surftrack::compute::{Backend, BackendChoice};
use surftrack::io::discover_sequence;
use surftrack::register::{FineOptions, GraphOptions};
use surftrack::sequence::{
    FrameFormat, FrameSource, Layout, Output, Progress, RunReport, SUMMARY_FILE, Start,
    track_sequence,
};
use surftrack::topology::subgrid::Fidelity;
use surftrack::topology::{CONTINUE_WITHIN, Carry};
use surftrack::track::{FrameLog, MAX_DISTANCE, Motion, TRACK_MAX_DEVIATION, TrackOptions};

#[derive(Debug, Args)]
pub struct TrackArgs {
    /// Input frames: a directory, or a pattern like `fluid_####.bobj.gz` or `frame_*.ply`.
    pub input: PathBuf,
    /// Output directory.
    #[arg(short, long)]
    pub out: PathBuf,
    /// Where the data-parallel stages run (correspondence projection, closest points, and the
    /// topology grid's rasterization, sweeps and narrow-band distance): auto (a hardware GPU if
    /// there is one), cpu or gpu.
    #[arg(long, value_enum, default_value_t = BackendChoice::Auto)]
    pub backend: BackendChoice,
    /// Tracked frame format: ply. obj is refused, since OBJ cannot carry the persistent vertex ids
    /// that propagate, eval, export and --resume read; `propagate --format obj` writes OBJ.
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
    /// At most about this many graph nodes: finer frames space them wider, leaving the detail to
    /// the per-vertex stage (a two-level registration that keeps 1M-vertex frames tractable).
    #[arg(long, default_value_t = GraphOptions::default().max_nodes)]
    #[serde(default = "default_max_graph_nodes")]
    pub max_graph_nodes: usize,
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
    /// How much harder a cover pair pulls the farther its target sample lies from the mesh: its
    /// weight is multiplied by (distance / a quarter of L) to this power; 0 weighs every pair
    /// alike.
    #[arg(long, default_value_t = FineOptions::default().cover_growth)]
    #[serde(default)]
    pub cover_growth: f64,
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
    /// How a vertex that re-sampling creates or deletes takes its data from the surface at its
    /// closest point: `corner` (the value of the closest triangle's nearest corner, whole: a
    /// texture stays crisp where the same splash is re-sampled frame after frame) or `blend` (the
    /// corners' barycentric blend: exact for data linear over the surface, such as UVs, but a
    /// texture blurs across a triangle each time).
    #[arg(long, value_enum, default_value_t = TransferArg::Corner)]
    #[serde(default = "blended")]
    pub transfer: TransferArg,
    /// Where re-sampling puts a new vertex within this many grid spacings of the old vertex it
    /// takes its data from, the old vertex continues there with its id and data instead of ending;
    /// 0 gives every re-sampled vertex a new id.
    #[arg(long, default_value_t = CONTINUE_WITHIN)]
    #[serde(default)]
    pub continue_within: f32,
}

/// `--fidelity`.
/// What a run recorded before `--max-graph-nodes` existed resumes with the default.
fn default_max_graph_nodes() -> usize {
    GraphOptions::default().max_nodes
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum FidelityArg {
    Input,
    Grid,
}

/// `--transfer`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum TransferArg {
    Corner,
    Blend,
}

/// The transfer of a run recorded before the flag existed: its topology patches blended, so
/// `--resume` asks for `--transfer blend` to continue it alike.
fn blended() -> TransferArg {
    TransferArg::Blend
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
        o.register.graph.max_nodes = self.max_graph_nodes;
        o.register.max_angle_degrees = self.max_normal_angle;
        o.register.coarse.alpha_fit = self.alpha_fit;
        o.register.coarse.alpha_reg_start = self.alpha_reg;
        o.register.fine.sigma = self.sigma;
        o.register.fine.cover_weight = self.cover_weight;
        o.register.fine.cover_growth = self.cover_growth;
        o.topology.depth = self.depth;
        o.topology.carry = match self.transfer {
            TransferArg::Corner => Carry::Corner,
            TransferArg::Blend => Carry::Blend,
        };
        o.topology.continue_within = self.continue_within;
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

impl MeshFormat {
    /// The tracked frames' format. OBJ is refused: an OBJ run could be neither propagated,
    /// evaluated nor exported, and its resume would renumber every vertex.
    fn frame_format(self) -> Result<FrameFormat, CliError> {
        match self {
            MeshFormat::Ply => Ok(FrameFormat::Ply),
            MeshFormat::Obj => Err(CliError::ObjTracking),
        }
    }
}

pub fn run(args: &TrackArgs) -> Result<(), CliError> {
    // Checked before anything is read or written.
    let format = args.format.frame_format()?;
    let (input, warnings) = input_frames(&args.input, args.frames)?;
    for warning in warnings {
        eprintln!("{warning}");
    }
    let backend = Backend::select(args.backend)?;
    let start = if args.resume {
        Start::Resume
    } else {
        Start::Fresh { force: args.force }
    };
    let bar = progress_bar(input.len(), 0, args.quiet);
    let report = track_into(
        &input,
        &args.out,
        format,
        &args.params,
        start,
        &backend,
        |progress| match progress {
            Progress::Tracking { k, done } => {
                bar.set_position(done as u64);
                bar.set_message(format!("frame {k}: tracking"));
            }
            // Warnings are shown with --quiet too (a hidden bar would swallow its println).
            Progress::Warning(message) => bar.suspend(|| eprintln!("{message}")),
            Progress::Frame { log, .. } => {
                if !args.quiet {
                    bar.suspend(|| println!("{}", log_line(log)));
                }
                bar.set_position(log.frame as u64 + 1);
            }
        },
    )?;
    bar.finish_and_clear();
    if !args.quiet {
        println!(
            "tracked {} frames in {:.1} s on {} -> {} ({SUMMARY_FILE})",
            report.frames.len(),
            report.seconds,
            backend,
            args.out.display()
        );
    }
    Ok(())
}

/// The frames of `input` (a folder, a pattern or one file) in numeric order, at most `limit`,
/// without the empty frames at either end (an inflow's frames before the fluid appears), and a
/// warning for each gap in their numbers and for the empty ends left out.
pub(super) fn input_frames(
    input: &Path,
    limit: Option<usize>,
) -> Result<(Vec<PathBuf>, Vec<String>), CliError> {
    let (sequence, empty) = discover_sequence(input)?.without_empty_ends()?;
    let mut warnings: Vec<String> = sequence
        .gap_ranges()
        .iter()
        .map(|range| format!("warning: input frames {range} are missing; tracking across the gap"))
        .collect();
    if let (Some((from, to)), Some((first, path))) = (empty.leading, sequence.frames.first()) {
        warnings.push(format!(
            "warning: input frames {from}..={to} are empty (no fluid yet); tracking starts at frame {first} ({}), tracked frame 0",
            path.display()
        ));
    }
    if let (Some((from, to)), Some((last, _))) = (empty.trailing, sequence.frames.last()) {
        warnings.push(format!(
            "warning: input frames {from}..={to} are empty (the fluid is gone); tracking ends at frame {last}"
        ));
    }
    let mut frames: Vec<PathBuf> = sequence.frames.into_iter().map(|(_, p)| p).collect();
    if let Some(n) = limit {
        frames.truncate(n);
    }
    Ok((frames, warnings))
}

/// Tracks `frames` into the folder `out` with `params`: where `track` and `batch` hand a run to
/// the sequence driver.
pub(super) fn track_into(
    frames: &[PathBuf],
    out: &Path,
    format: FrameFormat,
    params: &MethodParams,
    start: Start,
    backend: &Backend,
    progress: impl FnMut(Progress),
) -> Result<RunReport, CliError> {
    let output = Output {
        layout: Layout::new(out),
        format,
        params,
        start,
    };
    Ok(track_sequence(
        FrameSource::Files(frames),
        backend,
        &params.options(),
        Some(output),
        progress,
    )?)
}

fn log_line(log: &FrameLog) -> String {
    let e = &log.events;
    let t = &log.times;
    let r = &log.reconciled;
    format!(
        "frame {:4}: {:7} verts{} | split {} face {} collapse {} merge {} patch +{} -{} | components +{} -{} replaced {} grafted {} | lost: improve {} topology {}+{} sub-grid {} | residual {:.3} L (max {:.2}){} | register {:.0} improve {:.0} topology {:.0}+{:.0} reconcile {:.0} total {:.0} ms",
        log.frame,
        log.vertices,
        log.carried
            .map(|c| format!(" ({:.1}% carried over)", 100.0 * c))
            .unwrap_or_default(),
        e.split_edge,
        e.split_face,
        e.collapse,
        e.merge,
        e.patch_created,
        e.patch_deleted,
        r.inserted,
        r.deleted,
        r.replaced,
        r.grafted,
        log.churn.improve.lost,
        log.churn.topology_self.lost,
        log.churn.topology_target.lost,
        log.churn.subgrid.lost,
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
