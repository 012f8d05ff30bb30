//! The frames an export reads: the tracked meshes with their persistent ids, and, from a
//! `propagate` output, the channels carried onto them.

use super::ExportError;
use crate::io::{ReadOptions, read_frame_with};
use crate::mesh::IndexedMesh;
use crate::propagate::TrackedSequence;
use crate::sequence::frame_name;
use rustc_hash::FxHashMap;
use std::path::{Path, PathBuf};

/// A tracked sequence on disk, optionally with the folder `surftrack propagate` wrote from it.
#[derive(Debug, Clone)]
pub struct ExportSource {
    tracked: TrackedSequence,
    from: Option<PathBuf>,
}

impl ExportSource {
    /// Finds the tracked frames in `tracked` (the layout `surftrack track` writes); `from` is a
    /// folder of `frame_NNNN.ply` files with ids and channels, one per tracked frame.
    pub fn open(tracked: &Path, from: Option<&Path>) -> Result<Self, ExportError> {
        Ok(Self {
            tracked: TrackedSequence::open(tracked)?,
            from: from.map(Path::to_path_buf),
        })
    }

    pub fn len(&self) -> usize {
        self.tracked.len()
    }

    pub fn is_empty(&self) -> bool {
        self.tracked.is_empty()
    }

    /// The file frame `frame` is read from: the propagated one when there is one.
    pub fn frame_path(&self, frame: usize) -> PathBuf {
        match &self.from {
            Some(dir) => dir.join(frame_name(frame)),
            None => self.tracked.frame_path(frame).to_path_buf(),
        }
    }

    /// Tracked frame `frame` with its ids; with a propagated folder, its positions (a carried
    /// displacement moves them) and channels too, matched to the tracked vertices by id.
    pub fn read(&self, frame: usize) -> Result<IndexedMesh, ExportError> {
        let mut mesh = self.tracked.read_frame(frame)?;
        let Some(dir) = &self.from else {
            return Ok(mesh);
        };
        let path = dir.join(frame_name(frame));
        let options = ReadOptions {
            repair: false,
            ..ReadOptions::default()
        };
        let carried = read_frame_with(&path, &options)?.mesh;
        let mismatch = |reason: String| ExportError::FromMismatch {
            path: path.clone(),
            tracked: self.tracked.frame_path(frame).to_path_buf(),
            reason,
        };
        let Some(carried_ids) = &carried.ids else {
            return Err(mismatch("it has no persistent `id` vertex property".into()));
        };
        if carried.positions.len() != mesh.positions.len() {
            return Err(mismatch(format!(
                "it has {} vertices, the tracked frame {}",
                carried.positions.len(),
                mesh.positions.len()
            )));
        }
        let slot: FxHashMap<u64, usize> = carried_ids
            .iter()
            .enumerate()
            .map(|(v, &id)| (id, v))
            .collect();
        let ids = mesh.ids.as_deref().unwrap_or_default();
        let mut order = Vec::with_capacity(ids.len());
        for id in ids {
            match slot.get(id) {
                Some(&v) => order.push(v),
                None => return Err(mismatch(format!("tracked vertex id {id} is not in it"))),
            }
        }
        mesh.positions = order.iter().map(|&v| carried.positions[v]).collect();
        mesh.attributes = carried
            .attributes
            .iter()
            .map(|a| a.gather(&order))
            .collect();
        Ok(mesh)
    }
}
