//! Closest-point transfer across a re-sampled patch (paper §4.4, sharpened).
//!
//! The paper gives a new patch vertex the average of its neighbours marched in from the patch's
//! boundary, and a deleted vertex likewise going backward. On a fluid, whose surface is
//! re-sampled somewhere every frame, those averages blur a texture a little more each time. Here
//! a vertex a patch creates takes its data from the surface the patch replaces at its closest
//! point — the barycentric combination of that triangle's corners — and a vertex the patch
//! deletes takes, going backward, the data of the new surface at its own closest point. Where the
//! new surface lies on the old one the values come back exactly; they blend only across one
//! triangle, never across the patch.

use std::borrow::Cow;
use std::cell::OnceCell;

use glam::Vec3;

use crate::compute::Backend;
use crate::mesh::IndexedMesh;
use crate::project::{Bvh, ProjectError, closest_points};

/// Triangles to take data from at closest points. Their tree is built by the first query, so a
/// topology step that re-samples nothing builds none, and its attempts share one.
pub(crate) struct Transfer<'a> {
    positions: &'a [Vec3],
    triangles: Cow<'a, [[u32; 3]]>,
    bvh: OnceCell<Option<Bvh>>,
}

impl<'a> Transfer<'a> {
    /// Over `triangles`, whose corners index `positions`; with no triangles every query answers
    /// nothing.
    pub fn new(positions: &'a [Vec3], triangles: impl Into<Cow<'a, [[u32; 3]]>>) -> Self {
        Self {
            positions,
            triangles: triangles.into(),
            bvh: OnceCell::new(),
        }
    }

    /// The triangles' tree, built the first time; none without triangles.
    fn tree(&self) -> Result<Option<&Bvh>, ProjectError> {
        if let Some(tree) = self.bvh.get() {
            return Ok(tree.as_ref());
        }
        let built = tree_of(self.positions, &self.triangles)?;
        Ok(self.bvh.get_or_init(|| built).as_ref())
    }

    /// Runs `meanwhile` on this thread while the tree, if not built yet, is built on the thread
    /// pool: a caller about to query overlaps the build with the work before its first query. A
    /// build that fails is left to that query, which then reports it.
    pub fn prepare_while<R>(&self, meanwhile: impl FnOnce() -> R) -> R {
        if self.bvh.get().is_some() {
            return meanwhile();
        }
        let (positions, triangles) = (self.positions, &*self.triangles);
        let mut built = None;
        let result = rayon::in_place_scope(|scope| {
            scope.spawn(|_| built = Some(tree_of(positions, triangles)));
            meanwhile()
        });
        if let Some(Ok(tree)) = built {
            self.bvh.get_or_init(|| tree);
        }
        result
    }

    /// For each of `points`, the corners of the nearest triangle with their barycentric weights at
    /// the closest point (corners of weight 0 left out; the weights sum to 1), or nothing when
    /// there are no triangles.
    pub fn terms(&self, points: &[Vec3]) -> Result<Vec<Vec<(u32, f32)>>, ProjectError> {
        let Some(bvh) = self.tree()? else {
            return Ok(vec![Vec::new(); points.len()]);
        };
        let hits = closest_points(&Backend::Cpu, bvh, points, f32::INFINITY)?;
        Ok(hits
            .iter()
            .map(|hit| match hit.hit_triangle() {
                Some(t) => self.triangles[t as usize]
                    .into_iter()
                    .zip(hit.barycentric.to_array())
                    .filter(|&(_, w)| w > 0.0)
                    .collect(),
                None => Vec::new(),
            })
            .collect())
    }
}

/// The tree of `triangles` over `positions`; none without triangles.
fn tree_of(positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<Option<Bvh>, ProjectError> {
    if triangles.is_empty() {
        return Ok(None);
    }
    Ok(Some(Bvh::build_unsigned(&IndexedMesh::new(
        positions.to_vec(),
        triangles.to_vec(),
    ))?))
}
