//! `OUTROOT/batch.json` and the printed table, assembled from the caches' status files (a cache
//! without one is pending), so the report is the same whichever task or machine assembles it.

use super::{BatchError, CacheStatus, Manifest, State};
use crate::io::atomic_write;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The assembled report's file name under the output root.
pub const BATCH_FILE: &str = "batch.json";

/// One cache's line of the report.
#[derive(Debug, Clone, Serialize)]
pub struct Entry {
    pub name: String,
    pub line: usize,
    pub input: PathBuf,
    pub status: State,
    pub error: Option<String>,
    pub frames: usize,
    pub seconds: f64,
    pub coherence: Option<f64>,
}

/// Every cache of a manifest and where it stands.
#[derive(Debug, Clone, Serialize)]
pub struct BatchReport {
    pub manifest: PathBuf,
    pub done: usize,
    pub failed: usize,
    /// Caches pending or still running (or stopped while running).
    pub unfinished: usize,
    pub caches: Vec<Entry>,
}

impl BatchReport {
    /// Reads the status of every cache of `manifest` under `root`.
    pub fn assemble(manifest: &Manifest, root: &Path) -> Result<Self, BatchError> {
        let mut caches = Vec::with_capacity(manifest.caches.len());
        for cache in &manifest.caches {
            let status = CacheStatus::<serde_json::Value>::read(&root.join(&cache.name))?;
            caches.push(match status {
                Some(s) => Entry {
                    name: cache.name.clone(),
                    line: cache.line,
                    input: cache.input.clone(),
                    status: s.state,
                    error: s.error,
                    frames: s.frames,
                    seconds: s.seconds,
                    coherence: s.coherence,
                },
                None => Entry {
                    name: cache.name.clone(),
                    line: cache.line,
                    input: cache.input.clone(),
                    status: State::Pending,
                    error: None,
                    frames: 0,
                    seconds: 0.0,
                    coherence: None,
                },
            });
        }
        let count = |state: State| caches.iter().filter(|e| e.status == state).count();
        let (done, failed) = (count(State::Done), count(State::Failed));
        Ok(Self {
            manifest: manifest.path.clone(),
            done,
            failed,
            unfinished: caches.len() - done - failed,
            caches,
        })
    }

    /// Whether every cache is done.
    pub fn all_done(&self) -> bool {
        self.done == self.caches.len()
    }

    /// Writes `root/batch.json`, atomically.
    pub fn write(&self, root: &Path) -> Result<PathBuf, BatchError> {
        let path = root.join(BATCH_FILE);
        let json = serde_json::to_vec_pretty(self)?;
        atomic_write(&path, |f| f.write_all(&json))?;
        Ok(path)
    }

    /// The report as a text table, one cache per row, then the totals.
    pub fn table(&self) -> String {
        table(&self.caches)
            + &format!(
                "{} done, {} failed, {} unfinished of {} caches\n",
                self.done,
                self.failed,
                self.unfinished,
                self.caches.len()
            )
    }
}

/// `entries` as a text table; the error, when there is one, ends its row.
pub fn table(entries: &[Entry]) -> String {
    let width = entries
        .iter()
        .map(|e| e.name.len())
        .max()
        .unwrap_or(0)
        .max(5);
    let mut out = format!(
        "{:width$}  {:8}  {:>6}  {:>9}  {:>9}  error\n",
        "cache", "status", "frames", "seconds", "coherence"
    );
    for e in entries {
        let coherence = e
            .coherence
            .map_or("-".to_string(), |c| format!("{:.1}%", 100.0 * c));
        out += &format!(
            "{:width$}  {:8}  {:>6}  {:>9.1}  {:>9}  {}\n",
            e.name,
            e.status.label(),
            e.frames,
            e.seconds,
            coherence,
            e.error.as_deref().unwrap_or("")
        );
    }
    out
}
