//! A BVH's arrays on one GPU, read by both query kernels.

use crate::compute::{ComputeError, GpuContext};
use crate::kernels::shared::{BvhNode, BvhTriangle, NormalTriple, PseudoNormals};

/// A BVH's arrays on one GPU (see `Bvh::upload`).
#[derive(Debug, Clone)]
pub struct GpuBvh {
    pub(in crate::project) nodes: wgpu::Buffer,
    pub(in crate::project) triangles: wgpu::Buffer,
    pub(in crate::project) normals: wgpu::Buffer,
    pub(in crate::project) pseudo_normals: wgpu::Buffer,
}

impl GpuBvh {
    pub(in crate::project) fn upload(
        context: &GpuContext,
        nodes: &[BvhNode],
        triangles: &[BvhTriangle],
        normals: &[NormalTriple],
        pseudo_normals: &[PseudoNormals],
    ) -> Result<Self, ComputeError> {
        Ok(Self {
            nodes: context.upload("bvh nodes", nodes)?,
            triangles: context.upload("bvh triangles", triangles)?,
            normals: context.upload("bvh normals", normals)?,
            pseudo_normals: context.upload("bvh pseudo-normals", pseudo_normals)?,
        })
    }
}
