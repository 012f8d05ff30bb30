//! Every kernel in `kernels/`, listed once with its bindings and its CPU twin (the pattern of
//! vello's `shaders.rs`): the GPU context builds pipelines and bind-group layouts from these
//! entries, and `tests/kernels_validate.rs` checks them against the WGSL files on disk, so a kernel
//! without an entry, an entry whose bindings drift from its shader, or a missing CPU twin fails a
//! test instead of a run.

use super::ComputeError;
use super::aabb::Aabb;
use crate::grid::{
    BandChunk, BandTile, DistanceParams, GridCrossing, LatticePoint, Nearest, TreeNode,
    TreeTriangle, TriangleBox, WindingRun,
};
use crate::project::{
    BvhNode, BvhTriangle, Correspondence, NormalTriple, PseudoNormals, QueryParams,
};

/// A WGSL file of declarations (structs, constants, functions) that kernels share.
///
/// WGSL has no imports, so a kernel's full source is its shared files concatenated in the order
/// the kernel lists them, followed by the kernel's own file. Shared files must be valid WGSL modules
/// on their own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SharedWgsl {
    /// Path relative to the crate root.
    pub path: &'static str,
    pub source: &'static str,
}

impl SharedWgsl {
    pub const AABB: SharedWgsl = SharedWgsl {
        path: "kernels/shared/aabb.wgsl",
        source: include_str!("../../kernels/shared/aabb.wgsl"),
    };

    pub const BVH: SharedWgsl = SharedWgsl {
        path: "kernels/shared/bvh.wgsl",
        source: include_str!("../../kernels/shared/bvh.wgsl"),
    };

    pub const LATTICE: SharedWgsl = SharedWgsl {
        path: "kernels/shared/lattice.wgsl",
        source: include_str!("../../kernels/shared/lattice.wgsl"),
    };

    pub const EXACT: SharedWgsl = SharedWgsl {
        path: "kernels/shared/exact.wgsl",
        source: include_str!("../../kernels/shared/exact.wgsl"),
    };

    pub const CROSSING: SharedWgsl = SharedWgsl {
        path: "kernels/shared/crossing.wgsl",
        source: include_str!("../../kernels/shared/crossing.wgsl"),
    };

    pub const DISTANCE: SharedWgsl = SharedWgsl {
        path: "kernels/shared/distance.wgsl",
        source: include_str!("../../kernels/shared/distance.wgsl"),
    };
}

/// Every shared WGSL file.
pub const SHARED: &[SharedWgsl] = &[
    SharedWgsl::AABB,
    SharedWgsl::BVH,
    SharedWgsl::LATTICE,
    SharedWgsl::EXACT,
    SharedWgsl::CROSSING,
    SharedWgsl::DISTANCE,
];

/// How a kernel accesses one of its storage buffers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    Read,
    ReadWrite,
}

/// One storage buffer of a kernel: `@group(0) @binding(i)` where `i` is its position in
/// [`KernelInfo::bindings`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Binding {
    /// The WGSL variable name.
    pub name: &'static str,
    pub access: Access,
}

/// A compute kernel and everything needed to run it and to find its CPU twin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KernelInfo {
    /// Key of the pipeline cache; also the file stem.
    pub name: &'static str,
    /// Path relative to the crate root.
    pub path: &'static str,
    pub source: &'static str,
    /// Shared declarations prepended to `source`, in order.
    pub shared: &'static [SharedWgsl],
    pub entry_point: &'static str,
    /// Must equal the shader's `@workgroup_size` (x only; kernels are 1-D).
    pub workgroup_size: u32,
    /// Storage buffers of bind group 0, binding `i` at index `i`.
    pub bindings: &'static [Binding],
    /// Path (relative to the crate root) of the Rust function with the same loop shape.
    pub cpu_twin: &'static str,
}

impl KernelInfo {
    /// The source handed to the shader compiler: shared declarations, then the kernel.
    pub fn full_source(&self) -> String {
        let mut full = String::new();
        for shared in self.shared {
            full.push_str(&format!("// ---- {} ----\n", shared.path));
            full.push_str(shared.source);
            full.push('\n');
        }
        full.push_str(&format!("// ---- {} ----\n", self.path));
        full.push_str(self.source);
        full
    }
}

