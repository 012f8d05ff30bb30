use crate::compute::ComputeError;
use crate::io::IoError;
use crate::propagate::PropagateError;
use std::path::PathBuf;
use thiserror::Error;

/// Why frames could not be rendered; each message names the file or the setting involved.
#[derive(Debug, Error)]
pub enum RenderError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error(transparent)]
    Compute(#[from] ComputeError),
    #[error(transparent)]
    Texture(#[from] PropagateError),
    #[error("{}: no frames to render (expected frame_0000.ply, … in it or in its frames/)", dir.display())]
    NoFrames { dir: PathBuf },
    #[error("{}: cannot read: {reason}", path.display())]
    Unreadable { path: PathBuf, reason: String },
    #[error("{}: no vertex attribute '{name}' of {components} component(s) to colour by (the file has: {available})", path.display())]
    MissingChannel {
        path: PathBuf,
        name: String,
        components: usize,
        available: String,
    },
    #[error("an image of {width} × {height} pixels is not possible here (1 to {limit} a side)")]
    Size { width: u32, height: u32, limit: u32 },
    #[error("reading the rendered image back failed: {0}")]
    Readback(String),
    #[error("{}: cannot encode the animation: {reason}", path.display())]
    Animation { path: PathBuf, reason: String },
}
