use crate::events::EventError;
use crate::io::IoError;
use crate::propagate::PropagateError;
use std::path::PathBuf;
use thiserror::Error;

/// Why a wave simulation could not run; each message names the file or the parameter involved.
#[derive(Debug, Error)]
pub enum WaveError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error(transparent)]
    Tracked(#[from] PropagateError),
    #[error("{}: {source}", path.display())]
    Events { path: PathBuf, source: EventError },
    #[error("{}: vertex {id} received no wave state from the event lists", path.display())]
    Uncovered { path: PathBuf, id: u64 },
    #[error("{what} must be finite and {bound}, got {value}")]
    Parameter {
        what: &'static str,
        bound: &'static str,
        value: f64,
    },
    #[error("a seed names frame {frame}, but the sequence has {frames} frames")]
    SeedFrame { frame: usize, frames: usize },
    #[error("cannot write the wave summary: {0}")]
    Json(#[from] serde_json::Error),
}
