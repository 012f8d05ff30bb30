// The triangle tree of the narrow-band distance and its query records. Mirrored by the structs of
// src/kernels/shared/distance.rs; a test compares the layouts. Every member is an
// array of scalars or a scalar (4-byte aligned), so the host uploads its slices as they are.

// Interior node (count == 0): left child next, right child at `index`. Leaf: triangle slots
// `index .. index + count`. Box in cells from the tree's base cell.
struct TreeNode {
    min: array<f32, 3>,
    index: u32,
    max: array<f32, 3>,
    count: u32,
}

// A triangle's lowest cell, its mesh index, its corners as offsets from that cell in cells, and
// its plane: unit normal (zero when degenerate) and normal · a.
struct TreeTriangle {
    base: array<i32, 3>,
    id: u32,
    a: array<f32, 3>,
    b: array<f32, 3>,
    c: array<f32, 3>,
    normal: array<f32, 3>,
    offset: f32,
}

// Nearest triangle slot (NO_SLOT when none lies within the band) and squared distance in cells.
struct Nearest {
    distance_squared: f32,
    slot: u32,
}

// The tree's base cell and the squared half-width of the band, in cells.
struct DistanceParams {
    base: array<i32, 3>,
    bound: f32,
}

const NO_SLOT: u32 = 0xffffffffu;

// Entries of the traversal stack (`STACK_SIZE` in src/grid/triangle_tree.rs).
const TREE_STACK_SIZE: u32 = 40u;

// A triangle's box in cells from the tree's base cell, rounded outwards; in leaf order.
struct TriangleBox {
    min: array<f32, 3>,
    max: array<f32, 3>,
}

// Corners first + (i, 0, 0) for i < len, whose results go to nearest[out + i]: the part of one
// row of candidate corners that lies in one tile.
struct BandChunk {
    first: array<i32, 3>,
    len: u32,
    out: u32,
}

// The chunks first .. first + count (in tile order) of one tile, whose triangles are gathered once.
struct BandTile {
    first: u32,
    count: u32,
}

// Most triangles gathered for one tile (`GATHER_CAPACITY` in src/kernels/shared/distance.rs; the tiled variant,
// src/grid/cpu/distance_tiled.rs, gathers more).
const GATHER_CAPACITY: u32 = 256u;

// Allowance for rounding in the plane lower bound, in cells (`PLANE_SLACK` in src/kernels/shared/distance.rs).
const PLANE_SLACK: f32 = 1e-4;
