//! Where the mesh meets one cell face: the face graph of the design note (§2 step 5), built from the
//! rasterizer's grid-edge crossings ("type 1" points on the face's edges) and the pierce points of
//! mesh edges ("type 2" points inside the face), joined by the segments each triangle cuts across the
//! face.
//!
//! A face the cut can run along is *simple*: each of its edges carries at most one crossing, every
//! triangle meets it in exactly one segment, and the segments chain into arcs from one edge crossing
//! to another with no closed loop (Wojtan et al. 2009's complex face, thesis §3.4.4).

use super::keys::{GridEdge, GridFace};
use super::mesh_grid::MeshGrid;
use super::points::Point;

/// One arc of the mesh across a face: from the crossing on `ends[0]` through pierce points to the
/// crossing on `ends[1]`; segment `i` (from `points[i]` to `points[i + 1]`) lies in triangle
/// `triangles[i]`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Arc {
    pub ends: [GridEdge; 2],
    pub points: Vec<Point>,
    pub triangles: Vec<u32>,
}

/// The mesh on one face: the arcs of a simple face (none when the mesh misses it), or `None` for a
/// complex face.
pub(crate) fn face_arcs(grid: &MeshGrid, face: &GridFace) -> Option<Vec<Arc>> {
    let mut ends: Vec<(u32, Point)> = Vec::new();
    for edge in face.edges() {
        match grid.on_edge(edge) {
            [] => {}
            [c] => ends.push((
                c.triangle,
                Point::Crossing {
                    triangle: c.triangle,
                    edge,
                },
            )),
            _ => return None,
        }
    }
    let crossings = ends.len();
    for e in grid.pierced(face) {
        let point = Point::Pierce {
            edge: e,
            axis: face.axis,
            plane: face.plane(),
        };
        for t in grid.edges().tris[e as usize] {
            ends.push((t, point));
        }
    }
    if ends.is_empty() {
        return Some(Vec::new());
    }
    ends.sort_unstable();
    // One segment per triangle: exactly two of its points lie on the face.
    let mut segments: Vec<(u32, [Point; 2])> = Vec::with_capacity(ends.len() / 2);
    for group in ends.chunk_by(|x, y| x.0 == y.0) {
        let [a, b] = group else { return None };
        segments.push((a.0, [a.1, b.1]));
    }
    let mut used = vec![false; segments.len()];
    let mut starts: Vec<(GridEdge, Point)> = segments
        .iter()
        .flat_map(|(_, p)| *p)
        .filter_map(|p| match p {
            Point::Crossing { edge, .. } => Some((edge, p)),
            _ => None,
        })
        .collect();
    starts.sort_unstable();
    if starts.len() != crossings {
        return None;
    }
    let mut arcs: Vec<Arc> = Vec::new();
    for (start_edge, start) in starts {
        if arcs.iter().any(|a| a.ends[1] == start_edge) {
            continue;
        }
        let mut points = vec![start];
        let mut triangles = Vec::new();
        let mut at = start;
        let end_edge = loop {
            let s = (0..segments.len()).find(|&s| !used[s] && segments[s].1.contains(&at))?;
            used[s] = true;
            let (t, [p, q]) = segments[s];
            at = if p == at { q } else { p };
            points.push(at);
            triangles.push(t);
            if let Point::Crossing { edge, .. } = at {
                break edge;
            }
        };
        arcs.push(Arc {
            ends: [start_edge, end_edge],
            points,
            triangles,
        });
    }
    // A segment left over belongs to a closed loop on the face.
    used.iter().all(|&u| u).then_some(arcs)
}
