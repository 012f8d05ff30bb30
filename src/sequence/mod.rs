//! The sequence driver: Algorithm 1's frame loop over a whole sequence (`track::Tracker` does one
//! frame), with resume, read-ahead and the output layout. The CLI's `track`, `bench` and `demo`,
//! and the tests, all run sequences through [`track_sequence`].

mod driver;
mod layout;
mod orientation;
mod resume;
mod state;
mod summary;

pub use driver::{FrameSource, Output, Progress, RunReport, Start, track_sequence};
pub use layout::{
    EVENTS_DIR, FRAMES_DIR, FrameFormat, Layout, SUMMARY_FILE, TRACK_FILE, events_name,
    frame_file_name, frame_name, frame_number,
};
pub use resume::{ResumePoint, resume_point};
pub use state::{RunState, STATE_VERSION, Written};
pub use summary::Summary;

use crate::io::IoError;
use crate::mesh::MeshError;
use crate::track::TrackError;
use std::path::PathBuf;
use thiserror::Error;

/// Why a sequence run stopped; each names the file or frame involved.
#[derive(Debug, Error)]
pub enum SequenceError {
    #[error("the sequence has no frames")]
    Empty,
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("{frame}: not a closed 2-manifold: {source}")]
    InvalidFirst { frame: String, source: MeshError },
    #[error(transparent)]
    Track(#[from] TrackError),
    /// A step failed on this input frame (a file name, or `frame k` for frames in memory).
    #[error("{frame}: {source}")]
    Frame { frame: String, source: TrackError },
    #[error("{}: {message}", path.display())]
    State { path: PathBuf, message: String },
    #[error("cannot create {}: {source}", path.display())]
    Create {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: {reason}", path.display())]
    Damaged { path: PathBuf, reason: String },
    #[error("{}: the output folder disappeared during the run (frames {completed} and later were not written)", path.display())]
    OutputGone { path: PathBuf, completed: usize },
    #[error("cannot write the run description: {0}")]
    Json(#[from] serde_json::Error),
}
