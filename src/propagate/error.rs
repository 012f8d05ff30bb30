use crate::events::EventError;
use crate::events::file::EventFileError;
use crate::io::IoError;
use crate::project::ProjectError;
use std::path::PathBuf;
use thiserror::Error;

/// Why per-vertex data could not be carried through a tracked sequence; each message names the file
/// or frame involved.
#[derive(Debug, Error)]
pub enum PropagateError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("{}: no tracked frames (expected frames/frame_0000.ply, … as `surftrack track` writes)", dir.display())]
    NoFrames { dir: PathBuf },
    #[error("{}: tracked frames must be numbered 0, 1, 2, …; frame {missing} is missing", dir.display())]
    FrameGap { dir: PathBuf, missing: usize },
    #[error("{}: cannot read: {reason}", path.display())]
    Unreadable { path: PathBuf, reason: String },
    #[error("{}: {source}", path.display())]
    EventFile {
        path: PathBuf,
        source: EventFileError,
    },
    #[error("{}: {source}", path.display())]
    Events { path: PathBuf, source: EventError },
    #[error("{}: the frame has no persistent `id` vertex property", path.display())]
    NoIds { path: PathBuf },
    #[error("{}: {what}", path.display())]
    Inconsistent { path: PathBuf, what: String },
    #[error("{}: no vertex attribute '{name}' (the file has: {available})", path.display())]
    NoAttribute {
        path: PathBuf,
        name: String,
        available: String,
    },
    #[error("{}: cannot transfer '{name}' onto the tracked frame: {source}", path.display())]
    Transfer {
        path: PathBuf,
        name: String,
        source: ProjectError,
    },
    #[error("{}: not a usable PNG image: {reason}", path.display())]
    Image { path: PathBuf, reason: String },
    #[error(
        "a blend needs the same channels on both ends: the first frame has [{first}], the last [{last}]"
    )]
    BlendChannels { first: String, last: String },
    #[error("channel '{name}' is given twice")]
    DuplicateChannel { name: String },
    #[error("displacement needs a channel of 1, 3 or 4 components; '{name}' has {components}")]
    DisplaceChannel { name: String, components: usize },
    #[error("displacement channel '{name}' is not among the propagated channels")]
    NoDisplaceChannel { name: String },
    #[error("{what} must be finite and positive, got {value}")]
    Parameter { what: &'static str, value: f32 },
    #[error("cannot write the propagation summary: {0}")]
    Json(#[from] serde_json::Error),
}
