use crate::io::IoError;
use std::path::PathBuf;
use thiserror::Error;

/// Why a batch could not be read, selected or reported; each names the file or variable involved.
#[derive(Debug, Error)]
pub enum BatchError {
    #[error("{}: cannot read the manifest: {source}", path.display())]
    ReadManifest {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{}:{line}: {message}", path.display())]
    ManifestLine {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{}: lists no cache", path.display())]
    EmptyManifest { path: PathBuf },
    #[error("{}: index {index} is past its last cache ({count} caches, indices from 0)", path.display())]
    Index {
        path: PathBuf,
        index: usize,
        count: usize,
    },
    #[error("{name}={value} is not a cache index (0, 1, 2, …)")]
    IndexVariable { name: &'static str, value: String },
    #[error("{}: {message}", path.display())]
    Status { path: PathBuf, message: String },
    #[error("cannot create {}: {source}", path.display())]
    Create {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(transparent)]
    Io(#[from] IoError),
    #[error("cannot write a batch status: {0}")]
    Json(#[from] serde_json::Error),
}
