use crate::io::IoError;
use crate::project::ProjectError;
use crate::propagate::PropagateError;
use std::path::PathBuf;
use thiserror::Error;

/// Why a tracked sequence could not be evaluated; each message names the file involved.
#[derive(Debug, Error)]
pub enum EvalError {
    #[error(transparent)]
    Tracked(#[from] PropagateError),
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("{}: no input sequence given, and track.json lists none", dir.display())]
    NoInput { dir: PathBuf },
    #[error("{tracked} tracked frames but only {input} input frames")]
    TooFewInputFrames { tracked: usize, input: usize },
    #[error("{}: cannot measure distances: {source}", path.display())]
    Distance { path: PathBuf, source: ProjectError },
    #[error("{}: no 3-component `color` channel to measure a checker on", path.display())]
    NoColour { path: PathBuf },
    #[error("{}: cannot draw the chart: {reason}", path.display())]
    Plot { path: PathBuf, reason: String },
    #[error("cannot write the JSON report: {0}")]
    Json(#[from] serde_json::Error),
}
