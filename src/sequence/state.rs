//! `track.json`: what a run was asked and how far it got, rewritten atomically after every frame,
//! so a killed run resumes from its last complete frame (`docs/output_layout.md`).

use super::{FrameFormat, SequenceError};
use crate::track::FrameLog;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Version of `track.json`.
pub const STATE_VERSION: u32 = 1;

/// Largest vertex id a tracked frame holds exactly (its `id` property may be a `double`).
const MAX_ID: u64 = 1 << 53;

/// The run description; `P` is the caller's record of the method's parameters, compared on resume.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunState<P> {
    pub version: u32,
    pub input: Vec<PathBuf>,
    pub format: FrameFormat,
    pub params: P,
    pub edge_length: f32,
    /// The world position of the tracker's origin (`track::anchor_of`); 0 in runs recorded
    /// before it existed, which tracked in world coordinates.
    #[serde(default)]
    pub anchor: [f32; 3],
    pub completed: usize,
    pub next_id: u64,
    pub frames: Vec<FrameLog>,
    /// What each complete frame left on disk, so that `--resume` can tell a file a crash cut short
    /// (and step back to the frame before it) without reading every frame. Absent in runs
    /// recorded before it existed: those resume from their last frame only.
    #[serde(default)]
    pub written: Vec<Written>,
}

/// The files of one complete frame and the id counter after it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Written {
    /// Size of `frames/frame_NNNN.ply`.
    pub frame_bytes: u64,
    /// Size of `events/NNNN.events`.
    pub events_bytes: u64,
    /// The first unused vertex id after this frame: where a resume from it continues numbering.
    pub next_id: u64,
}

/// The parameters that differ between the run's `then` and `now`, each with both values, as
/// their serialized names say them (`transfer: "Blend" then, "Corner" now`): what a user must
/// pass again to resume.
fn differing<P: Serialize>(then: &P, now: &P) -> String {
    let (Ok(Value::Object(then)), Ok(Value::Object(now))) =
        (serde_json::to_value(then), serde_json::to_value(now))
    else {
        return "not comparable field by field".into();
    };
    let mut names: Vec<&String> = then.keys().chain(now.keys()).collect();
    names.sort_unstable();
    names.dedup();
    let shown = |v: Option<&Value>| v.map_or("unset".to_string(), Value::to_string);
    names
        .into_iter()
        .filter(|name| then.get(*name) != now.get(*name))
        .map(|name| {
            format!(
                "{name}: {} then, {} now",
                shown(then.get(name)),
                shown(now.get(name))
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

impl<P: DeserializeOwned + PartialEq + Serialize> RunState<P> {
    /// The state at `path`, checked to describe the same run as `input`, `format` and `params`,
    /// with at least one complete frame and figures that agree with each other.
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
        if state.input != input || state.format != format {
            return Err(bad(
                "the input frames or the frame format differ from the interrupted run's; resume with the same arguments".into(),
            ));
        }
        if state.params != *params {
            return Err(bad(format!(
                "parameters differ from the interrupted run's ({}); resume with the same arguments",
                differing(&state.params, params)
            )));
        }
        if state.completed == 0 {
            return Err(bad(
                "no frame was completed; start the run again without --resume".into(),
            ));
        }
        state.check_figures().map_err(bad)?;
        Ok(state)
    }
}

impl<P> RunState<P> {
    /// The figures of a damaged or edited state that would make a resumed run go wrong.
    fn check_figures(&self) -> Result<(), String> {
        if !self.input.is_empty() && self.completed > self.input.len() {
            return Err(format!(
                "{} frames completed of an input of {}",
                self.completed,
                self.input.len()
            ));
        }
        if self.frames.len() != self.completed {
            return Err(format!(
                "{} frame records for {} completed frames",
                self.frames.len(),
                self.completed
            ));
        }
        if !self.written.is_empty() && self.written.len() != self.completed {
            return Err(format!(
                "{} written-file records for {} completed frames",
                self.written.len(),
                self.completed
            ));
        }
        if !(self.edge_length.is_finite() && self.edge_length > 0.0) {
            return Err(format!(
                "edge length {} is not finite and positive",
                self.edge_length
            ));
        }
        let ids = std::iter::once(self.next_id).chain(self.written.iter().map(|w| w.next_id));
        if let Some(id) = ids.clone().find(|&id| id > MAX_ID) {
            return Err(format!("next vertex id {id} is beyond 2^53"));
        }
        if self
            .written
            .last()
            .is_some_and(|w| w.next_id != self.next_id)
            || self.written.windows(2).any(|w| w[1].next_id < w[0].next_id)
        {
            return Err("the vertex id counters of the frames disagree".into());
        }
        Ok(())
    }

    /// Forgets every frame after the first `frames`, as if the run had stopped there.
    pub(super) fn roll_back(&mut self, frames: usize) {
        self.completed = frames;
        self.frames.truncate(frames);
        self.written.truncate(frames);
        if let Some(last) = self.written.last() {
            self.next_id = last.next_id;
        }
    }
}
