//! Synthetic incoherent sequences with known ground truth, for tests and demos.
//!
//! Each frame evaluates an analytic implicit field on a grid and extracts its surface with
//! [`marching_cubes`](crate::grid::marching_cubes), independently per frame and on a grid shifted by
//! a per-frame fraction of a cell, so consecutive frames share no triangulation, like independently
//! meshed simulation frames (the paper tracks marching-cubes reconstructions of a liquid's level
//! set, §5). What the analytic field tells is kept with each frame: the field itself, the rigid
//! motion where there is one, and the number of components and the genus the surface must have.

mod error;
mod field;
mod frame;
mod manifest;
mod scene;
mod scenes;
mod schedule;
mod transform;
mod write;

pub use error::SynthError;
pub use field::{Ball, Capsule, Field};
pub use frame::{Frame, FrameTruth, GridRecord, extract, generate, plan};
pub use manifest::{FrameRecord, Manifest};
pub use scene::Scene;
pub use scenes::MARGIN_CELLS;
pub use transform::RigidTransform;
pub use write::{MANIFEST_FILE, write_sequence};

/// Fewest grid cells across a scene's longest side: below this the scenes' smallest features
/// (droplets, the breaking bar) are not resolved with the margin the expected topology relies on.
pub const MIN_RESOLUTION: usize = 24;
pub const MAX_RESOLUTION: usize = 1024;
pub const MIN_FRAMES: usize = 2;
pub const MAX_FRAMES: usize = 100_000;

/// How finely and how long to sample a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SynthOptions {
    /// Grid cells across the scene's longest side.
    pub resolution: usize,
    /// Number of frames.
    pub frames: usize,
}

impl Default for SynthOptions {
    /// 80 cells across gives frames of about 5,000 (droplets, rigid) to 20,000 (morph) vertices;
    /// 32 frames show each scene's motion in steps of a fraction of its size.
    fn default() -> Self {
        Self {
            resolution: 80,
            frames: 32,
        }
    }
}

impl SynthOptions {
    pub fn check(&self) -> Result<(), SynthError> {
        if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&self.resolution) {
            return Err(SynthError::Resolution {
                got: self.resolution,
                min: MIN_RESOLUTION,
                max: MAX_RESOLUTION,
            });
        }
        if !(MIN_FRAMES..=MAX_FRAMES).contains(&self.frames) {
            return Err(SynthError::Frames {
                got: self.frames,
                min: MIN_FRAMES,
                max: MAX_FRAMES,
            });
        }
        Ok(())
    }
}
