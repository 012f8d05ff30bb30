//! Where `--resume` continues an interrupted run: the last frame whose files are whole.
//!
//! Every write is atomic, so a killed process leaves each file old or new, never cut short; but a
//! machine that loses power before its disk cache reaches the disk, or a copy between file
//! systems that stops part-way, can leave a frame or event file shorter than it was written.
//! `track.json` records the size of every frame's two files, so a file cut short is found
//! without reading every frame: the run resumes from the frame before the first damaged one, and
//! rewrites the rest byte for byte as the uninterrupted run would have.

use super::state::Written;
use super::{FrameFormat, Layout, RunState, SequenceError};
use crate::events::file::decode;
use crate::io::{ReadOptions, read_frame_with, remove_stale_temporaries};
use crate::mesh::IndexedMesh;
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::path::{Path, PathBuf};

/// An interrupted run's state, rolled back to its last intact frame, and that frame's mesh.
#[derive(Debug)]
pub struct ResumePoint<P> {
    pub state: RunState<P>,
    /// The last intact frame exactly as written, with its persistent ids.
    pub mesh: IndexedMesh,
    /// One line per damaged file found (each names the file and what is wrong with it).
    pub warnings: Vec<String>,
}

/// Finds where the run in `layout` continues; `input`, `format` and `params` must be the
/// interrupted run's. Temporary files of writes the interruption cut short are removed.
pub fn resume_point<P: DeserializeOwned + PartialEq + Serialize>(
    layout: &Layout,
    input: &[PathBuf],
    format: FrameFormat,
    params: &P,
) -> Result<ResumePoint<P>, SequenceError> {
    for dir in [
        layout.root().to_path_buf(),
        layout.frames_dir(),
        layout.events_dir(),
    ] {
        remove_stale_temporaries(&dir)?;
    }
    let mut state = RunState::load_matching(&layout.state_path(), input, format, params)?;
    let mut warnings = Vec::new();
    // Runs recorded without file sizes cannot step back (their id counters are not recorded per
    // frame): their last frame must be whole.
    let can_step_back = !state.written.is_empty();
    let mut intact = if can_step_back {
        intact_prefix(layout, &state, &mut warnings)
    } else {
        state.completed
    };
    let mesh = loop {
        let Some(last) = intact.checked_sub(1) else {
            return Err(SequenceError::State {
                path: layout.state_path(),
                message: "no complete frame is left intact; start the run again without --resume"
                    .into(),
            });
        };
        let next_id = state.written.get(last).map_or(state.next_id, |w| w.next_id);
        match read_frame_exactly(layout, last, state.format, next_id) {
            Ok(mesh) => break mesh,
            Err(e) if can_step_back => {
                warnings.push(format!("warning: {e}; resuming from the frame before it"));
                intact = last;
            }
            Err(e) => return Err(e),
        }
    };
    if intact < state.completed {
        state.roll_back(intact);
    }
    Ok(ResumePoint {
        state,
        mesh,
        warnings,
    })
}

/// The number of leading frames whose two files have the sizes `track.json` recorded.
fn intact_prefix<P>(layout: &Layout, state: &RunState<P>, warnings: &mut Vec<String>) -> usize {
    for (k, written) in state.written.iter().enumerate() {
        let files = [
            (layout.frame_path(k, state.format), written.frame_bytes),
            (layout.events_path(k), written.events_bytes),
        ];
        for (path, expected) in files {
            if let Some(problem) = size_problem(&path, expected) {
                warnings.push(format!(
                    "warning: {}: {problem}; resuming from frame {k}",
                    path.display()
                ));
                return k;
            }
        }
    }
    state.written.len()
}

fn size_problem(path: &Path, expected: u64) -> Option<String> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.len() == expected => None,
        Ok(meta) => Some(format!(
            "{} bytes where {expected} were written (cut short or replaced)",
            meta.len()
        )),
        Err(e) => Some(format!("cannot read: {e}")),
    }
}

/// Frame `k` as written (no repair, which could weld two vertices improvement left close), with
/// ids below `next_id`, and its event list whole.
fn read_frame_exactly(
    layout: &Layout,
    k: usize,
    format: FrameFormat,
    next_id: u64,
) -> Result<IndexedMesh, SequenceError> {
    let path = layout.frame_path(k, format);
    let exact = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    let mesh = read_frame_with(&path, &exact)?.mesh;
    let damaged = |path: &Path, reason: String| SequenceError::Damaged {
        path: path.to_path_buf(),
        reason,
    };
    match mesh.ids.as_ref().and_then(|ids| ids.iter().max()) {
        None => return Err(damaged(&path, "the frame has no persistent ids".into())),
        Some(&max) if max >= next_id => {
            return Err(damaged(
                &path,
                format!("vertex id {max} is not below the run's next id {next_id}"),
            ));
        }
        Some(_) => {}
    }
    let events = layout.events_path(k);
    let bytes =
        std::fs::read(&events).map_err(|e| damaged(&events, format!("cannot read: {e}")))?;
    decode(&bytes).map_err(|e| damaged(&events, e.to_string()))?;
    Ok(mesh)
}

/// What `commit` records for a frame whose files were just written.
pub(super) fn written(
    frame: &Path,
    events_bytes: usize,
    next_id: u64,
) -> Result<Written, SequenceError> {
    let frame_bytes = std::fs::metadata(frame)
        .map_err(|source| SequenceError::Create {
            path: frame.to_path_buf(),
            source,
        })?
        .len();
    Ok(Written {
        frame_bytes,
        events_bytes: events_bytes as u64,
        next_id,
    })
}
