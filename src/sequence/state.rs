//! `track.json`: what a run was asked and how far it got, rewritten atomically after every frame,
//! so a killed run resumes from its last complete frame (`docs/output_layout.md`).

use super::{FrameFormat, SequenceError};
use crate::track::FrameLog;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Version of `track.json`.
pub const STATE_VERSION: u32 = 1;

/// The run description; `P` is the caller's record of the method's parameters, compared on resume.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunState<P> {
    pub version: u32,
    pub input: Vec<PathBuf>,
    pub format: FrameFormat,
    pub params: P,
    pub edge_length: f32,
    pub completed: usize,
    pub next_id: u64,
    pub frames: Vec<FrameLog>,
}

impl<P: DeserializeOwned + PartialEq> RunState<P> {
    /// The state at `path`, checked to describe the same run as `input`, `format` and `params`,
    /// with at least one complete frame.
    pub fn load_matching(
        path: &Path,
        input: &[PathBuf],
        format: FrameFormat,
        params: &P,
    ) -> Result<Self, SequenceError> {
        let bad = |message: String| SequenceError::State {
            path: path.to_path_buf(),
            message,
        };
        let text = std::fs::read_to_string(path).map_err(|e| {
            bad(format!(
                "cannot resume: {e} (was the run started with -o {}?)",
                path.parent().unwrap_or(path).display()
            ))
        })?;
        let state: Self =
            serde_json::from_str(&text).map_err(|e| bad(format!("not a track state: {e}")))?;
        if state.version != STATE_VERSION {
            return Err(bad(format!(
                "state version {} is not {STATE_VERSION}",
                state.version
            )));
        }
        if state.input != input || state.params != *params || state.format != format {
            return Err(bad(
                "the input frames or parameters differ from the interrupted run's; resume with the same arguments".into(),
            ));
        }
        if state.completed == 0 {
            return Err(bad(
                "no frame was completed; start the run again without --resume".into(),
            ));
        }
        Ok(state)
    }
}
