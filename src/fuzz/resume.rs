//! The resume state of a tracked folder: a real three-frame run of two small spheres, whose
//! `track.json` is mutated as JSON (numbers replaced by garbage, keys dropped, per-frame lists cut)
//! or as text, and whose partial outputs (frames, event lists) are cut, flipped, removed, or
//! joined by a stale temporary file. Each input goes through `--resume`'s own checks and, when
//! they pass, starts a tracker from what they return.

use super::mutate::{GARBAGE_TOKENS, bytes_any, text_any};
use super::{Harness, Input, Rng, Verdict};
use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::sequence::{
    FrameFormat, FrameSource, Layout, Output, Start, resume_point, track_sequence,
};
use crate::track::{TrackOptions, Tracker};
use serde_json::Value;
use std::path::Path;

type Params = Option<Value>;

pub(super) struct Resume {
    /// Every file of the tracked folder, relative to it.
    files: Vec<(String, Vec<u8>)>,
    params: Params,
}

impl Resume {
    pub(super) fn new(dir: &Path) -> Result<Self, String> {
        let frames: Vec<IndexedMesh> = [0.0f32, 0.1, 0.2]
            .iter()
            .map(|&x| IndexedMesh::icosphere(glam::Vec3::new(x, 0.0, 0.0), 1.0, 2))
            .collect();
        let params = serde_json::json!({ "fuzz": 1 });
        let root = dir.join("tracked");
        let output = Output {
            layout: Layout::new(&root),
            format: FrameFormat::Ply,
            params: &params,
            start: Start::Fresh { force: true },
        };
        track_sequence(
            FrameSource::Meshes(&frames),
            &Backend::Cpu,
            &TrackOptions::default(),
            Some(output),
            |_| {},
        )
        .map_err(|e| e.to_string())?;
        let mut files = Vec::new();
        for name in [
            "track.json",
            "frames/frame_0000.ply",
            "frames/frame_0001.ply",
            "frames/frame_0002.ply",
            "events/0000.events",
            "events/0001.events",
            "events/0002.events",
        ] {
            let bytes = std::fs::read(root.join(name)).map_err(|e| format!("{name}: {e}"))?;
            files.push((name.to_string(), bytes));
        }
        Ok(Self {
            files,
            params: Some(params),
        })
    }
}

/// A garbage JSON value for a field of `track.json`.
fn garbage_value(rng: &mut Rng) -> Value {
    match rng.below(10) {
        0 => Value::Null,
        1 => Value::from(-1),
        2 => Value::from(u64::MAX),
        3 => Value::from((1u64 << 53) + 1),
        4 => Value::from(1e308),
        5 => Value::from(-0.0),
        6 => Value::from(rng.below(8) as u64),
        7 => Value::from(1.5),
        8 => Value::from("x"),
        _ => Value::Array(Vec::new()),
    }
}

/// Replaces a random leaf of `value` (or drops a key, or cuts an array).
fn mutate_json(rng: &mut Rng, value: &mut Value) {
    match value {
        Value::Object(map) if !map.is_empty() => {
            let keys: Vec<String> = map.keys().cloned().collect();
            let key = rng.pick(&keys).clone();
            if rng.chance(10) {
                map.remove(&key);
            } else if let Some(child) = map.get_mut(&key) {
                mutate_json(rng, child);
            }
        }
        Value::Array(items) if !items.is_empty() => {
            if rng.chance(15) {
                let keep = rng.below(items.len());
                items.truncate(keep);
            } else {
                let i = rng.below(items.len());
                mutate_json(rng, &mut items[i]);
            }
        }
        leaf => *leaf = garbage_value(rng),
    }
}

impl Harness for Resume {
    fn generate(&self, rng: &mut Rng) -> Input {
        let mut files: Vec<(String, Option<Vec<u8>>)> = self
            .files
            .iter()
            .map(|(name, bytes)| (name.clone(), Some(bytes.clone())))
            .collect();
        for _ in 0..1 + rng.below(2) {
            let which = match rng.below(100) {
                0..=49 => 0,
                50..=64 => 3,
                65..=74 => 2,
                75..=89 => 6,
                _ => rng.below(files.len()),
            };
            let donor = self.files[rng.below(self.files.len())].1.clone();
            let Some(bytes) = files[which].1.as_mut() else {
                continue;
            };
            match rng.below(20) {
                0 => files[which].1 = None,
                1 => {
                    let (name, _) = &files[which];
                    let stale = match name.rsplit_once('/') {
                        Some((dir, file)) => format!("{dir}/.{file}.77.0.tmp"),
                        None => format!(".{name}.77.0.tmp"),
                    };
                    files.push((stale, Some(donor)));
                }
                _ if which == 0 && rng.chance(60) => {
                    if let Ok(mut json) = serde_json::from_slice::<Value>(bytes) {
                        mutate_json(rng, &mut json);
                        *bytes = serde_json::to_vec_pretty(&json).unwrap_or_default();
                    }
                }
                _ if which == 0 => {
                    if rng.chance(50) {
                        let word = *rng.pick(GARBAGE_TOKENS);
                        super::mutate::replace_token(rng, bytes, word);
                    } else {
                        text_any(rng, bytes, &donor);
                    }
                }
                _ => bytes_any(rng, bytes, &donor),
            }
        }
        Input { files }
    }

    fn check(&self, scratch: &Path) -> Result<Verdict, String> {
        let layout = Layout::new(scratch);
        let Ok(point) = resume_point(&layout, &[], FrameFormat::Ply, &self.params) else {
            return Ok(Verdict::Refused);
        };
        let state = &point.state;
        if !(1..=3).contains(&state.completed) || state.frames.len() != state.completed {
            return Err(format!("resumed at {} complete frames", state.completed));
        }
        if let Some(max) = point.mesh.ids.as_ref().and_then(|ids| ids.iter().max())
            && *max >= state.next_id
        {
            return Err(format!(
                "id {max} is not below the next id {}",
                state.next_id
            ));
        }
        let options = TrackOptions::default();
        let last = state.completed.saturating_sub(1);
        if Tracker::resume(
            last,
            &point.mesh,
            state.next_id,
            (state.edge_length, glam::Vec3::from(state.anchor)),
            &options,
        )
        .is_err()
        {
            return Ok(Verdict::Refused);
        }
        Ok(Verdict::Accepted)
    }
}
