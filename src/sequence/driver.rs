//! The frame loop of Algorithm 1 over a whole sequence: the first frame starts the tracker, every
//! later one steps it, the next frame's file is read and made ready for its step (`TargetFrame`:
//! its tree built) while this one tracks, and each finished frame is written (mesh, then events,
//! then `track.json`, each atomically) before the next begins, so a run killed at any moment
//! resumes from its last complete frame with the same bytes.

use super::orientation::{Turned, outward};
use super::resume::written;
use super::state::{STATE_VERSION, Written};
use super::{FrameFormat, Layout, RunState, SequenceError, Summary, resume_point};
use crate::compute::Backend;
use crate::events::EventList;
use crate::events::file::encode;
use crate::io::{atomic_write, prepare_output_dir, read_frame, write_ply};
use crate::mesh::{IndexedMesh, MeshError};
use crate::track::{FrameLog, TargetFrame, TrackOptions, Tracker};
use glam::Vec3;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::borrow::Cow;
use std::path::PathBuf;
use std::time::Instant;

/// A frame read ahead: made ready for its step (see `TargetFrame`), with what was turned to face
/// outward and why it is no closed 2-manifold, if it is none.
struct Ready {
    target: TargetFrame,
    turned: Turned,
    invalid: Option<MeshError>,
}

impl Ready {
    /// Frame `k` of `source` for a tracker anchored at `anchor`.
    fn of(source: &FrameSource, k: usize, anchor: Vec3) -> Result<Self, SequenceError> {
        let (mesh, turned) = source.get(k)?;
        let invalid = mesh.validate().err();
        let target =
            TargetFrame::new(k, mesh.into_owned(), anchor).map_err(|e| SequenceError::Frame {
                frame: source.name(k),
                source: e,
            })?;
        Ok(Self {
            target,
            turned,
            invalid,
        })
    }
}

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

    /// Frame `k`, made to face outward (see `orientation`), with what was turned.
    fn get(&self, k: usize) -> Result<(Cow<'_, IndexedMesh>, Turned), SequenceError> {
        let frame = match self {
            FrameSource::Files(paths) => Cow::Owned(read_frame(&paths[k])?.mesh),
            FrameSource::Meshes(meshes) => Cow::Borrowed(&meshes[k]),
        };
        Ok(outward(frame))
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
    /// and projection are used), or one facing inward is tracked turned.
    Warning(String),
    /// Frame `log.frame` is complete; with an output folder its files are written while the next
    /// frame tracks (a resume finds them through `track.json`).
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

/// Tracks `source` into `output` (when given), reporting to `progress`. While a frame tracks, the
/// next one is read and the previous one's files are written on other threads, so frame I/O stays
/// off the critical path; a run that stops on an error still writes every frame it tracked.
pub fn track_sequence<P>(
    source: FrameSource,
    backend: &Backend,
    options: &TrackOptions,
    output: Option<Output<P>>,
    mut progress: impl FnMut(Progress),
) -> Result<RunReport, SequenceError>
where
    P: Serialize + DeserializeOwned + PartialEq + Clone + Send + Sync,
{
    let started = Instant::now();
    if source.is_empty() {
        return Err(SequenceError::Empty);
    }
    // An inward-facing frame is reported once: a cache made so is usually made so throughout.
    let mut warned = false;
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
                (state.edge_length, glam::Vec3::from(state.anchor)),
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
            let (first, turned) = source.get(0)?;
            if turned.any() {
                progress(Progress::Warning(turned.warning(&source.name(0))));
                warned = true;
            }
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
                anchor: tracker.anchor().to_array(),
                completed: 0,
                next_id: 0,
                frames: Vec::new(),
                written: Vec::new(),
            };
            if let Some(write) = record(output.as_ref(), &tracker, &events, log, &mut state) {
                state.written.push(write.run()?);
            }
            progress(Progress::Frame {
                tracker: &tracker,
                events: &events,
                log: state.frames.last().expect("frame 0 was just committed"),
            });
            (tracker, state)
        }
    };

    let anchor = tracker.anchor();
    let ready = |k: usize| Ready::of(&source, k, anchor);
    let mut next = (state.completed < source.len()).then(|| ready(state.completed));
    // The previous frame's files, written while this frame tracks.
    let mut pending: Option<FrameWrite<P>> = None;
    for k in state.completed..source.len() {
        let current = match next.take().expect("the frame was read ahead") {
            Ok(current) => current,
            Err(error) => {
                // The frames tracked before an unreadable or unusable one are written all the same.
                if let Some(write) = pending.take() {
                    state.written.push(write.run()?);
                }
                return Err(error);
            }
        };
        if current.turned.any() && !warned {
            progress(Progress::Warning(current.turned.warning(&source.name(k))));
            warned = true;
        }
        if let Some(e) = current.invalid {
            progress(Progress::Warning(format!(
                "warning: {}: {e}; using it as a target anyway (only its voxelization and projection are used)",
                source.name(k)
            )));
        }
        let target = current.target;
        progress(Progress::Tracking {
            k,
            done: state.completed,
        });
        let (stepped, read, wrote) = std::thread::scope(|scope| {
            let ahead = (k + 1 < source.len()).then(|| scope.spawn(|| ready(k + 1)));
            let writing = pending.take().map(|write| scope.spawn(move || write.run()));
            let stepped = tracker.step(backend, k, &target);
            let read = ahead.map(join);
            let wrote = writing.map(join);
            (stepped, read, wrote)
        });
        // The earlier frame's failure is reported first: its files are what a resume starts from.
        if let Some(wrote) = wrote {
            state.written.push(wrote?);
        }
        next = read;
        let (events, log) = stepped.map_err(|error| SequenceError::Frame {
            frame: source.name(k),
            source: error,
        })?;
        pending = record(output.as_ref(), &tracker, &events, log, &mut state);
        progress(Progress::Frame {
            tracker: &tracker,
            events: &events,
            log: state.frames.last().expect("the frame was just committed"),
        });
    }
    if let Some(write) = pending {
        state.written.push(write.run()?);
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

/// The result of a scoped thread, its panic passed on.
fn join<T>(handle: std::thread::ScopedJoinHandle<'_, T>) -> T {
    match handle.join() {
        Ok(value) => value,
        Err(panic) => std::panic::resume_unwind(panic),
    }
}

/// Records frame `state.completed` in `state`; with an output folder, returns the writing of its
/// files, which the driver runs while the next frame tracks (off the critical path).
fn record<'o, P: Clone>(
    output: Option<&'o Output<'o, P>>,
    tracker: &Tracker,
    events: &EventList,
    log: FrameLog,
    state: &mut RunState<Option<P>>,
) -> Option<FrameWrite<'o, P>> {
    let k = state.completed;
    state.frames.push(log);
    state.completed = k + 1;
    state.next_id = tracker.mesh().next_id();
    output.map(|output| FrameWrite {
        output,
        k,
        mesh: tracker.world_mesh(),
        events: encode(events),
        state: state.clone(),
    })
}

