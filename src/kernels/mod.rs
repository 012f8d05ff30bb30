//! Every kernel in `kernels/`, listed once with its bindings and its CPU twin (the pattern of
//! vello's `shaders.rs`), and the Rust mirrors of the structs in `kernels/shared/` ([`shared`]).
//!
//! This module sits between the GPU context (`crate::compute`, which runs whatever kernel it is
//! handed) and the stages (which hand it one of these entries): it imports no stage, and no stage
//! defines a GPU struct. `tests/kernels_validate.rs` checks the entries against the WGSL files on
//! disk, so a kernel without an entry, an entry whose bindings drift from its shader, or a missing
//! CPU twin fails a test instead of a run.
//!
//! Each stage has the same shape: a dispatcher (`<stage>.rs`, choosing the backend), its CPU twin
//! (`cpu/<kernel>.rs`, the kernel's loop structure and names) and its GPU host (`gpu/<kernel>.rs`,
//! upload, dispatch and readback).

pub mod shared;

use crate::compute::{Access, Binding, GpuStructLayout, KernelInfo, SharedWgsl};

/// A [`KernelInfo`] for `kernels/<name>.wgsl`, whose entry point is `main` with 64 threads per
/// workgroup and whose CPU twin is `src/<stage>/cpu/<name>.rs`, from its shared files and its
/// bindings in binding order.
macro_rules! kernel {
    ($stage:literal, $name:literal, [$($shared:ident),*], [$($access:ident $binding:ident),* $(,)?]) => {
        KernelInfo {
            name: $name,
            path: concat!("kernels/", $name, ".wgsl"),
            source: include_str!(concat!("../../kernels/", $name, ".wgsl")),
            shared: &[$(SharedWgsl::$shared),*],
            entry_point: "main",
            workgroup_size: 64,
            bindings: &[$(Binding { name: stringify!($binding), access: kernel!(@$access) }),*],
            cpu_twin: concat!("src/", $stage, "/cpu/", $name, ".rs"),
        }
    };
    (@read) => { Access::Read };
    (@write) => { Access::ReadWrite };
}

/// `kernels/shared/<name>.wgsl`.
macro_rules! shared_wgsl {
    ($name:literal) => {
        SharedWgsl {
            path: concat!("kernels/shared/", $name, ".wgsl"),
            source: include_str!(concat!("../../kernels/shared/", $name, ".wgsl")),
        }
    };
}

impl SharedWgsl {
    pub const AABB: SharedWgsl = shared_wgsl!("aabb");
    pub const BVH: SharedWgsl = shared_wgsl!("bvh");
    pub const LATTICE: SharedWgsl = shared_wgsl!("lattice");
    pub const EXACT: SharedWgsl = shared_wgsl!("exact");
    pub const CROSSING: SharedWgsl = shared_wgsl!("crossing");
    pub const DISTANCE: SharedWgsl = shared_wgsl!("distance");
    pub const FINE: SharedWgsl = shared_wgsl!("fine");
}

/// Every shared WGSL file.
pub const SHARED: &[SharedWgsl] = &[
    SharedWgsl::AABB,
    SharedWgsl::BVH,
    SharedWgsl::LATTICE,
    SharedWgsl::EXACT,
    SharedWgsl::CROSSING,
    SharedWgsl::DISTANCE,
    SharedWgsl::FINE,
];

/// Per triangle, its bounding box: the leaves of the BVH.
pub const TRIANGLE_BOUNDS: KernelInfo = kernel!("project", "triangle_bounds", [AABB],
    [read positions, read triangles, write bounds]);

/// Per point, the nearest hit of its normal line on the target.
pub const PROJECT: KernelInfo = kernel!("project", "project", [BVH], [read params, read nodes,
    read triangles, read normals, read points, read directions, write correspondences]);

/// Per point, the nearest point of the target with its signed distance.
pub const CLOSEST_POINT: KernelInfo = kernel!("project", "closest_point", [BVH], [read params,
    read nodes, read triangles, read normals, read pseudo_normals, read points,
    write correspondences]);

/// Per candidate grid line, the crossing of a triangle with a grid edge.
pub const RASTERIZE: KernelInfo = kernel!("grid", "rasterize", [LATTICE, EXACT, CROSSING],
    [read points, read triangles, read offsets, write crossings, write count]);

