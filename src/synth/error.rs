use crate::grid::GridError;
use crate::io::IoError;
use thiserror::Error;

/// Why a synthetic sequence could not be generated or written.
#[derive(Debug, Error)]
pub enum SynthError {
    #[error("unknown scene {0:?}: expected one of blobs, merge, split, droplets, morph, rigid")]
    UnknownScene(String),
    #[error("resolution {got} is out of range: expected {min} to {max} cells across the scene")]
    Resolution { got: usize, min: usize, max: usize },
    #[error("frame count {got} is out of range: expected {min} to {max} frames")]
    Frames { got: usize, min: usize, max: usize },
    #[error(transparent)]
    Grid(#[from] GridError),
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("cannot encode the manifest: {0}")]
    Manifest(#[from] serde_json::Error),
}
