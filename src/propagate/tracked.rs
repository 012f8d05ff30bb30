//! Reading what `surftrack track -o OUT` wrote (docs/output_layout.md), one frame at a time, so that
//! memory never depends on the length of the sequence.

use super::PropagateError;
use crate::events::EventList;
use crate::events::file::{decode, touched, verify};
use crate::io::{ReadOptions, read_frame_with};
use crate::mesh::IndexedMesh;
use crate::sequence::{Layout, TRACK_FILE, frame_name, frame_number};
use crate::track::StageChurn;
use std::path::{Path, PathBuf};

/// A tracked sequence on disk: `frames/frame_NNNN.ply` with persistent ids and `events/NNNN.events`,
/// the event list of the transition from frame `NNNN − 1` to frame `NNNN`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedSequence {
    dir: PathBuf,
    frames: Vec<PathBuf>,
    input: Option<Vec<PathBuf>>,
    churn: Vec<Option<StageChurn>>,
}

impl TrackedSequence {
    /// Finds the frames of a tracked output directory.
    ///
    /// Frames are numbered from 0 without gaps. When `track.json` says how many frames are complete
    /// (`completed`), frames beyond that (a run still going, or killed) are left out; its `input`
    /// list, when present, is kept for [`Self::input`]. The event list of every transition must be
    /// present and whole.
    pub fn open(dir: &Path) -> Result<Self, PropagateError> {
        let frames_dir = Layout::new(dir).frames_dir();
        let entries = std::fs::read_dir(&frames_dir).map_err(|e| PropagateError::Unreadable {
            path: frames_dir.clone(),
            reason: e.to_string(),
        })?;
        let mut numbered: Vec<usize> = entries
            .filter_map(|entry| entry.ok())
            .filter_map(|entry| frame_number(&entry.file_name().to_string_lossy()))
            .collect();
        numbered.sort_unstable();
        numbered.dedup();
        if let Some(missing) = numbered.iter().enumerate().find(|&(i, &n)| i != n) {
            return Err(PropagateError::FrameGap {
                dir: frames_dir,
                missing: missing.0,
            });
        }
        let (completed, input, churn) = read_run_description(dir)?;
        let count = completed.map_or(numbered.len(), |c| c.min(numbered.len()));
        if count == 0 {
            return Err(PropagateError::NoFrames {
                dir: dir.to_path_buf(),
            });
        }
        let sequence = Self {
            dir: dir.to_path_buf(),
            frames: (0..count).map(|k| frames_dir.join(frame_name(k))).collect(),
            input,
            churn,
        };
        // Every event list is checked whole up front (its length and checksum, not its decoding),
        // so a missing or damaged one stops a command before it writes anything.
        for frame in 1..count {
            let (path, bytes) = sequence.event_bytes(frame)?;
            verify(&bytes).map_err(|source| PropagateError::EventFile { path, source })?;
        }
        Ok(sequence)
    }

    pub fn dir(&self) -> &Path {
        &self.dir
    }

    pub fn len(&self) -> usize {
        self.frames.len()
    }

    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// The input frames `track.json` lists, one per tracked frame, when it lists them.
    pub fn input(&self) -> Option<&[PathBuf]> {
        self.input.as_deref()
    }

    /// What each stage of the tracker created and removed in frame `frame`, as `track.json`
    /// records it (absent for runs recorded before it did).
    pub fn churn(&self, frame: usize) -> Option<StageChurn> {
        self.churn.get(frame).copied().flatten()
    }

    pub fn frame_path(&self, frame: usize) -> &Path {
        &self.frames[frame]
    }

    /// The event list of the transition `frame − 1 → frame`.
    pub fn events_path(&self, frame: usize) -> PathBuf {
        Layout::new(&self.dir).events_path(frame)
    }

