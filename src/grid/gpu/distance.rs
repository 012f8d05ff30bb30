//! GPU host of `kernels/distance.wgsl`: its buffers, upload, dispatch and readback kept apart so each can be timed on
//! its own (see `benches/grid.rs`).

use crate::compute::GpuContext;
use crate::grid::RasterError;
use crate::grid::triangle_tree::TriangleTree;
use crate::kernels::DISTANCE;
use crate::kernels::shared::{BandChunk, BandTile, DistanceParams, Nearest};

/// A triangle tree and candidate corners uploaded for `kernels/distance.wgsl`, one chunk per tile.
///
/// The CPU twin shares one gather among the chunks of a 4 × 2 × 2 tile; on the GPU each chunk is
/// a tile of its own. That gives a GPU thousands more invocations to schedule, and it keeps every
/// invocation within lavapipe's bound on the loop iterations of one invocation (65 535 in all,
/// after which llvmpipe leaves the loops silently: a whole tile's corners against a full gather
/// passed that bound and lost their results). Each chunk gathers the triangles near its own box,
/// a subset of its tile's, so the nearest triangle found is the same.
#[derive(Debug)]
pub(crate) struct GpuDistance {
    buffers: Option<Buffers>,
}

#[derive(Debug)]
struct Buffers {
    params: wgpu::Buffer,
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    boxes: wgpu::Buffer,
    chunks: wgpu::Buffer,
    tiles: wgpu::Buffer,
    nearest: wgpu::Buffer,
    tile_count: usize,
    corner_count: usize,
}

impl GpuDistance {
    /// Uploads the tree and the chunks of candidate corners.
    pub(crate) fn upload(
        context: &GpuContext,
        tree: &TriangleTree,
        chunks: &[BandChunk],
        bound: f32,
    ) -> Result<Self, RasterError> {
        if chunks.is_empty() {
            return Ok(Self { buffers: None });
        }
        let tiles = (0..chunks.len())
            .map(|c| {
                let first = u32::try_from(c).map_err(|_| RasterError::TooManyItems(c))?;
                Ok(BandTile { first, count: 1 })
            })
            .collect::<Result<Vec<_>, RasterError>>()?;
        let corner_count = chunks.iter().map(|c| c.len as usize).sum();
        let params = DistanceParams {
            base: tree.base(),
            bound,
        };
        Ok(Self {
            buffers: Some(Buffers {
                params: context.upload("params", &[params])?,
                nodes: context.upload("nodes", tree.nodes())?,
                triangles: context.upload("triangles", tree.triangles())?,
                boxes: context.upload("boxes", tree.boxes())?,
                chunks: context.upload("chunks", chunks)?,
                tiles: context.upload("tiles", &tiles)?,
                nearest: context.output::<Nearest>("nearest", corner_count)?,
                tile_count: tiles.len(),
                corner_count,
            }),
        })
    }

    /// Submits the kernel; [`Self::read`] waits for it.
    pub fn dispatch(&self, context: &GpuContext) -> Result<(), RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(());
        };
        context.dispatch(
            &DISTANCE,
            &[
                &b.params,
                &b.nodes,
                &b.triangles,
                &b.boxes,
                &b.chunks,
                &b.tiles,
                &b.nearest,
            ],
            b.tile_count as u64,
        )?;
        Ok(())
    }

    /// The nearest triangle of every corner, at its chunk's output offset.
    pub fn read(&self, context: &GpuContext) -> Result<Vec<Nearest>, RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(Vec::new());
        };
        Ok(context.read_back::<Nearest>(&b.nearest, b.corner_count)?)
    }
}
