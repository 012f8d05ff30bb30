//! Per-vertex velocities of a tracked sequence. Re-meshed fluid caches cannot have them (a vertex
//! of one frame is no vertex of the next); a tracked sequence can, because a persistent id names the
//! same material point in every frame it lives in. Renderers use them for motion blur.
//!
//! In frame `j` at `fps` frames per second, a vertex whose id lives in frames `j` and `j + 1`
//! moves at `(p(j+1) − p(j)) · fps`; one that ends in frame `j` but lives in `j − 1` at
//! `(p(j) − p(j−1)) · fps`; one that lives in frame `j` only at 0.

use crate::mesh::IndexedMesh;
use glam::Vec3;
use rustc_hash::FxHashMap;
use thiserror::Error;

/// Where each persistent id of one frame is: what a neighbouring frame's velocities look up.
pub type Trail = FxHashMap<u64, Vec3>;

/// The trail of a frame given by its ids and positions (same order).
pub fn trail(ids: &[u64], positions: &[Vec3]) -> Trail {
    ids.iter().copied().zip(positions.iter().copied()).collect()
}

/// The velocities of one frame (ids and positions in vertex order), in units per second, from the
/// trails of the frames before and after it (none at the ends of the sequence).
pub fn velocities(
    previous: Option<&Trail>,
    ids: &[u64],
    positions: &[Vec3],
    next: Option<&Trail>,
    fps: f32,
) -> Vec<Vec3> {
    ids.iter()
        .zip(positions)
        .map(|(id, &p)| {
            if let Some(&later) = next.and_then(|t| t.get(id)) {
                (later - p) * fps
            } else if let Some(&earlier) = previous.and_then(|t| t.get(id)) {
                (p - earlier) * fps
            } else {
                Vec3::ZERO
            }
        })
        .collect()
}

/// A frame read for velocities has no persistent ids.
#[derive(Debug, Error)]
#[error("tracked frame {frame} has no persistent vertex ids, so its vertices have no velocities")]
pub struct NoIds {
    pub frame: usize,
}

/// One frame of a [`VelocityStream`]: the mesh as read and its vertices' velocities.
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityFrame {
    pub index: usize,
    pub mesh: IndexedMesh,
    pub velocities: Vec<Vec3>,
}

/// Frames `0..count` with their velocities, read one at a time through `read` in order, each once.
///
/// Frame `j` is given out once frame `j + 1` has been read, so at most two meshes and the trail of
/// the frame before are held: memory does not depend on the length of the sequence.
pub struct VelocityStream<F> {
    read: F,
    count: usize,
    fps: f32,
    /// Index of the next frame to give out.
    position: usize,
    previous: Option<Trail>,
    ahead: Option<(IndexedMesh, Trail)>,
}

impl<F> VelocityStream<F> {
    pub fn new(read: F, count: usize, fps: f32) -> Self {
        Self {
            read,
            count,
            fps,
            position: 0,
            previous: None,
            ahead: None,
        }
    }
}

impl<F, E> VelocityStream<F>
where
    F: FnMut(usize) -> Result<IndexedMesh, E>,
    E: From<NoIds>,
{
    fn load(&mut self, frame: usize) -> Result<(IndexedMesh, Trail), E> {
        let mesh = (self.read)(frame)?;
        let ids = mesh.ids.as_deref().ok_or(NoIds { frame })?;
        let trail = trail(ids, &mesh.positions);
        Ok((mesh, trail))
    }

    fn advance(&mut self) -> Result<VelocityFrame, E> {
        let index = self.position;
        let (mesh, current) = match self.ahead.take() {
            Some(frame) => frame,
            None => self.load(index)?,
        };
        if index + 1 < self.count {
            self.ahead = Some(self.load(index + 1)?);
        }
        let ids = mesh.ids.as_deref().ok_or(NoIds { frame: index })?;
        let next = self.ahead.as_ref().map(|(_, t)| t);
        let velocities = velocities(self.previous.as_ref(), ids, &mesh.positions, next, self.fps);
        self.previous = Some(current);
        self.position += 1;
        Ok(VelocityFrame {
            index,
            mesh,
            velocities,
        })
    }
}

impl<F, E> Iterator for VelocityStream<F>
where
    F: FnMut(usize) -> Result<IndexedMesh, E>,
    E: From<NoIds>,
{
    type Item = Result<VelocityFrame, E>;

    /// After an error the stream ends.
    fn next(&mut self) -> Option<Self::Item> {
        if self.position >= self.count {
            return None;
        }
        let item = self.advance();
        if item.is_err() {
            self.position = self.count;
        }
        Some(item)
    }
}
