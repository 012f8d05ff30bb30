//! GPU host of `kernels/project.wgsl` and `kernels/closest_point.wgsl`: each batch of queries,
//! split into upload, dispatch and readback so each step can be timed on its own (see
//! `benches/project.rs`). The BVH they traverse is uploaded once per target frame ([`GpuBvh`]).

use glam::Vec3;

use super::GpuBvh;
use crate::compute::{ComputeError, GpuContext};
use crate::kernels::shared::{Correspondence, QueryParams};
use crate::kernels::{CLOSEST_POINT, PROJECT};
use crate::project::directions::directions;
use crate::project::options::absolute_distance;
use crate::project::order::SpatialOrder;
use crate::project::{Bvh, ProjectError, ProjectOptions};

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
    /// [`crate::project::project`]).
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
    /// [`crate::project::closest_points`]).
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
                    &PROJECT,
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
                    &CLOSEST_POINT,
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
