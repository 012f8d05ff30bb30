use crate::apps::NoIds;
use crate::io::IoError;
use crate::propagate::PropagateError;
use std::path::PathBuf;
use thiserror::Error;

/// Why a tracked sequence could not be exported; each message names the file involved.
#[derive(Debug, Error)]
pub enum ExportError {
    #[error(transparent)]
    Io(#[from] IoError),
    #[error(transparent)]
    Tracked(#[from] PropagateError),
    #[error(transparent)]
    NoIds(#[from] NoIds),
    #[error("{}: exists; pass --force to replace it", path.display())]
    OutputExists { path: PathBuf },
    #[error("{}: unknown USD file extension (expected .usda, .usdc or .usd)", path.display())]
    UsdExtension { path: PathBuf },
    #[error("{}: cannot write USD: {reason}", path.display())]
    Usd { path: PathBuf, reason: String },
    #[error("{}: persistent id {id} does not fit the USD `id` primvar (int, at most 2147483647)", path.display())]
    IdRange { path: PathBuf, id: u64 },
    #[error("{}: vertex attribute '{name}' is not a USD primvar name (letters, digits and _, not starting with a digit)", path.display())]
    AttributeName { path: PathBuf, name: String },
    #[error("{}: does not match tracked frame {}: {reason}", path.display(), tracked.display())]
    FromMismatch {
        path: PathBuf,
        tracked: PathBuf,
        reason: String,
    },
    #[error("{}: the channels differ from the first frame's ({first}): {found}", path.display())]
    ChannelsChanged {
        path: PathBuf,
        first: String,
        found: String,
    },
    #[error("{what} must be finite and positive, got {value}")]
    Parameter { what: &'static str, value: f64 },
    #[error("nothing to write: give --usd FILE and/or --ply DIR")]
    NoOutput,
}
