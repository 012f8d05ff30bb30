//! Correspondences for the registration energies: each deformed vertex's normal ray cast onto the
//! target (paper §4.2), through the projection module on the chosen backend.

use glam::{DVec3, Vec3};

use super::RegisterError;
use super::energy::FitTarget;
use super::model::Units;
use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::project::{Bvh, ProjectOptions, Status, closest_points, project};

/// A target surface sample paired with its nearest point on the deformed source (the fine stage's
/// cover term): the sample and the target's unit normal there (world coordinates), and the source
/// triangle with the barycentric weights of the nearest point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoverHit {
    pub point: Vec3,
    pub normal: Vec3,
    pub triangle: u32,
    pub barycentric: Vec3,
}

/// Finds target points for source points with normals (world coordinates).
pub trait Correspond {
    /// For each point, its target point and the target's unit normal there, or `None` when the ray
    /// misses within `max_distance` (in mean edge lengths of the target) or the normals differ by
    /// more than the pruning angle.
    fn correspond(
        &self,
        points: &[Vec3],
        normals: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<Option<(Vec3, Vec3)>>, RegisterError>;

    /// The target's mean edge length (the unit of `max_distance`).
    fn target_unit(&self) -> f32;

    /// For each target surface sample between `min_distance` and `max_distance` (mean edge
    /// lengths of `source`) from `source` (world coordinates) whose normal agrees with the
    /// source's at its nearest point within the pruning angle: that pair. The samples are the
    /// target triangles' centroids, with the target's vertex normals interpolated there.
    fn cover(
        &self,
        source: &IndexedMesh,
        min_distance: f32,
        max_distance: f32,
    ) -> Result<CoverPairs, RegisterError>;
}

/// What [`Correspond::cover`] found, and how many target samples it tried.
#[derive(Debug, Clone, PartialEq)]
pub struct CoverPairs {
    pub hits: Vec<CoverHit>,
    pub samples: usize,
}

/// Normal-ray projection onto a target's BVH.
pub struct Projector<'a> {
    pub backend: &'a Backend,
    pub bvh: &'a Bvh,
    pub max_angle_degrees: f32,
}

impl Correspond for Projector<'_> {
    fn correspond(
        &self,
        points: &[Vec3],
        normals: &[Vec3],
        max_distance: f32,
    ) -> Result<Vec<Option<(Vec3, Vec3)>>, RegisterError> {
        let options = ProjectOptions {
            max_angle_degrees: self.max_angle_degrees,
            max_distance,
        };
        let found = project(self.backend, self.bvh, points, normals, &options)
            .map_err(RegisterError::Correspondence)?;
        Ok(found
            .iter()
            .map(|c| (c.status() == Status::Accepted).then_some((c.point, c.normal)))
            .collect())
    }

    fn target_unit(&self) -> f32 {
        self.bvh.mean_edge_length()
    }

    fn cover(
        &self,
        source: &IndexedMesh,
        min_distance: f32,
        max_distance: f32,
    ) -> Result<CoverPairs, RegisterError> {
        let failed = RegisterError::Correspondence;
        let tree = Bvh::build(source).map_err(failed)?;
        let (points, normals): (Vec<Vec3>, Vec<Vec3>) = self
            .bvh
            .triangles()
            .iter()
            .zip(self.bvh.normals())
            .map(|(t, n)| {
                (
                    (t.a + t.b + t.c) / 3.0,
                    (n.a + n.b + n.c).normalize_or_zero(),
                )
            })
            .unzip();
        let found = closest_points(self.backend, &tree, &points, max_distance).map_err(failed)?;
        let min_cos = self.max_angle_degrees.to_radians().cos();
        let near = min_distance * tree.mean_edge_length();
        let hits = found
            .iter()
            .zip(points.iter().zip(&normals))
            .filter_map(|(c, (&point, &normal))| {
                let triangle = c.hit_triangle()?;
                let usable = normal != Vec3::ZERO && c.distance.abs() >= near;
                (usable && c.normal.dot(normal) >= min_cos).then_some(CoverHit {
                    point,
                    normal,
                    triangle,
                    barycentric: c.barycentric,
                })
            })
            .collect();
        Ok(CoverPairs {
            hits,
            samples: points.len(),
        })
    }
}

/// Targets of the solver-coordinate points `points` with normals `normals`, at most
/// `max_distance` source mean edge lengths away.
pub fn targets(
    correspond: &dyn Correspond,
    units: &Units,
    points: &[DVec3],
    normals: &[Vec3],
    max_distance: f64,
) -> Result<Vec<Option<FitTarget>>, RegisterError> {
    let world: Vec<Vec3> = points.iter().map(|&p| units.to_world(p)).collect();
    let relative = (max_distance * units.unit / f64::from(correspond.target_unit())) as f32;
    let found = correspond.correspond(&world, normals, relative)?;
    Ok(found
        .into_iter()
        .map(|hit| {
            hit.and_then(|(point, normal)| {
                let normal = normal.as_dvec3().normalize_or_zero();
                (normal != DVec3::ZERO).then(|| FitTarget {
                    point: units.to_local(point),
                    normal,
                })
            })
        })
        .collect())
}
