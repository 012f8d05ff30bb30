//! Reading what `surftrack track -o OUT` wrote (docs/output_layout.md), one frame at a time, so that
//! memory never depends on the length of the sequence.

use super::PropagateError;
use crate::events::EventList;
use crate::events::file::decode;
use crate::io::{ReadOptions, read_frame_with};
use crate::mesh::IndexedMesh;
use std::path::{Path, PathBuf};

/// Sub-directory of the tracked meshes.
pub const FRAMES_DIR: &str = "frames";
/// Sub-directory of the event lists.
pub const EVENTS_DIR: &str = "events";
/// The run description `track` keeps up to date.
pub const TRACK_FILE: &str = "track.json";

/// A tracked sequence on disk: `frames/frame_NNNN.ply` with persistent ids and `events/NNNN.events`,
/// the event list of the transition from frame `NNNN − 1` to frame `NNNN`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackedSequence {
    dir: PathBuf,
    frames: Vec<PathBuf>,
    input: Option<Vec<PathBuf>>,
}

impl TrackedSequence {
    /// Finds the frames of a tracked output directory.
    ///
    /// Frames are numbered from 0 without gaps. When `track.json` says how many frames are complete
    /// (`completed`), frames beyond that (a run still going, or killed) are left out; its `input`
    /// list, when present, is kept for [`Self::input`].
    pub fn open(dir: &Path) -> Result<Self, PropagateError> {
        let frames_dir = dir.join(FRAMES_DIR);
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
        let (completed, input) = read_run_description(dir)?;
        let count = completed.map_or(numbered.len(), |c| c.min(numbered.len()));
        if count == 0 {
            return Err(PropagateError::NoFrames {
                dir: dir.to_path_buf(),
            });
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            frames: (0..count).map(|k| frames_dir.join(frame_name(k))).collect(),
            input,
        })
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

    pub fn frame_path(&self, frame: usize) -> &Path {
        &self.frames[frame]
    }

    /// The event list of the transition `frame − 1 → frame`.
    pub fn events_path(&self, frame: usize) -> PathBuf {
        self.dir.join(EVENTS_DIR).join(format!("{frame:04}.events"))
    }

    /// Tracked frame `frame` exactly as written (no repair, which could renumber vertices), with its
    /// persistent ids, which must be present and distinct.
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
        Ok(mesh)
    }

    /// The checked event list of the transition `frame − 1 → frame`.
    pub fn read_events(&self, frame: usize) -> Result<EventList, PropagateError> {
        let path = self.events_path(frame);
        let bytes = std::fs::read(&path).map_err(|e| PropagateError::Unreadable {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        let list = decode(&bytes).map_err(|source| PropagateError::EventFile {
            path: path.clone(),
            source,
        })?;
        list.check()
            .map_err(|source| PropagateError::Events { path, source })?;
        Ok(list)
    }
}

/// `frame_0042.ply` → 42.
fn frame_number(name: &str) -> Option<usize> {
    let digits = name.strip_prefix("frame_")?.strip_suffix(".ply")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The file name of tracked frame `frame`.
pub fn frame_name(frame: usize) -> String {
    format!("frame_{frame:04}.ply")
}

/// `completed` and `input` from `track.json`, when the file exists.
fn read_run_description(
    dir: &Path,
) -> Result<(Option<usize>, Option<Vec<PathBuf>>), PropagateError> {
    let path = dir.join(TRACK_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((None, None)),
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
    Ok((completed, input))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_round_trip_and_others_are_ignored() {
        for k in [0, 7, 42, 9999, 12345] {
            assert_eq!(frame_number(&frame_name(k)), Some(k));
        }
        for name in [
            "frame_.ply",
            "frame_12.obj",
            "frame_1a.ply",
            "x_0001.ply",
            "frame_-1.ply",
        ] {
            assert_eq!(frame_number(name), None, "{name}");
        }
    }
}
