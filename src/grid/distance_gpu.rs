//! The distance kernel's buffers: upload, dispatch and readback kept apart so each can be timed on
//! its own (see `benches/grid.rs`).

use bytemuck::{Pod, Zeroable};

use super::RasterError;
use super::distance::{BandChunk, Nearest};
use super::triangle_tree::TriangleTree;
use crate::compute::GpuContext;
use crate::compute::registry::{GpuStructLayout, SharedWgsl};

/// The tree's base cell and the band's squared half-width in cells.
///
/// Mirrors `struct DistanceParams` in `kernels/shared/distance.wgsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct DistanceParams {
    pub base: [i32; 3],
    pub bound: f32,
}

impl DistanceParams {
    /// The layout the WGSL mirror must have, checked against naga in `tests/kernels_validate.rs`.
    pub const LAYOUT: GpuStructLayout = GpuStructLayout {
        name: "DistanceParams",
        wgsl: &SharedWgsl::DISTANCE,
        size: size_of::<Self>(),
        members: &[
            ("base", core::mem::offset_of!(Self, base)),
            ("bound", core::mem::offset_of!(Self, bound)),
        ],
    };
}

/// A triangle tree and chunks of candidate corners uploaded for `kernels/distance.wgsl`.
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
    nearest: wgpu::Buffer,
    chunk_count: usize,
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
        let Some(last) = chunks.last() else {
            return Ok(Self { buffers: None });
        };
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
                nearest: context.output::<Nearest>("nearest", (last.out + last.len) as usize)?,
                chunk_count: chunks.len(),
                corner_count: (last.out + last.len) as usize,
            }),
        })
    }

    /// Submits the kernel; [`Self::read`] waits for it.
    pub fn dispatch(&self, context: &GpuContext) -> Result<(), RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(());
        };
        context.dispatch(
            "distance",
            &[
                &b.params,
                &b.nodes,
                &b.triangles,
                &b.boxes,
                &b.chunks,
                &b.nearest,
            ],
            b.chunk_count as u64,
        )?;
        Ok(())
    }

    /// The nearest triangle of every corner, chunk after chunk.
    pub fn read(&self, context: &GpuContext) -> Result<Vec<Nearest>, RasterError> {
        let Some(b) = &self.buffers else {
            return Ok(Vec::new());
        };
        Ok(context.read_back::<Nearest>(&b.nearest, b.corner_count)?)
    }
}
