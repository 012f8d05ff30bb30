use std::path::PathBuf;
use surftrack::io::IoError;
use surftrack::mesh::MeshError;
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
    #[error("cannot write the JSON summary: {0}")]
    Json(#[from] serde_json::Error),
}
