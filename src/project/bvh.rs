use std::sync::{Arc, OnceLock, Weak};

use rayon::prelude::*;

use super::build::{self, MAX_LEAF, STACK_SIZE};
use super::gpu::GpuBvh;
use super::shading::{Shading, mean_edge_length};
use super::{ProjectError, triangle_bounds};
use crate::compute::{Backend, ComputeError, GpuContext};
use crate::kernels::shared::{Aabb, BvhChild, BvhNode, BvhTriangle, NormalTriple, PseudoNormals};
use crate::mesh::{IndexedMesh, MeshError};

/// A bounding volume hierarchy over one target frame, with what the queries report at a hit.
///
/// Built on the CPU (binned SAH, see [`Bvh::build`]) once per target frame and read as it is by
/// both backends: the node array, the triangles in leaf order, and per triangle its vertex normals
/// and pseudo-normals. On a GPU backend the arrays are uploaded on first use and kept on the device
/// for every later query against this frame.
#[derive(Debug)]
pub struct Bvh {
    nodes: Vec<BvhNode>,
    triangles: Vec<BvhTriangle>,
    normals: Vec<NormalTriple>,
    pseudo: Vec<PseudoNormals>,
    mean_edge_length: f32,
    resident: OnceLock<Resident>,
}

impl Bvh {
    /// Builds the BVH of a target mesh.
    ///
    /// The mesh needs at least one triangle, indices in range and finite coordinates; it need not
    /// be closed, though closest-point signs are only meaningful for a closed, consistently oriented
    /// mesh.
    pub fn build(mesh: &IndexedMesh) -> Result<Bvh, ProjectError> {
        Self::build_with(mesh, Normals::Shaded)
    }

    /// Builds the BVH of a mesh that is only measured against: the same tree, so queries find
    /// the same nearest triangles, points and weights at the same distances (up to sign) as with
    /// [`Bvh::build`], without the vertex normals and pseudo-normals: a fifth of a build's time
    /// (`cargo bench --bench project -- project/build`). Signs of distances then mean nothing
    /// (the edge and corner pseudo-normals that decide them are zero) and interpolated normals
    /// are zero. For the queries that ask only how far one surface lies from another or which
    /// triangle is nearest: the sub-grid match's distance bounds (several per frame on torn fluid
    /// frames), the data transfer of topology patches and of `propagate`, and `eval`.
    pub fn build_unsigned(mesh: &IndexedMesh) -> Result<Bvh, ProjectError> {
        Self::build_with(mesh, Normals::None)
    }

    fn build_with(mesh: &IndexedMesh, normals: Normals) -> Result<Bvh, ProjectError> {
        let boxes = checked_bounds(mesh)?;
        let (tree, shading) = rayon::join(
            || build::build(&boxes),
            || match normals {
                Normals::Shaded => Beside::Shading(Shading::new(mesh)),
                Normals::None => Beside::MeanEdgeLength(mean_edge_length(mesh)),
            },
        );
        let triangles = tree
            .order
            .par_iter()
            .map(|&t| {
                let corners = mesh.triangles[t as usize].map(|v| mesh.positions[v as usize]);
                BvhTriangle::new(corners, t)
            })
            .collect();
        let (normals, pseudo, mean_edge_length) = match shading {
            Beside::Shading(shading) => {
                let (normals, pseudo) = shading.in_leaf_order(mesh, &tree.order);
                (normals, pseudo, shading.mean_edge_length)
            }
            Beside::MeanEdgeLength(mean_edge_length) => {
                let slots = tree.order.len();
                (
                    vec![bytemuck::Zeroable::zeroed(); slots],
                    vec![bytemuck::Zeroable::zeroed(); slots],
                    mean_edge_length,
                )
            }
        };
        Ok(Bvh {
            nodes: tree.nodes,
            triangles,
            normals,
            pseudo,
            mean_edge_length,
            resident: OnceLock::new(),
        })
    }

    /// The 4-wide nodes, root first.
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// The triangles in leaf order: a leaf child holds slots `first .. first + count`.
    pub fn triangles(&self) -> &[BvhTriangle] {
        &self.triangles
    }

    /// Per leaf slot, the target's vertex normals at the triangle's corners.
    pub fn normals(&self) -> &[NormalTriple] {
        &self.normals
    }