    /// Tracked frame `frame` exactly as written (no repair, which could renumber vertices), with its
    /// persistent ids, which must be present and distinct, and which the event list of the
    /// transition into it must agree with ([`Self::check_events`]; frame 0's list records the
    /// first frame's own improvement and carries nothing): a reader of the folder never goes on
    /// past a missing, damaged or foreign event list.
    pub fn read_frame(&self, frame: usize) -> Result<IndexedMesh, PropagateError> {
        let path = self.frame_path(frame);
        let options = ReadOptions {
            repair: false,
            ..ReadOptions::default()
        };
        let mesh = read_frame_with(path, &options)?.mesh;
        let Some(ids) = &mesh.ids else {
            return Err(PropagateError::NoIds {
                path: path.to_path_buf(),
            });
        };
        let mut sorted = ids.clone();
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(PropagateError::Inconsistent {
                path: path.to_path_buf(),
                what: format!("persistent id {} appears twice", w[0]),
            });
        }
        if frame > 0 {
            self.check_events(frame, &sorted)?;
        }
        Ok(mesh)
    }

    /// Checks the event list of `frame` against the frame's ids (`sorted`): every vertex the list
    /// leaves alive (created, or kept by an event) is in the frame, and every vertex it destroys
    /// is not. An event list of another run or frame fails this almost surely; the previous frame
    /// is not needed, so the check costs one small file per frame.
    fn check_events(&self, frame: usize, sorted: &[u64]) -> Result<(), PropagateError> {
        let (path, bytes) = self.event_bytes(frame)?;
        let touched =
            touched(&bytes).map_err(|source| PropagateError::EventFile { path, source })?;
        if let Some((id, alive)) = touched
            .into_iter()
            .find(|&(id, alive)| sorted.binary_search(&id).is_ok() != alive)
        {
            let frame_file = self.frame_path(frame).display().to_string();
            return Err(PropagateError::Inconsistent {
                path: self.events_path(frame),
                what: format!(
                    "vertex {id} is {} by this event list but {} {frame_file} (an event list of another run or frame?)",
                    if alive { "left alive" } else { "destroyed" },
                    if alive { "missing from" } else { "present in" },
                ),
            });
        }
        Ok(())
    }

    /// The bytes of the event list of the transition `frame − 1 → frame`.
    fn event_bytes(&self, frame: usize) -> Result<(PathBuf, Vec<u8>), PropagateError> {
        let path = self.events_path(frame);
        let bytes = std::fs::read(&path).map_err(|e| PropagateError::Unreadable {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        Ok((path, bytes))
    }

    /// The checked event list of the transition `frame − 1 → frame`.
    pub fn read_events(&self, frame: usize) -> Result<EventList, PropagateError> {
        let (path, bytes) = self.event_bytes(frame)?;
        let list = decode(&bytes).map_err(|source| PropagateError::EventFile {
            path: path.clone(),
            source,
        })?;
        list.check()
            .map_err(|source| PropagateError::Events { path, source })?;
        Ok(list)
    }
}

/// What `track.json` holds, when it exists.
type RunDescription = (Option<usize>, Option<Vec<PathBuf>>, Vec<Option<StageChurn>>);

/// `completed`, `input` and each frame's churn from `track.json`, when the file exists.
fn read_run_description(dir: &Path) -> Result<RunDescription, PropagateError> {
    let path = dir.join(TRACK_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((None, None, Vec::new())),
        Err(e) => {
            return Err(PropagateError::Unreadable {
                path,
                reason: e.to_string(),
            });
        }
    };
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| PropagateError::Unreadable {
            path: path.clone(),
            reason: format!("not valid JSON: {e}"),
        })?;
    let completed = json
        .get("completed")
        .and_then(serde_json::Value::as_u64)
        .map(|c| c as usize);
    let input = json.get("input").and_then(|v| v.as_array()).map(|list| {
        list.iter()
            .filter_map(|p| p.as_str().map(PathBuf::from))
            .collect()
    });
    let churn = json
        .get("frames")
        .and_then(|v| v.as_array())
        .map(|frames| {
            frames
                .iter()
                .map(|f| {
                    f.get("churn")
                        .and_then(|c| serde_json::from_value(c.clone()).ok())
                })
                .collect()
        })
        .unwrap_or_default();
    Ok((completed, input, churn))
}
