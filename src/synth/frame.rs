use super::field::Field;
use super::scenes::shape;
use super::schedule::{frame_time, jitter};
use super::transform::RigidTransform;
use super::{Scene, SynthError, SynthOptions};
use crate::grid::{ScalarGrid, marching_cubes};
use crate::mesh::IndexedMesh;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Cells of padding between the scene's bounds and the grid's border.
const PADDING: usize = 2;

/// Where a frame's field was sampled: corner `(i, j, k)` at `origin + spacing · (i, j, k)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GridRecord {
    pub origin: [f32; 3],
    pub spacing: f32,
    /// Corner counts along x, y, z.
    pub dims: [usize; 3],
}

/// Everything known about a frame before its surface is extracted.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameTruth {
    pub index: usize,
    /// 0 at the first frame, 1 at the last.
    pub time: f32,
    pub grid: GridRecord,
    /// The surface is this field's zero set (negative inside).
    pub field: Field,
    /// Object-to-world motion of scenes that move rigidly (`blobs`, `rigid`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<RigidTransform>,
    /// Connected components the surface has.
    pub components: usize,
    /// Total genus of the surface (sum over components).
    pub genus: i64,
}

/// One generated frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub truth: FrameTruth,
    pub mesh: IndexedMesh,
}

/// The fields, grids and expected topology of every frame, without extracting any surface.
pub fn plan(scene: Scene, options: &SynthOptions) -> Result<Vec<FrameTruth>, SynthError> {
    options.check()?;
    let [lo, hi] = scene.bounds();
    let extent = hi - lo;
    let spacing = extent.max_element() / options.resolution as f32;
    let cells = (extent / spacing).ceil().to_array();
    let dims = cells.map(|c| c as usize + 1 + 2 * PADDING + 1);
    Ok((0..options.frames)
        .map(|index| {
            let shift = Vec3::from_array(jitter(index)) + Vec3::splat(PADDING as f32);
            let shape = shape(scene, index, options.frames, spacing);
            FrameTruth {
                index,
                time: frame_time(index, options.frames) as f32,
                grid: GridRecord {
                    origin: (lo - spacing * shift).to_array(),
                    spacing,
                    dims,
                },
                field: shape.field,
                transform: shape.transform,
                components: shape.components,
                genus: shape.genus,
            }
        })
        .collect())
}

/// The surface of one planned frame: its field sampled on its grid, then marching cubes.
pub fn extract(truth: &FrameTruth) -> Result<IndexedMesh, SynthError> {
    let grid = &truth.grid;
    let samples = ScalarGrid::from_fn(
        Vec3::from_array(grid.origin),
        grid.spacing,
        grid.dims,
        |p| truth.field.value(p),
    )?;
    Ok(marching_cubes(&samples, 0.0))
}

/// Every frame of a scene, extracted one at a time as the iterator advances, so memory holds one
/// frame whatever the sequence length.
pub fn generate(
    scene: Scene,
    options: &SynthOptions,
) -> Result<impl Iterator<Item = Result<Frame, SynthError>>, SynthError> {
    let truths = plan(scene, options)?;
    Ok(truths
        .into_iter()
        .map(|truth| extract(&truth).map(|mesh| Frame { truth, mesh })))
}
