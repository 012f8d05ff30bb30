//! The four vertices around an edge, which every local operation examines first.

use crate::mesh::{HalfEdgeId, Mesh, VertexId};

/// The edge of `h` from `a` to `b` and the opposite corners of its two faces: `(a, b, c)` on
/// `h`'s side, `(b, a, d)` on its twin's.
pub(super) fn diamond(mesh: &Mesh, h: HalfEdgeId) -> [VertexId; 4] {
    let t = mesh.twin(h);
    [
        mesh.origin(h),
        mesh.target(h),
        mesh.origin(mesh.prev(h)),
        mesh.origin(mesh.prev(t)),
    ]
}
