//! Each cache's own status file, `OUTROOT/NAME/status.json`: written when the cache starts and
//! again when it ends, by whichever task runs it, so tasks on different machines never write the
//! same file; `batch.json` is assembled from these. Its presence also marks the folder as the
//! batch's own, which a rerun may resume or start over without `--force`.

use super::BatchError;
use crate::io::atomic_write;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The status file's name inside a cache's folder.
pub const STATUS_FILE: &str = "status.json";
/// Version of the status file.
pub const STATUS_VERSION: u32 = 1;

/// Where a cache stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum State {
    /// No task has started it.
    Pending,
    /// A task is running it, or was stopped while it ran (a rerun resumes it).
    Running,
    Done,
    Failed,
}

impl State {
    pub fn label(self) -> &'static str {
        match self {
            State::Pending => "pending",
            State::Running => "running",
            State::Done => "done",
            State::Failed => "failed",
        }
    }
}

/// One cache's status; `R` is the caller's record of what was asked (parameters, follow-up
/// steps), compared on a rerun so a cache done with other settings is not taken as done.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CacheStatus<R> {
    pub version: u32,
    pub name: String,
    /// The manifest's line, from 1.
    pub line: usize,
    pub input: PathBuf,
    pub request: R,
    /// Named as in `batch.json`.
    #[serde(rename = "status")]
    pub state: State,
    pub error: Option<String>,
    /// Frames tracked.
    pub frames: usize,
    /// Wall-clock seconds of the run that last worked on the cache.
    pub seconds: f64,
    /// Mean share of each frame's vertices carried over from the previous frame.
    pub coherence: Option<f64>,
}

impl<R: Serialize + DeserializeOwned> CacheStatus<R> {
    pub fn path(dir: &Path) -> PathBuf {
        dir.join(STATUS_FILE)
    }

    /// The status in folder `dir`, `None` when it has none.
    pub fn read(dir: &Path) -> Result<Option<Self>, BatchError> {
        let path = Self::path(dir);
        let text = match std::fs::read_to_string(&path) {
            Ok(text) => text,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => {
                return Err(BatchError::Status {
                    path,
                    message: e.to_string(),
                });
            }
        };
        let status: Self = serde_json::from_str(&text).map_err(|e| BatchError::Status {
            path: path.clone(),
            message: format!("not a cache status: {e}"),
        })?;
        if status.version != STATUS_VERSION {
            return Err(BatchError::Status {
                path,
                message: format!("status version {} is not {STATUS_VERSION}", status.version),
            });
        }
        Ok(Some(status))
    }

    /// Writes the status into `dir` (created), atomically.
    pub fn write(&self, dir: &Path) -> Result<(), BatchError> {
        std::fs::create_dir_all(dir).map_err(|source| BatchError::Create {
            path: dir.to_path_buf(),
            source,
        })?;
        let json = serde_json::to_vec_pretty(self)?;
        atomic_write(&Self::path(dir), |f| f.write_all(&json))?;
        Ok(())
    }
}
