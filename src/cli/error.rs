use std::path::PathBuf;
use surftrack::apps::waves::WaveError;
use surftrack::compute::ComputeError;
use surftrack::eval::EvalError;
use surftrack::export::ExportError;
use surftrack::io::IoError;
use surftrack::mesh::MeshError;
use surftrack::propagate::PropagateError;
use surftrack::render::RenderError;
use surftrack::synth::SynthError;
use thiserror::Error;

/// Everything a subcommand can fail with; each message names the file involved.
#[derive(Debug, Error)]
pub enum CliError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error(transparent)]
    Synth(#[from] SynthError),
    #[error("{}: not a closed 2-manifold: {source}", path.display())]
    InvalidMesh { path: PathBuf, source: MeshError },
    #[error("{failed} of {total} frames are not closed 2-manifolds (see above)")]
    InvalidFrames { failed: usize, total: usize },
    #[error("{}: {message}", path.display())]
    Manifest { path: PathBuf, message: String },
    #[error("{}: frame topology disagrees with the manifest in {count} frame(s) (see above)", path.display())]
    ManifestMismatch { path: PathBuf, count: usize },
    #[error(transparent)]
    Track(#[from] surftrack::track::TrackError),
    #[error(transparent)]
    Sequence(#[from] surftrack::sequence::SequenceError),
    #[error("cannot write the JSON summary: {0}")]
    Json(#[from] serde_json::Error),
    #[error(transparent)]
    Compute(#[from] ComputeError),
    #[error(transparent)]
    Propagate(#[from] PropagateError),
    #[error(transparent)]
    Eval(#[from] EvalError),
    #[error(transparent)]
    Export(#[from] ExportError),
    #[error(transparent)]
    Waves(#[from] WaveError),
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(
        "track writes PLY frames only: OBJ cannot carry the persistent vertex ids that propagate, eval, export and --resume read; write OBJ from the tracked frames with `surftrack propagate TRACKED --format obj`"
    )]
    ObjTracking,
    #[error("{failing} of {total} tracked frames fail the bars (see the table)")]
    EvalFailed { failing: usize, total: usize },
    #[error(transparent)]
    Batch(#[from] surftrack::batch::BatchError),
    #[error("{flag}: {message}")]
    FollowUpArgs { flag: &'static str, message: String },
    #[error("{}: exists and holds no batch status file ({}); move it away or use --force", path.display(), surftrack::batch::STATUS_FILE)]
    ForeignCacheFolder { path: PathBuf },
    #[error("cannot create {}: {source}", path.display())]
    CreateDir {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cache {name} failed: {error}")]
    CacheFailed { name: String, error: String },
    #[error("{failed} failed and {unfinished} unfinished of {total} caches (see the table and {})", report.display())]
    BatchUnfinished {
        failed: usize,
        unfinished: usize,
        total: usize,
        report: PathBuf,
    },
    #[error("panicked: {0}")]
    Panic(String),
}
