//! The propagation loop (paper §4.6): start-frame values walked through the event lists one frame
//! transition at a time, forward with the rules `f` or backward with the rules `g`.

use super::{PropagateError, TrackedSequence};
use crate::events::{VertexValues, backward, forward};
use crate::mesh::{Attribute, IndexedMesh};
use serde::Serialize;

/// Which way values travel through the sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Direction {
    /// From frame 0 to the last frame, through each transition's forward rules.
    Forward,
    /// From the last frame to frame 0, through each transition's backward rules, last event first.
    Backward,
}

impl Direction {
    /// The frame the values are given on.
    pub fn start(self, frames: usize) -> usize {
        match self {
            Self::Forward => 0,
            Self::Backward => frames.saturating_sub(1),
        }
    }
}

/// Carries `channels` (values on the vertices of `start`, the start frame of `direction`, in its
/// vertex order) through `sequence`, and hands each frame, start frame first, to `visit` with the
/// carried channels as its attributes (any attributes the tracked file had are replaced).
///
/// Only one frame and one set of values are held at a time. Every vertex of every frame must
/// receive a value and no value may be left without a vertex: anything else means the event lists
/// and the frames disagree, and is reported with the frame's file.
pub fn carry<F>(
    sequence: &TrackedSequence,
    direction: Direction,
    start: IndexedMesh,
    channels: &[Attribute],
    mut visit: F,
) -> Result<(), PropagateError>
where
    F: FnMut(usize, IndexedMesh) -> Result<(), PropagateError>,
{
    let first = direction.start(sequence.len());
    let layout: Vec<(String, usize)> = channels
        .iter()
        .map(|c| (c.name.clone(), c.components))
        .collect();
    let mut values = pack(sequence, first, &start, channels)?;
    visit(first, with_channels(start, &layout, &values))?;
    let order: Box<dyn Iterator<Item = usize>> = match direction {
        Direction::Forward => Box::new(1..sequence.len()),
        Direction::Backward => Box::new((0..first).rev()),
    };
    for frame in order {
        let path = |transition: usize| sequence.events_path(transition);
        let result = match direction {
            Direction::Forward => forward(&sequence.read_events(frame)?, &mut values)
                .map_err(|source| (path(frame), source)),
            Direction::Backward => backward(&sequence.read_events(frame + 1)?, &mut values)
                .map_err(|source| (path(frame + 1), source)),
        };
        result.map_err(|(path, source)| PropagateError::Events { path, source })?;
        let mesh = sequence.read_frame(frame)?;
        check_cover(sequence, frame, &mesh, &values)?;
        visit(frame, with_channels(mesh, &layout, &values))?;
    }
    Ok(())
}

/// Every channel's values interleaved per vertex (one `VertexValues` of all components, since every
/// rule is linear and acts on each component alike).
fn pack(
    sequence: &TrackedSequence,
    frame: usize,
    mesh: &IndexedMesh,
    channels: &[Attribute],
) -> Result<VertexValues, PropagateError> {
    let path = sequence.frame_path(frame);
    let inconsistent = |what: String| PropagateError::Inconsistent {
        path: path.to_path_buf(),
        what,
    };
    let Some(ids) = &mesh.ids else {
        return Err(PropagateError::NoIds {
            path: path.to_path_buf(),
        });
    };
    let n = mesh.positions.len();
    let width: usize = channels.iter().map(|c| c.components).sum();
    let mut packed = Vec::with_capacity(n * width);
    for c in channels {
        if c.values.len() != n * c.components {
            return Err(inconsistent(format!(
                "channel '{}' has {} values for {n} vertices × {} components",
                c.name,
                c.values.len(),
                c.components
            )));
        }
    }
    for v in 0..n {
        for c in channels {
            packed.extend_from_slice(&c.values[v * c.components..(v + 1) * c.components]);
        }
    }
    VertexValues::from_parts(width, ids, &packed).map_err(|e| inconsistent(e.to_string()))
}

/// Checks that the carried values cover exactly the vertices of `mesh`.
fn check_cover(
    sequence: &TrackedSequence,
    frame: usize,
    mesh: &IndexedMesh,
    values: &VertexValues,
) -> Result<(), PropagateError> {
    let path = sequence.frame_path(frame);
    let Some(ids) = &mesh.ids else {
        return Err(PropagateError::NoIds {
            path: path.to_path_buf(),
        });
    };
    if let Some(id) = ids.iter().find(|&&id| values.get(id).is_none()) {
        return Err(PropagateError::Inconsistent {
            path: path.to_path_buf(),
            what: format!("vertex {id} received no value from the event lists"),
        });
    }
    if values.len() != ids.len() {
        return Err(PropagateError::Inconsistent {
            path: path.to_path_buf(),
            what: format!(
                "the event lists leave {} vertices but the frame has {}",
                values.len(),
                ids.len()
            ),
        });
    }
    Ok(())
}

/// `mesh` with the carried values as its attributes, in its own vertex order.
fn with_channels(
    mut mesh: IndexedMesh,
    layout: &[(String, usize)],
    values: &VertexValues,
) -> IndexedMesh {
    let ids = mesh.ids.as_deref().unwrap_or_default();
    let mut attributes: Vec<Attribute> = layout
        .iter()
        .map(|(name, components)| Attribute {
            name: name.clone(),
            components: *components,
            values: Vec::with_capacity(ids.len() * components),
        })
        .collect();
    for &id in ids {
        let mut value = values.get(id).unwrap_or_default();
        for a in &mut attributes {
            let (head, rest) = value.split_at(a.components.min(value.len()));
            a.values.extend_from_slice(head);
            value = rest;
        }
    }
    mesh.attributes = attributes;
    mesh
}
