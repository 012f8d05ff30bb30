//! What the start frame's values are: the channels `propagate` carries.

use super::PropagateError;
use super::checker::Checker;
use super::projection::{Bounds, Projection};
use super::texture::Texture;
use super::transfer::transfer;
use crate::mesh::{Attribute, IndexedMesh};
use serde::Serialize;
use std::path::PathBuf;

/// Where one channel's values on the start frame come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// A 3-D checkerboard colour with cells of `cell` start-frame mean edge lengths, aligned with the
    /// start frame's bounds (see [`StartFrame::checker`]).
    Checker { cell: f32 },
    /// An image's colour through a projection of the start frame.
    Image {
        texture: Texture,
        projection: Projection,
    },
    /// Texture coordinates from a projection of the start frame.
    Uv { projection: Projection },
    /// An attribute of a mesh file (see [`transfer`]).
    Attribute { path: PathBuf, name: String },
}

/// A named channel and its source. Names follow the PLY writer's conventions (`color`, `uv`), which
/// is what makes Blender and Houdini pick them up as vertex colours and texture coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    pub name: String,
    pub source: Source,
}

impl Channel {
    pub fn checker(cell: f32) -> Self {
        Self {
            name: "color".to_string(),
            source: Source::Checker { cell },
        }
    }

    pub fn image(texture: Texture, projection: Projection) -> Self {
        Self {
            name: "color".to_string(),
            source: Source::Image {
                texture,
                projection,
            },
        }
    }

    pub fn uv(projection: Projection) -> Self {
        Self {
            name: "uv".to_string(),
            source: Source::Uv { projection },
        }
    }

    pub fn attribute(path: PathBuf, name: &str) -> Self {
        Self {
            name: name.to_string(),
            source: Source::Attribute {
                path,
                name: name.to_string(),
            },
        }
    }
}

/// The scale of the start frame, which sizes checker cells and projections.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StartFrame {
    /// Index of the start frame in the tracked sequence.
    pub frame: usize,
    /// Its mean edge length Δ.
    pub mean_edge_length: f32,
    pub bounds: Bounds,
}

impl StartFrame {
    pub fn of(frame: usize, mesh: &IndexedMesh) -> Self {
        let bounds = Bounds::of(&mesh.positions).unwrap_or(Bounds {
            min: glam::Vec3::ZERO,
            max: glam::Vec3::ZERO,
        });
        Self {
            frame,
            mean_edge_length: mesh.mean_edge_length(),
            bounds,
        }
    }

    /// The checker a [`Source::Checker`] of `cell` mean edge lengths paints on this frame. Its walls
    /// lie half a cell off the bounds, so flat sides of the surface that touch the bounds (axis-aligned
    /// faces are common) never lie on a wall, where rounding alone would pick the colour.
    pub fn checker(&self, cell: f32) -> Checker {
        let size = cell * self.mean_edge_length;
        Checker {
            origin: self.bounds.min - glam::Vec3::splat(0.5 * size),
            cell: size,
        }
    }
}

/// The values of `channel` on the start frame's vertices.
pub fn start_values(
    channel: &Channel,
    mesh: &IndexedMesh,
    start: &StartFrame,
) -> Result<Attribute, PropagateError> {
    let per_vertex = |components: usize, f: &dyn Fn(glam::Vec3) -> Vec<f32>| Attribute {
        name: channel.name.clone(),
        components,
        values: mesh.positions.iter().flat_map(|&p| f(p)).collect(),
    };
    Ok(match &channel.source {
        Source::Checker { cell } => {
            if !(cell.is_finite() && *cell > 0.0) {
                return Err(PropagateError::Parameter {
                    what: "checker cell size",
                    value: *cell,
                });
            }
            let checker = start.checker(*cell);
            per_vertex(3, &|p| checker.colour(p).to_vec())
        }
        Source::Image {
            texture,
            projection,
        } => per_vertex(3, &|p| {
            texture.sample(projection.uv(p, &start.bounds)).to_vec()
        }),
        Source::Uv { projection } => {
            per_vertex(2, &|p| projection.uv(p, &start.bounds).to_array().to_vec())
        }
        Source::Attribute { path, name } => {
            let mut values = transfer(path, name, mesh)?;
            values.name = channel.name.clone();
            values
        }
    })
}
