//! Mirrors of `kernels/shared/distance.wgsl`: the triangle tree over a lattice mesh, the band's
//! chunks and tiles of candidate corners, and the nearest triangle found for each.

/// Most triangles one invocation gathers for a tile (`GATHER_CAPACITY` in
/// `kernels/shared/distance.wgsl`); a tile near more searches the tree once per corner.
pub const GATHER_CAPACITY: usize = 256;

/// Allowance for rounding in the plane distance, in cells: the bounds only prune, so making them
/// smaller can cost time but never the nearest triangle (`PLANE_SLACK` in
/// `kernels/shared/distance.wgsl`).
pub const PLANE_SLACK: f32 = 1e-4;

gpu_struct! {
    mirrors DISTANCE;
    /// The nearest triangle slot of one corner and its squared distance in cells; `slot` is
    /// [`Nearest::NONE`] when no triangle lies within the band.
    ///
    /// Mirrors `struct Nearest` in `kernels/shared/distance.wgsl`.
    pub struct Nearest {
        pub distance_squared: f32,
        pub slot: u32,
    }
}

impl Nearest {
    pub const NONE: u32 = u32::MAX;
}

gpu_struct! {
    mirrors DISTANCE;
    /// The tree's base cell and the band's squared half-width in cells.
    ///
    /// Mirrors `struct DistanceParams` in `kernels/shared/distance.wgsl`.
    pub struct DistanceParams {
        pub base: [i32; 3],
        pub bound: f32,
    }
}

gpu_struct! {
    mirrors DISTANCE;
    /// Corners `first + (i, 0, 0)` for `i < len`, whose results go to `out + i`: the part of one row of
    /// candidate corners that lies in one tile.
    ///
    /// Mirrors `struct BandChunk` in `kernels/shared/distance.wgsl`.
    #[derive(Eq)]
    pub struct BandChunk {
        pub first: [i32; 3],
        pub len: u32,
        pub out: u32,
    }
}

gpu_struct! {
    mirrors DISTANCE;
    /// The chunks `first .. first + count` (in tile order) of one tile: up to a chunk's length ×
    /// `TILE_ROWS` × `TILE_ROWS` candidate corners whose triangles are gathered once.
    ///
    /// Mirrors `struct BandTile` in `kernels/shared/distance.wgsl`.
    #[derive(Eq)]
    pub struct BandTile {
        pub first: u32,
        pub count: u32,
    }
}

gpu_struct! {
    mirrors DISTANCE;
    /// A node: interior (`count == 0`) with its left child next and its right child at `index`, or a
    /// leaf holding triangle slots `index .. index + count`. Box in cells from the tree's base cell.
    ///
    /// Mirrors `struct TreeNode` in `kernels/shared/distance.wgsl`.
    pub struct TreeNode {
        pub min: [f32; 3],
        pub index: u32,
        pub max: [f32; 3],
        pub count: u32,
    }
}

gpu_struct! {
    mirrors DISTANCE;
    /// A triangle in leaf order: its lowest cell, its index in the mesh, its corners as offsets from
    /// that cell in cells, and its plane: unit normal (zero when degenerate) and `normal · a`. The
    /// distance to the plane is a lower bound of the distance to the triangle, and often a tight one.
    ///
    /// Mirrors `struct TreeTriangle` in `kernels/shared/distance.wgsl`.
    pub struct TreeTriangle {
        pub base: [i32; 3],
        pub id: u32,
        pub a: [f32; 3],
        pub b: [f32; 3],
        pub c: [f32; 3],
        pub normal: [f32; 3],
        pub offset: f32,
    }
}

gpu_struct! {
    mirrors DISTANCE;
    /// A triangle's bounding box in cells from the tree's base cell, rounded outwards; in leaf order.
    ///
    /// Mirrors `struct TriangleBox` in `kernels/shared/distance.wgsl`.
    pub struct TriangleBox {
        pub min: [f32; 3],
        pub max: [f32; 3],
    }
}