    /// Per leaf slot, the triangle's corner and edge pseudo-normals.
    pub fn pseudo_normals(&self) -> &[PseudoNormals] {
        &self.pseudo
    }

    /// The target's mean edge length: the unit of every relative distance in the queries.
    pub fn mean_edge_length(&self) -> f32 {
        self.mean_edge_length
    }

    /// Levels of nodes below the root (0 when the root is the only node). A traversal keeps at
    /// most three entries per level, so `3 · (depth + 1)` never exceeds [`Bvh::STACK_SIZE`].
    pub fn depth(&self) -> usize {
        let mut deepest = 0;
        let mut pending = vec![(0usize, 0usize)];
        while let Some((n, depth)) = pending.pop() {
            deepest = deepest.max(depth);
            for (_, child) in self.nodes[n].children() {
                if let BvhChild::Node { index } = child {
                    pending.push((index as usize, depth + 1));
                }
            }
        }
        deepest
    }

    /// Entries the traversal stacks hold (`STACK_SIZE` in `kernels/shared/bvh.wgsl`).
    pub const STACK_SIZE: usize = STACK_SIZE;

    /// Most triangles in one leaf.
    pub const MAX_LEAF_TRIANGLES: usize = MAX_LEAF;
}

/// The box of every triangle of `mesh`, once it is known to have at least one triangle, fewer
/// than `u32::MAX`, indices in range and finite coordinates: what every surface the queries
/// search must have.
pub(super) fn checked_bounds(mesh: &IndexedMesh) -> Result<Vec<Aabb>, ProjectError> {
    if mesh.triangles.is_empty() {
        return Err(ProjectError::Target(MeshError::Empty));
    }
    if mesh.triangles.len() >= u32::MAX as usize {
        return Err(ProjectError::TooManyTriangles {
            triangles: mesh.triangles.len(),
            max: u32::MAX as usize - 1,
        });
    }
    if let Some((vertex, p)) = mesh
        .positions
        .par_iter()
        .enumerate()
        .find_first(|(_, p)| !p.is_finite())
    {
        return Err(ProjectError::Target(MeshError::NonFiniteCoordinate {
            vertex,
            position: p.to_array(),
        }));
    }
    triangle_bounds(&Backend::Cpu, &mesh.positions, &mesh.triangles).map_err(|e| match e {
        ComputeError::IndexOutOfRange {
            triangle,
            vertex,
            count,
        } => ProjectError::Target(MeshError::IndexOutOfRange {
            triangle,
            vertex,
            count,
        }),
        other => ProjectError::Compute(other),
    })
}

/// Whether a build computes the normals that sign distances and shade hits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Normals {
    Shaded,
    None,
}

/// What a build computes beside the tree: the shading, or (without normals) only the mean edge
/// length the queries measure in.
enum Beside {
    Shading(Shading),
    MeanEdgeLength(f32),
}

/// The upload a [`Bvh`] keeps for the context it was first queried on. The weak reference both
/// identifies the context and keeps its address from being reused while the upload lives.
#[derive(Debug)]
struct Resident {
    context: Weak<GpuContext>,
    bvh: GpuBvh,
}

impl Bvh {
    /// This BVH's arrays on `context`'s device.
    pub fn upload(&self, context: &GpuContext) -> Result<GpuBvh, ComputeError> {
        GpuBvh::upload(
            context,
            &self.nodes,
            &self.triangles,
            &self.normals,
            &self.pseudo,
        )
    }

    /// This BVH on `context`'s device: uploaded on the first query there and kept; for any other
    /// context it is uploaded for the one query.
    pub(super) fn on_gpu(&self, context: &Arc<GpuContext>) -> Result<GpuBvh, ComputeError> {
        if let Some(resident) = self.resident.get() {
            if Weak::ptr_eq(&resident.context, &Arc::downgrade(context)) {
                return Ok(resident.bvh.clone());
            }
            return self.upload(context);
        }
        let bvh = self.upload(context)?;
        // Another thread may have stored its upload first; this one then serves only this query.
        let _ = self.resident.set(Resident {
            context: Arc::downgrade(context),
            bvh: bvh.clone(),
        });
        Ok(bvh)
    }
}
