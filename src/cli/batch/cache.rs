//! One cache of a batch: skipped when its status says it is done with the same request, else
//! tracked into `OUTROOT/NAME/` (resumed from its last complete frame when a run was stopped
//! there), then its follow-up steps; its status file records the start and the end, its error
//! included, so a failure stays with its cache and the other caches go on.

use super::progress::BatchProgress;
use crate::cli::CliError;
use crate::cli::track::{MethodParams, input_frames, track_into};
use crate::cli::{eval, propagate};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;
use surftrack::batch::{Cache, CacheStatus, Entry, STATUS_VERSION, State};
use surftrack::compute::Backend;
use surftrack::sequence::{FrameFormat, Layout, Progress, RunState, Start};

/// What every cache of a batch is asked: recorded in its status, and compared on a rerun, so a
/// cache done with other parameters or follow-ups is not taken as done.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct Request {
    pub params: MethodParams,
    pub propagate: Option<String>,
    pub eval: bool,
}

/// What a batch run shares between its caches.
pub(super) struct CacheRun<'a> {
    pub root: &'a Path,
    pub backend: &'a Backend,
    pub request: &'a Request,
    pub force: bool,
    pub progress: &'a BatchProgress,
}

/// How a cache ended in this run.
#[derive(Debug, Clone)]
pub(super) struct Outcome {
    pub status: CacheStatus<Request>,
}

impl Outcome {
    pub fn entry(&self) -> Entry {
        let s = &self.status;
        Entry {
            name: s.name.clone(),
            line: s.line,
            input: s.input.clone(),
            status: s.state,
            error: s.error.clone(),
            frames: s.frames,
            seconds: s.seconds,
            coherence: s.coherence,
        }
    }

    /// The error, when the cache failed.
    pub fn failure(&self) -> Option<&str> {
        match self.status.state {
            State::Failed => Some(self.status.error.as_deref().unwrap_or("failed")),
            _ => None,
        }
    }
}

/// What tracking a cache gave.
struct Tracked {
    frames: usize,
    coherence: Option<f64>,
}

impl CacheRun<'_> {
    /// Runs `cache` to its end, done or failed; a panic inside it is recorded as its failure.
    pub fn run(&self, cache: &Cache) -> Outcome {
        let dir = self.root.join(&cache.name);
        let started = Instant::now();
        let previous = CacheStatus::<Request>::read(&dir);
        if let Ok(Some(status)) = &previous
            && !self.force
            && status.state == State::Done
            && status.input == cache.input
            && status.request == *self.request
        {
            self.progress
                .line(format!("{}: done before, skipped", cache.name));
            self.progress.cache_finished();
            return Outcome {
                status: status.clone(),
            };
        }
        let mut status = CacheStatus {
            version: STATUS_VERSION,
            name: cache.name.clone(),
            line: cache.line,
            input: cache.input.clone(),
            request: self.request.clone(),
            state: State::Running,
            error: None,
            frames: 0,
            seconds: 0.0,
            coherence: None,
        };
        let result = previous
            .map_err(CliError::from)
            .and_then(|_| Ok(status.write(&dir)?))
            .and_then(|()| {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| self.track(cache, &dir)))
                    .unwrap_or_else(|panic| Err(CliError::Panic(panic_message(&panic))))
            });
        status.seconds = started.elapsed().as_secs_f64();
        match result {
            Ok(tracked) => {
                status.state = State::Done;
                status.frames = tracked.frames;
                status.coherence = tracked.coherence;
            }
            Err(e) => {
                status.state = State::Failed;
                status.error = Some(e.to_string());
                status.frames = completed_frames(&dir);
            }
        }
        if let Err(e) = status.write(&dir) {
            status.state = State::Failed;
            status.error = Some(e.to_string());
        }
        self.progress.line(match &status.error {
            None => format!(
                "{}: done, {} frames in {:.1} s",
                cache.name, status.frames, status.seconds
            ),
            Some(error) => format!("{}: failed: {error}", cache.name),
        });
        self.progress.cache_finished();
        Outcome { status }
    }

    /// Tracks `cache` into `dir`, then runs the follow-up steps.
    fn track(&self, cache: &Cache, dir: &Path) -> Result<Tracked, CliError> {
        let (frames, warnings) = input_frames(&cache.input, None)?;
        for warning in warnings {
            self.progress.line(format!("{}: {warning}", cache.name));
        }
        let start = if !self.force && Layout::new(dir).state_path().exists() {
            Start::Resume
        } else {
            // The folder is the batch's own (its status file was just written).
            Start::Fresh { force: true }
        };
        let bar = self.progress.cache(&cache.name, frames.len());
        let report = track_into(
            &frames,
            dir,
            FrameFormat::Ply,
            &self.request.params,
            start,
            self.backend,
            |progress| match progress {
                Progress::Tracking { k, done } => {
                    bar.set_position(done as u64);
                    bar.set_message(format!("{}: frame {k}", cache.name));
                }
                Progress::Warning(message) => {
                    self.progress.line(format!("{}: {message}", cache.name))
                }
                Progress::Frame { log, .. } => bar.set_position(log.frame as u64 + 1),
            },
        );
        bar.finish_and_clear();
        let report = report?;
        if let Some(text) = &self.request.propagate {
            propagate::propagate_tracked(&propagate::PropagateArgs::for_batch(dir, text)?)?;
        }
        if self.request.eval {
            eval::evaluate_tracked(dir)?;
        }
        let carried: Vec<f64> = report.frames.iter().filter_map(|f| f.carried).collect();
        Ok(Tracked {
            frames: report.frames.len(),
            coherence: (!carried.is_empty())
                .then(|| carried.iter().sum::<f64>() / carried.len() as f64),
        })
    }
}

/// Frames complete in `dir` (its `track.json`), for a cache that failed part-way.
fn completed_frames(dir: &Path) -> usize {
    std::fs::read_to_string(Layout::new(dir).state_path())
        .ok()
        .and_then(|text| serde_json::from_str::<RunState<serde_json::Value>>(&text).ok())
        .map_or(0, |state| state.completed)
}

fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string())
}