/// Frame `k`'s files: its mesh, its encoded event list, and the run state `track.json` holds once
/// they are written (without this frame's [`Written`] yet, which writing them adds).
struct FrameWrite<'o, P> {
    output: &'o Output<'o, P>,
    k: usize,
    mesh: IndexedMesh,
    events: Vec<u8>,
    state: RunState<Option<P>>,
}

impl<P: Serialize> FrameWrite<'_, P> {
    /// Writes the mesh, then the event list, then advances `track.json`; each write is atomic, so
    /// a crash leaves either the old or the new state, never a torn one. Returns what the frame
    /// left on disk.
    fn run(mut self) -> Result<Written, SequenceError> {
        let (w, k) = (self.output, self.k);
        // The folders are made one level at a time: a root that vanished during the run (deleted,
        // or its disk unmounted) is reported rather than silently made again without the frames
        // it held.
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
        let path = w.layout.frame_path(k, w.format);
        let mut write = || -> Result<Written, SequenceError> {
            match w.format {
                FrameFormat::Ply => write_ply(&path, &self.mesh)?,
            }
            atomic_write(&w.layout.events_path(k), |f| f.write_all(&self.events))?;
            let done = written(&path, self.events.len(), self.state.next_id)?;
            self.state.written.push(done);
            let json = serde_json::to_vec_pretty(&self.state)?;
            atomic_write(&w.layout.state_path(), |f| f.write_all(&json))?;
            Ok(done)
        };
        // A write that failed because the folder went away says so, not which file it was at.
        write().map_err(|e| if w.layout.root().is_dir() { e } else { gone() })
    }
}
