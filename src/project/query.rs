//! Dispatcher of the two query kernels (`kernels/project.wgsl`, `kernels/closest_point.wgsl`):
//! each query on either backend, through its CPU twin in `cpu/` or its GPU host in `gpu/query.rs`.

use glam::Vec3;
use rayon::prelude::*;

use super::cpu::closest_point::closest_point_cpu;
use super::cpu::project::project_cpu;
use super::directions::directions;
use super::gpu::GpuQueries;
use super::options::absolute_distance;
use super::order::SpatialOrder;
use super::{Bvh, ProjectError, ProjectOptions};
use crate::compute::{Backend, kernel_time};
use crate::kernels::shared::{Correspondence, QueryParams};

/// Projects each source point along its normal onto the target (paper §4.2): casts the line
/// `p + t·n` both ways, keeps the hit with the least `|t|` within `options.max_distance`, and
/// reports the hit point, the target's interpolated normal there, the signed `t`, the triangle
/// and its barycentric weights. A hit whose normal is more than `options.max_angle_degrees`
/// from `n` is reported as [`Status::NormalMismatch`](super::Status::NormalMismatch).
///
/// Normals need not be unit (they are normalised; `t` is a distance). A point with a zero or
/// non-finite normal, or a non-finite point, is a miss. Queries run in the spatial order of
/// their points (see `order.rs`) and come back in the caller's order. Rays through shared edges and vertices
/// never slip through a closed target (watertight test, Woop et al. 2013).
pub fn project(
    backend: &Backend,
    bvh: &Bvh,
    points: &[Vec3],
    normals: &[Vec3],
    options: &ProjectOptions,
) -> Result<Vec<Correspondence>, ProjectError> {
    kernel_time::timed(|| match backend {
        Backend::Cpu => {
            let params = options.params(bvh.mean_edge_length())?;
            let directions = directions(points, normals)?;
            let order = SpatialOrder::new(points);
            let found = project_cpu(
                bvh,
                &order.permute(points),
                &order.permute(&directions),
                &params,
            );
            Ok(order.restore(&found))
        }
        Backend::Gpu(context) => {
            let job = GpuQueries::project(context, bvh, points, normals, options)?;
            job.dispatch(context, &bvh.on_gpu(context)?)?;
            Ok(job.read(context)?)
        }
    })
}

/// The nearest target surface point of each point, with `distance` = |p − point| signed by the
/// target's orientation (negative inside a closed, consistently oriented target), the
/// interpolated normal, triangle and barycentric weights. Points farther than `max_distance`
/// mean edge lengths from the target (`f32::INFINITY`: no limit), and non-finite points, are
/// misses.
pub fn closest_points(
    backend: &Backend,
    bvh: &Bvh,
    points: &[Vec3],
    max_distance: f32,
) -> Result<Vec<Correspondence>, ProjectError> {
    let mut found = kernel_time::timed(|| -> Result<_, ProjectError> {
        Ok(match backend {
            Backend::Cpu => {
                let params =
                    QueryParams::closest(absolute_distance(max_distance, bvh.mean_edge_length())?);
                let order = SpatialOrder::new(points);
                order.restore(&closest_point_cpu(bvh, &order.permute(points), &params))
            }
            Backend::Gpu(context) => {
                let job = GpuQueries::closest_points(context, bvh, points, max_distance)?;
                job.dispatch(context, &bvh.on_gpu(context)?)?;
                job.read(context)?
            }
        })
    })?;
    // WGSL gives no guarantee about NaN and infinity, so misses for unusable points are set here,
    // for both backends alike.
    found
        .par_iter_mut()
        .zip(points)
        .filter(|(_, p)| !p.is_finite())
        .for_each(|(c, _)| *c = Correspondence::MISS);
    Ok(found)
}