/// Per grid line, the winding runs of its sorted crossings.
pub const SWEEP: KernelInfo = kernel!("grid", "sweep", [CROSSING],
    [read crossings, read starts, write runs]);

/// Per tile of band corners, the nearest triangle of each corner.
pub const DISTANCE: KernelInfo = kernel!("grid", "distance", [DISTANCE], [read params, read nodes,
    read triangles, read boxes, read chunks, read tiles, write nearest]);

/// Per vertex of the fine stage, its fit matrix, right-hand side, preconditioner block and `|b_v|²`.
pub const FINE_SYSTEM: KernelInfo = kernel!("register", "fine_system", [FINE], [read params,
    read start, read targets, read offsets, read directions, read cover_offsets,
    read cover_entries, read cover_weights, read cover_matrices, read cover_pulls, write fit,
    write b, write preconditioner, write terms]);

/// Per cover pair, its matrix times the blend of its three vertices' values.
pub const FINE_COVER: KernelInfo = kernel!("register", "fine_cover", [FINE], [read params,
    read state, read corners, read weights, read matrices, read x, write moved]);

/// Per vertex, the fine system's matrix times a vector, and that product's term of `xᵀAx`.
pub const FINE_APPLY: KernelInfo = kernel!("register", "fine_apply", [FINE], [read params,
    read state, read fit, read offsets, read neighbours, read directions, read cover_offsets,
    read cover_entries, read cover_weights, read moved, read x, write out, write terms]);

/// Per chunk of vertices, the in-order sums of their two terms.
pub const FINE_REDUCE: KernelInfo = kernel!("register", "fine_reduce", [FINE], [read params,
    read terms, write partials]);

/// One invocation: a conjugate-gradient step's scalars from the chunk sums.
pub const FINE_SCALARS: KernelInfo = kernel!("register", "fine_scalars", [FINE], [read params,
    read phase, read partials, write state]);

/// Per vertex, the first residual, preconditioned residual and direction of a solve.
pub const FINE_START: KernelInfo = kernel!("register", "fine_start", [FINE], [read params,
    read state, read b, read preconditioner, read ad, write d, write r, write z, write p,
    write terms]);

/// Per vertex, a conjugate-gradient step of the solution and the residuals.
pub const FINE_UPDATE: KernelInfo = kernel!("register", "fine_update", [FINE], [read params,
    read state, read p, read ad, read preconditioner, write d, write r, write z, write terms]);

/// Per vertex, the next search direction.
pub const FINE_DIRECTION: KernelInfo = kernel!("register", "fine_direction", [FINE],
    [read params, read state, read z, write p]);

/// Every kernel.
pub const KERNELS: &[KernelInfo] = &[
    TRIANGLE_BOUNDS,
    PROJECT,
    CLOSEST_POINT,
    RASTERIZE,
    SWEEP,
    DISTANCE,
    FINE_SYSTEM,
    FINE_COVER,
    FINE_APPLY,
    FINE_REDUCE,
    FINE_SCALARS,
    FINE_START,
    FINE_UPDATE,
    FINE_DIRECTION,
];

/// Every Rust struct mirrored in WGSL.
pub const GPU_STRUCTS: &[GpuStructLayout] = &[
    shared::Aabb::LAYOUT,
    shared::BvhNode::LAYOUT,
    shared::BvhTriangle::LAYOUT,
    shared::NormalTriple::LAYOUT,
    shared::PseudoNormals::LAYOUT,
    shared::Correspondence::LAYOUT,
    shared::QueryParams::LAYOUT,
    shared::LatticePoint::LAYOUT,
    shared::GridCrossing::LAYOUT,
    shared::WindingRun::LAYOUT,
    shared::TreeNode::LAYOUT,
    shared::TreeTriangle::LAYOUT,
    shared::Nearest::LAYOUT,
    shared::DistanceParams::LAYOUT,
    shared::TriangleBox::LAYOUT,
    shared::BandChunk::LAYOUT,
    shared::BandTile::LAYOUT,
    shared::FineParams::LAYOUT,
    shared::CgState::LAYOUT,
    shared::FineTarget::LAYOUT,
];
