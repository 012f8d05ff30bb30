//! The layout of a tracked output folder (`docs/output_layout.md`), defined once: the sequence
//! driver writes it and every reader (`propagate`, `eval`, `inspect`) reads it through these names.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Sub-folder of the tracked meshes.
pub const FRAMES_DIR: &str = "frames";
/// Sub-folder of the event lists.
pub const EVENTS_DIR: &str = "events";
/// The run description, kept up to date after every frame (what `--resume` continues from).
pub const TRACK_FILE: &str = "track.json";
/// Totals and per-frame figures, written last.
pub const SUMMARY_FILE: &str = "summary.json";

/// The file format of the tracked frames, recorded in `track.json`: binary PLY, the one format
/// that carries the persistent vertex ids (`id`) every reader of a tracked folder needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum FrameFormat {
    Ply,
}

impl FrameFormat {
    pub fn extension(self) -> &'static str {
        match self {
            FrameFormat::Ply => "ply",
        }
    }
}

/// The file name of tracked frame `frame` in the default format (PLY).
pub fn frame_name(frame: usize) -> String {
    frame_file_name(frame, FrameFormat::Ply)
}

/// The file name of tracked frame `frame` in `format`.
pub fn frame_file_name(frame: usize, format: FrameFormat) -> String {
    format!("frame_{frame:04}.{}", format.extension())
}

/// `frame_0042.ply` → 42.
pub fn frame_number(name: &str) -> Option<usize> {
    let digits = name.strip_prefix("frame_")?.strip_suffix(".ply")?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// The file name of the event list of the transition `frame − 1 → frame` (frame 0: the first
/// frame's own improvement).
pub fn events_name(frame: usize) -> String {
    format!("{frame:04}.events")
}

/// The paths of one tracked output folder.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Layout {
    root: PathBuf,
}

impl Layout {
    pub fn new(root: &Path) -> Self {
        Self {
            root: root.to_path_buf(),
        }
    }

    pub fn root(&self) -> &Path {
        &self.root
    }

    pub fn frames_dir(&self) -> PathBuf {
        self.root.join(FRAMES_DIR)
    }

    pub fn events_dir(&self) -> PathBuf {
        self.root.join(EVENTS_DIR)
    }

    pub fn frame_path(&self, frame: usize, format: FrameFormat) -> PathBuf {
        self.frames_dir().join(frame_file_name(frame, format))
    }

    pub fn events_path(&self, frame: usize) -> PathBuf {
        self.events_dir().join(events_name(frame))
    }

    pub fn state_path(&self) -> PathBuf {
        self.root.join(TRACK_FILE)
    }

    pub fn summary_path(&self) -> PathBuf {
        self.root.join(SUMMARY_FILE)
    }
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
