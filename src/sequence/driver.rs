//! The frame loop of Algorithm 1 over a whole sequence: the first frame starts the tracker, every
//! later one steps it, the next frame's file is read while this one tracks, and each finished frame
//! is written (mesh, then events, then `track.json`, each atomically) before the next begins, so a
//! run killed at any moment resumes from its last complete frame with the same bytes.

use super::resume::written;
use super::state::STATE_VERSION;
use super::{FrameFormat, Layout, RunState, SequenceError, Summary, resume_point};
use crate::compute::Backend;
use crate::events::EventList;
use crate::events::file::encode;
use crate::io::{atomic_write, prepare_output_dir, read_frame, write_ply};
use crate::mesh::IndexedMesh;
use crate::track::{FrameLog, TrackOptions, Tracker};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::borrow::Cow;
use std::path::PathBuf;
use std::time::Instant;

/// Where the frames come from.
#[derive(Debug, Clone, Copy)]
pub enum FrameSource<'a> {
    /// Frame files, read one at a time (the next while the current one tracks).
    Files(&'a [PathBuf]),
    /// Frames already in memory (benchmarks, tests).
    Meshes(&'a [IndexedMesh]),
}

impl FrameSource<'_> {
    pub fn len(&self) -> usize {
        match self {
            FrameSource::Files(paths) => paths.len(),
            FrameSource::Meshes(meshes) => meshes.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn get(&self, k: usize) -> Result<Cow<'_, IndexedMesh>, SequenceError> {
        match self {
            FrameSource::Files(paths) => Ok(Cow::Owned(read_frame(&paths[k])?.mesh)),
            FrameSource::Meshes(meshes) => Ok(Cow::Borrowed(&meshes[k])),
        }
    }

    fn name(&self, k: usize) -> String {
        match self {
            FrameSource::Files(paths) => paths[k].display().to_string(),
            FrameSource::Meshes(_) => format!("frame {k}"),
        }
    }
}

/// How a run with an output folder begins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// A new run; `force` writes into an existing non-empty folder.
    Fresh { force: bool },
    /// Continue the run described by the folder's `track.json` from its last complete frame.
    Resume,
}

/// An output folder for a run; `params` is the caller's record of the method's parameters,
/// written to `track.json` and compared on resume.
#[derive(Debug, Clone)]
pub struct Output<'a, P> {
    pub layout: Layout,
    pub format: FrameFormat,
    pub params: &'a P,
    pub start: Start,
}

/// What the driver reports while it runs.
pub enum Progress<'a> {
    /// Frame `k` is being tracked; `done` frames are complete.
    Tracking { k: usize, done: usize },
    /// A frame that is not a closed 2-manifold is used as a target anyway (only its voxelization
    /// and projection are used).
    Warning(String),
    /// Frame `log.frame` is complete (and written, with an output folder).
    Frame {
        tracker: &'a Tracker,
        events: &'a EventList,
        log: &'a FrameLog,
    },
}

/// What a finished run did.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// Every frame's log, those of an interrupted run's first part included.
    pub frames: Vec<FrameLog>,
    pub edge_length: f32,
    pub seconds: f64,
}

