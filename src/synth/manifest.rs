use super::frame::FrameTruth;
use serde::{Deserialize, Serialize};

/// `manifest.json` of a written sequence: the scene, how it was sampled, and each frame's file with
/// its ground truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub scene: String,
    pub description: String,
    /// Grid cells across the scene's longest side.
    pub resolution: usize,
    pub frame_count: usize,
    /// The extracted level of every field (inside is below it).
    pub iso: f32,
    /// Closest approach of any frame to a topology change, in grid cells.
    pub margin_cells: f32,
    /// World box holding the surface in every frame: `[min, max]`.
    pub bounds: [[f32; 3]; 2],
    pub frames: Vec<FrameRecord>,
}

/// One frame of a manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameRecord {
    /// File name within the sequence's directory.
    pub file: String,
    pub vertices: usize,
    pub triangles: usize,
    #[serde(flatten)]
    pub truth: FrameTruth,
}