/// Every kernel.
pub const KERNELS: &[KernelInfo] = &[
    KernelInfo {
        name: "triangle_bounds",
        path: "kernels/triangle_bounds.wgsl",
        source: include_str!("../../kernels/triangle_bounds.wgsl"),
        shared: &[SharedWgsl::AABB],
        entry_point: "main",
        workgroup_size: 64,
        bindings: &[
            Binding {
                name: "positions",
                access: Access::Read,
            },
            Binding {
                name: "triangles",
                access: Access::Read,
            },
            Binding {
                name: "bounds",
                access: Access::ReadWrite,
            },
        ],
        cpu_twin: "src/compute/triangle_bounds.rs",
    },
    KernelInfo {
        name: "project",
        path: "kernels/project.wgsl",
        source: include_str!("../../kernels/project.wgsl"),
        shared: &[SharedWgsl::BVH],
        entry_point: "main",
        workgroup_size: 64,
        bindings: &[
            Binding {
                name: "params",
                access: Access::Read,
            },
            Binding {
                name: "nodes",
                access: Access::Read,
            },
            Binding {
                name: "triangles",
                access: Access::Read,
            },
            Binding {
                name: "normals",
                access: Access::Read,
            },
            Binding {
                name: "points",
                access: Access::Read,
            },
            Binding {
                name: "directions",
                access: Access::Read,
            },
            Binding {
                name: "correspondences",
                access: Access::ReadWrite,
            },
        ],
        cpu_twin: "src/project/cpu/project.rs",
    },
    KernelInfo {
        name: "closest_point",
        path: "kernels/closest_point.wgsl",
        source: include_str!("../../kernels/closest_point.wgsl"),
        shared: &[SharedWgsl::BVH],
        entry_point: "main",
        workgroup_size: 64,
        bindings: &[
            Binding {
                name: "params",
                access: Access::Read,
            },
            Binding {
                name: "nodes",
                access: Access::Read,
            },
            Binding {
                name: "triangles",
                access: Access::Read,
            },
            Binding {
                name: "normals",
                access: Access::Read,
            },
            Binding {
                name: "pseudo_normals",
                access: Access::Read,
            },
            Binding {
                name: "points",
                access: Access::Read,
            },
            Binding {
                name: "correspondences",
                access: Access::ReadWrite,
            },
        ],
        cpu_twin: "src/project/cpu/closest_point.rs",
    },
    KernelInfo {
        name: "rasterize",
        path: "kernels/rasterize.wgsl",
        source: include_str!("../../kernels/rasterize.wgsl"),
        shared: &[SharedWgsl::LATTICE, SharedWgsl::EXACT, SharedWgsl::CROSSING],
        entry_point: "main",
        workgroup_size: 64,
        bindings: &[
            Binding {
                name: "points",
                access: Access::Read,
            },
            Binding {
                name: "triangles",
                access: Access::Read,
            },
            Binding {
                name: "offsets",
                access: Access::Read,
            },
            Binding {
                name: "crossings",
                access: Access::ReadWrite,
            },
            Binding {
                name: "count",
                access: Access::ReadWrite,
            },
        ],
        cpu_twin: "src/grid/rasterize.rs",
    },
    KernelInfo {
        name: "sweep",
        path: "kernels/sweep.wgsl",
        source: include_str!("../../kernels/sweep.wgsl"),
        shared: &[SharedWgsl::CROSSING],
        entry_point: "main",
        workgroup_size: 64,
        bindings: &[
            Binding {
                name: "crossings",
                access: Access::Read,
            },
            Binding {
                name: "starts",
                access: Access::Read,
            },
            Binding {
                name: "runs",
                access: Access::ReadWrite,
            },
        ],
        cpu_twin: "src/grid/sweep.rs",
    },
    KernelInfo {
        name: "distance",
        path: "kernels/distance.wgsl",
        source: include_str!("../../kernels/distance.wgsl"),
        shared: &[SharedWgsl::DISTANCE],
        entry_point: "main",
        workgroup_size: 64,
        bindings: &[
            Binding {
                name: "params",
                access: Access::Read,
            },
            Binding {
                name: "nodes",
                access: Access::Read,
            },
            Binding {
                name: "triangles",
                access: Access::Read,
            },
            Binding {
                name: "boxes",
                access: Access::Read,
            },
            Binding {
                name: "chunks",
                access: Access::Read,
            },
            Binding {
                name: "tiles",
                access: Access::Read,
            },
            Binding {
                name: "nearest",
                access: Access::ReadWrite,
            },
        ],
        cpu_twin: "src/grid/distance_cpu.rs",
    },
];

/// Looks a kernel up by name.
pub fn kernel(name: &str) -> Result<&'static KernelInfo, ComputeError> {
    KERNELS
        .iter()
        .find(|k| k.name == name)
        .ok_or_else(|| ComputeError::UnknownKernel(name.to_owned()))
}

/// The byte layout of a Rust struct that a shared WGSL file mirrors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpuStructLayout {
    /// The struct's name in both languages.
    pub name: &'static str,
    pub wgsl: &'static SharedWgsl,
    pub size: usize,
    /// Member names (as in WGSL) and byte offsets, in declaration order.
    pub members: &'static [(&'static str, usize)],
}

/// Every Rust struct mirrored in WGSL.
pub const GPU_STRUCTS: &[GpuStructLayout] = &[
    Aabb::LAYOUT,
    BvhNode::LAYOUT,
    BvhTriangle::LAYOUT,
    NormalTriple::LAYOUT,
    PseudoNormals::LAYOUT,
    Correspondence::LAYOUT,
    QueryParams::LAYOUT,
    LatticePoint::LAYOUT,
    GridCrossing::LAYOUT,
    WindingRun::LAYOUT,
    TreeNode::LAYOUT,
    TreeTriangle::LAYOUT,
    Nearest::LAYOUT,
    DistanceParams::LAYOUT,
    TriangleBox::LAYOUT,
    BandChunk::LAYOUT,
    BandTile::LAYOUT,
];
