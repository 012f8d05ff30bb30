//! The query kernels' buffers: the BVH, uploaded once per target frame and kept on the device,
//! and each batch of queries, split into upload, dispatch and readback so each step can be timed
//! on its own (see `benches/project.rs`).

use std::sync::{Arc, Weak};

use glam::Vec3;

use super::options::{QueryParams, absolute_distance};
use super::order::SpatialOrder;
use super::query::directions;
use super::{Bvh, Correspondence, ProjectError, ProjectOptions};
use crate::compute::{ComputeError, GpuContext};

/// A BVH's arrays on one GPU.
#[derive(Debug, Clone)]
pub struct GpuBvh {
    nodes: wgpu::Buffer,
    triangles: wgpu::Buffer,
    normals: wgpu::Buffer,
    pseudo_normals: wgpu::Buffer,
}

impl GpuBvh {
    pub fn upload(context: &GpuContext, bvh: &Bvh) -> Result<Self, ComputeError> {
        Ok(Self {
            nodes: context.upload("bvh nodes", bvh.nodes())?,
            triangles: context.upload("bvh triangles", bvh.triangles())?,
            normals: context.upload("bvh normals", bvh.normals())?,
            pseudo_normals: context.upload("bvh pseudo-normals", bvh.pseudo_normals())?,
        })
    }
}

/// The upload a [`Bvh`] keeps for the context it was first queried on. The weak reference both
/// identifies the context and keeps its address from being reused while the upload lives.
#[derive(Debug)]
pub(super) struct Resident {
    context: Weak<GpuContext>,
    bvh: GpuBvh,
}

impl Bvh {
    /// This BVH on `context`'s device: uploaded on the first query there and kept; for any other
    /// context it is uploaded for the one query.
    pub(super) fn on_gpu(&self, context: &Arc<GpuContext>) -> Result<GpuBvh, ComputeError> {
        if let Some(resident) = self.resident.get() {
            if Weak::ptr_eq(&resident.context, &Arc::downgrade(context)) {
                return Ok(resident.bvh.clone());
            }
            return GpuBvh::upload(context, self);
        }
        let bvh = GpuBvh::upload(context, self)?;
        // Another thread may have stored its upload first; this one then serves only this query.
        let _ = self.resident.set(Resident {
            context: Arc::downgrade(context),
            bvh: bvh.clone(),
        });
        Ok(bvh)
    }
}

/// A batch of queries on the GPU, in chunks small enough for one storage binding each.
#[derive(Debug)]
pub struct GpuQueries {
    params: wgpu::Buffer,
    chunks: Vec<Chunk>,
    /// The queries are uploaded in spatial order (see `order.rs`) and read back in the caller's.
    order: SpatialOrder,
}

/// One run of consecutive queries and the correspondences the kernel writes for them.
#[derive(Debug)]
struct Chunk {
    points: wgpu::Buffer,
    /// Unit directions of a projection; `None` for closest points.
    directions: Option<wgpu::Buffer>,
    correspondences: wgpu::Buffer,
    count: usize,
}

impl GpuQueries {
    /// Uploads the projections of `points` along `normals` onto `bvh`'s target (see
    /// [`super::project`]).
    pub fn project(
        context: &GpuContext,
        bvh: &Bvh,
        points: &[Vec3],
        normals: &[Vec3],
        options: &ProjectOptions,
    ) -> Result<Self, ProjectError> {
        let params = options.params(bvh.mean_edge_length())?;
        let directions = directions(points, normals)?;
        let order = SpatialOrder::new(points);
        let (points, directions) = (order.permute(points), order.permute(&directions));
        Self::upload(context, &params, &points, Some(&directions), order)
    }

    /// Uploads the closest-point queries of `points` onto `bvh`'s target (see
    /// [`super::closest_points`]).
    pub fn closest_points(
        context: &GpuContext,
        bvh: &Bvh,
        points: &[Vec3],
        max_distance: f32,
    ) -> Result<Self, ProjectError> {
        let params = QueryParams::closest(absolute_distance(max_distance, bvh.mean_edge_length())?);
        let order = SpatialOrder::new(points);
        Self::upload(context, &params, &order.permute(points), None, order)
    }

    fn upload(
        context: &GpuContext,
        params: &QueryParams,
        points: &[Vec3],
        directions: Option<&[Vec3]>,
        order: SpatialOrder,
    ) -> Result<Self, ProjectError> {
        let chunk_len = context
            .max_binding_len::<Correspondence>()
            .min(context.max_binding_len::<Vec3>());
        let mut chunks = Vec::new();
        for (k, chunk) in points.chunks(chunk_len).enumerate() {
            let first = k * chunk_len;
            let directions = match directions {
                Some(all) => Some(context.upload("directions", &all[first..first + chunk.len()])?),
                None => None,
            };
            chunks.push(Chunk {
                points: context.upload("points", chunk)?,
                directions,
                correspondences: context
                    .output::<Correspondence>("correspondences", chunk.len())?,
                count: chunk.len(),
            });
        }
        Ok(Self {
            params: context.upload("query params", std::slice::from_ref(params))?,
            chunks,
            order,
        })
    }

    /// Submits the kernel over every chunk against `bvh`; [`Self::read`] or [`GpuContext::wait`]
    /// waits for it.
    pub fn dispatch(&self, context: &GpuContext, bvh: &GpuBvh) -> Result<(), ComputeError> {
        for chunk in &self.chunks {
            match &chunk.directions {
                Some(directions) => context.dispatch(
                    "project",
                    &[
                        &self.params,
                        &bvh.nodes,
                        &bvh.triangles,
                        &bvh.normals,
                        &chunk.points,
                        directions,
                        &chunk.correspondences,
                    ],
                    chunk.count as u64,
                )?,
                None => context.dispatch(
                    "closest_point",
                    &[
                        &self.params,
                        &bvh.nodes,
                        &bvh.triangles,
                        &bvh.normals,
                        &bvh.pseudo_normals,
                        &chunk.points,
                        &chunk.correspondences,
                    ],
                    chunk.count as u64,
                )?,
            }
        }
        Ok(())
    }

    /// The correspondences of all chunks, in the caller's query order.
    pub fn read(&self, context: &GpuContext) -> Result<Vec<Correspondence>, ComputeError> {
        let mut all = Vec::with_capacity(self.chunks.iter().map(|c| c.count).sum());
        for chunk in &self.chunks {
            all.extend(context.read_back::<Correspondence>(&chunk.correspondences, chunk.count)?);
        }
        Ok(self.order.restore(&all))
    }
}
