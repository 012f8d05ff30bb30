//! The scenes' motions and the topology each frame must have, derived from the analytic field.
//!
//! Where a scene passes through a topology change, frames are kept [`MARGIN_CELLS`] grid cells
//! away from it (gaps and overlaps at least that wide, features at least that thick), so the grid
//! resolves every frame's topology and the expected counts hold for every resolution allowed.

mod blobs;
mod droplets;
mod merge;
mod morph;
mod rigid;
mod split;

use super::Scene;
use super::field::Field;
use super::transform::RigidTransform;
use glam::Vec3;

/// Closest approach to a topology change, in grid cells.
pub const MARGIN_CELLS: f32 = 2.0;

/// One frame of a scene: its field and what is known about it.
pub(super) struct Shape {
    pub field: Field,
    pub transform: Option<RigidTransform>,
    pub components: usize,
    pub genus: i64,
}

impl Scene {
    /// World box `[min, max]` holding the scene's surface in every frame.
    pub fn bounds(self) -> [Vec3; 2] {
        match self {
            Scene::Blobs => blobs::BOUNDS,
            Scene::Merge => merge::BOUNDS,
            Scene::Split => split::BOUNDS,
            Scene::Droplets => droplets::BOUNDS,
            Scene::Morph => morph::BOUNDS,
            Scene::Rigid => rigid::BOUNDS,
        }
    }
}

/// Frame `index` of `frames`, for a grid of the given spacing.
pub(super) fn shape(scene: Scene, index: usize, frames: usize, spacing: f32) -> Shape {
    let margin = MARGIN_CELLS * spacing;
    match scene {
        Scene::Blobs => blobs::shape(index, frames),
        Scene::Merge => merge::shape(index, frames, margin),
        Scene::Split => split::shape(index, frames, margin),
        Scene::Droplets => droplets::shape(index, frames, margin),
        Scene::Morph => morph::shape(index, frames, margin),
        Scene::Rigid => rigid::shape(index, frames),
    }
}