/// Tracks `source` into `output` (when given), reporting to `progress`.
pub fn track_sequence<P>(
    source: FrameSource,
    backend: &Backend,
    options: &TrackOptions,
    output: Option<Output<P>>,
    mut progress: impl FnMut(Progress),
) -> Result<RunReport, SequenceError>
where
    P: Serialize + DeserializeOwned + PartialEq + Clone,
{
    let started = Instant::now();
    if source.is_empty() {
        return Err(SequenceError::Empty);
    }
    let input: Vec<PathBuf> = match source {
        FrameSource::Files(paths) => paths.to_vec(),
        FrameSource::Meshes(_) => Vec::new(),
    };
    let (mut tracker, mut state) = match &output {
        Some(o) if o.start == Start::Resume => {
            let point = resume_point(&o.layout, &input, o.format, &Some(o.params.clone()))?;
            for warning in point.warnings {
                progress(Progress::Warning(warning));
            }
            let state = point.state;
            let tracker = Tracker::resume(
                state.completed.saturating_sub(1),
                &point.mesh,
                state.next_id,
                state.edge_length,
                options,
            )?;
            (tracker, state)
        }
        _ => {
            if let Some(Output {
                layout,
                start: Start::Fresh { force },
                ..
            }) = &output
            {
                prepare_output_dir(layout.root(), *force)?;
            }
            let first = source.get(0)?;
            first
                .validate()
                .map_err(|source_error| SequenceError::InvalidFirst {
                    frame: source.name(0),
                    source: source_error,
                })?;
            let (tracker, events, log) = Tracker::start(&first, backend, options)?;
            let mut state = RunState {
                version: STATE_VERSION,
                input: input.clone(),
                format: output.as_ref().map_or(FrameFormat::Ply, |o| o.format),
                params: output.as_ref().map(|o| o.params.clone()),
                edge_length: tracker.edge_length(),
                completed: 0,
                next_id: 0,
                frames: Vec::new(),
                written: Vec::new(),
            };
            commit(output.as_ref(), &tracker, &events, log, &mut state)?;
            progress(Progress::Frame {
                tracker: &tracker,
                events: &events,
                log: state.frames.last().expect("frame 0 was just committed"),
            });
            (tracker, state)
        }
    };

    let mut next = (state.completed < source.len()).then(|| source.get(state.completed));
    for k in state.completed..source.len() {
        let target = next.take().expect("the frame was read ahead")?;
        if let Err(e) = target.validate() {
            progress(Progress::Warning(format!(
                "warning: {}: {e}; using it as a target anyway (only its voxelization and projection are used)",
                source.name(k)
            )));
        }
        progress(Progress::Tracking {
            k,
            done: state.completed,
        });
        let (stepped, read) = std::thread::scope(|scope| {
            let ahead = (k + 1 < source.len()).then(|| scope.spawn(|| source.get(k + 1)));
            let stepped = tracker.step(backend, k, &target);
            let read = ahead.map(|handle| match handle.join() {
                Ok(read) => read,
                Err(panic) => std::panic::resume_unwind(panic),
            });
            (stepped, read)
        });
        next = read;
        let (events, log) = stepped.map_err(|error| SequenceError::Frame {
            frame: source.name(k),
            source: error,
        })?;
        commit(output.as_ref(), &tracker, &events, log, &mut state)?;
        progress(Progress::Frame {
            tracker: &tracker,
            events: &events,
            log: state.frames.last().expect("the frame was just committed"),
        });
    }
    let seconds = started.elapsed().as_secs_f64();
    if let Some(o) = &output {
        let summary = Summary::of(
            &state.frames,
            seconds,
            backend.to_string(),
            state.edge_length,
        );
        let json = serde_json::to_vec_pretty(&summary)?;
        atomic_write(&o.layout.summary_path(), |f| f.write_all(&json))?;
    }
    Ok(RunReport {
        frames: state.frames,
        edge_length: state.edge_length,
        seconds,
    })
}

/// Records frame `state.completed` in `state` and, with an output folder, writes it (mesh, then events),
/// then advances `track.json`; each write is atomic, so a crash leaves either the old or the new
/// state, never a torn one.
fn commit<P: Serialize>(
    output: Option<&Output<P>>,
    tracker: &Tracker,
    events: &EventList,
    log: FrameLog,
    state: &mut RunState<Option<P>>,
) -> Result<(), SequenceError> {
    let k = state.completed;
    state.frames.push(log);
    state.completed = k + 1;
    state.next_id = tracker.mesh().next_id();
    let Some(w) = output else {
        return Ok(());
    };
    // The folders are made one level at a time: a root that vanished during the run (deleted,
    // or its disk unmounted) is reported rather than silently made again without the frames it held.
    let gone = || SequenceError::OutputGone {
        path: w.layout.root().to_path_buf(),
        completed: k,
    };
    if !w.layout.root().is_dir() || (k > 0 && !w.layout.state_path().is_file()) {
        return Err(gone());
    }
    for dir in [w.layout.frames_dir(), w.layout.events_dir()] {
        match std::fs::create_dir(&dir) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(gone()),
            Err(source) => return Err(SequenceError::Create { path: dir, source }),
        }
    }
    let mesh = tracker.mesh().to_indexed();
    let path = w.layout.frame_path(k, w.format);
    let bytes = encode(events);
    let mut write = || -> Result<(), SequenceError> {
        match w.format {
            FrameFormat::Ply => write_ply(&path, &mesh)?,
        }
        atomic_write(&w.layout.events_path(k), |f| f.write_all(&bytes))?;
        state
            .written
            .push(written(&path, bytes.len(), state.next_id)?);
        let json = serde_json::to_vec_pretty(state)?;
        atomic_write(&w.layout.state_path(), |f| f.write_all(&json))?;
        Ok(())
    };
    // A write that failed because the folder went away says so, not which file it was at.
    write().map_err(|e| if w.layout.root().is_dir() { e } else { gone() })
}
