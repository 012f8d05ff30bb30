//! Growing the complex region until the cut can run along its boundary (thesis §3.4.4: "the complex
//! regions defined by the deep cells are grown until the boundary of the regions are non-complex").
//!
//! A face between a complex cell and a simple one is a *front face*, an edge with complex and simple
//! cells around it a *front edge*. The cut and the fill meet on them, so they must describe one
//! curve:
//!
//! * a front edge carries as many mesh crossings as Θ does (0 or 1), and where it is crossed the mesh
//!   and Θ agree on which end is inside, with the mesh's winding 0 or 1 at both ends;
//! * a front face is simple (see [`super::face_arcs`]) and its arcs pair its crossings as the
//!   marching-cubes face rule pairs Θ's (the same pairs, on an ambiguous face).
//!
//! Whenever a front face fails, the simple cell across it joins the region; whenever a front edge
//! fails, all four cells around it do. Both tests depend on the face or edge alone, so the result is
//! the least region containing the seeds that is closed under these two rules, whatever the order
//! of growth. Far from both surfaces every test passes, so growth stops.

use std::rc::Rc;

use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

use super::face_arcs::{Arc, face_arcs};
use super::field::Field;
use super::keys::{Cell, GridEdge, GridFace, cell_corner, cell_edge, cell_face, cell_neighbour};
use super::mesh_grid::MeshGrid;
use crate::grid::cube::{FACE_CORNERS, FACE_EDGES, face_segments};

/// Memoized front tests of faces and edges.
pub(crate) struct Checks<'g, 'm> {
    grid: &'g MeshGrid<'m>,
    field: &'g Field,
    faces: FxHashMap<GridFace, Option<Rc<Vec<Arc>>>>,
    edges: FxHashMap<GridEdge, bool>,
}

impl<'g, 'm> Checks<'g, 'm> {
    pub fn new(grid: &'g MeshGrid<'m>, field: &'g Field) -> Self {
        Self {
            grid,
            field,
            faces: FxHashMap::default(),
            edges: FxHashMap::default(),
        }
    }

    /// The arcs of a face that can be a front face; `None` when it cannot.
    pub fn face(&mut self, face: GridFace) -> Option<Rc<Vec<Arc>>> {
        if let Some(known) = self.faces.get(&face) {
            return known.clone();
        }
        let arcs = face_arcs(self.grid, &face)
            .filter(|arcs| pairs_follow_rule(self.field, &face, arcs))
            .map(Rc::new);
        self.faces.insert(face, arcs.clone());
        arcs
    }

    /// Whether an edge can be a front edge.
    pub fn edge(&mut self, edge: GridEdge) -> bool {
        if let Some(&known) = self.edges.get(&edge) {
            return known;
        }
        let fits = edge_fits(self.grid, self.field, edge);
        self.edges.insert(edge, fits);
        fits
    }

    /// Tests, in parallel, the faces and edges among these that are not known yet. Each test
    /// depends on its face or edge alone, so the memo holds the same answers whichever thread
    /// or order computed them.
    fn test_all(&mut self, mut faces: Vec<GridFace>, mut edges: Vec<GridEdge>) {
        let (grid, field) = (self.grid, self.field);
        faces.retain(|f| !self.faces.contains_key(f));
        faces.par_sort_unstable();
        faces.dedup();
        if !faces.is_empty() {
            grid.build_tables();
        }
        let tested: Vec<Option<Vec<Arc>>> = faces
            .par_iter()
            .map(|face| face_arcs(grid, face).filter(|arcs| pairs_follow_rule(field, face, arcs)))
            .collect();
        self.faces.extend(
            faces
                .into_iter()
                .zip(tested.into_iter().map(|a| a.map(Rc::new))),
        );
        edges.retain(|e| !self.edges.contains_key(e));
        edges.par_sort_unstable();
        edges.dedup();
        let fits: Vec<bool> = edges
            .par_iter()
            .map(|&edge| edge_fits(grid, field, edge))
            .collect();
        self.edges.extend(edges.into_iter().zip(fits));
    }
}

/// Whether the mesh and Θ agree on a grid edge (see the module docs).
pub(crate) fn edge_fits(grid: &MeshGrid, field: &Field, edge: GridEdge) -> bool {
    let crossings = grid.on_edge(edge);
    let [a, b] = edge.ends();
    let (in_a, in_b) = (field.inside(a), field.inside(b));
    if crossings.len() != usize::from(in_a != in_b) {
        return false;
    }
    match crossings {
        [c] => {
            let wa = grid.winding(edge.axis(), a);
            let wb = wa + c.sign();
            (0..=1).contains(&wa) && (0..=1).contains(&wb) && (wa == 1) == in_a && (wb == 1) == in_b
        }
        _ => true,
    }
}

/// Whether the arcs on a face join the same pairs of edges as the marching-cubes face rule applied
/// to Θ's corner signs.
pub(crate) fn pairs_follow_rule(field: &Field, face: &GridFace, arcs: &[Arc]) -> bool {
    // Seen from the cell above the face, the face is that cell's lower face `2 · axis`.
    let (cell, f) = (face.cell, 2 * face.axis());
    let inside = FACE_CORNERS[f].map(|c| field.inside(cell_corner(cell, c)));
    let segments = face_segments(inside);
    let segments = segments.as_slice();
    if segments.len() != arcs.len() {
        return false;
    }
    segments.iter().all(|s| {
        let pair = [FACE_EDGES[f][s.from], FACE_EDGES[f][s.to]].map(|e| cell_edge(cell, e));
        arcs.iter()
            .any(|a| a.ends == pair || a.ends == [pair[1], pair[0]])
    })
}

/// The least region containing `seeds` closed under the front rules (see the module docs).
///
/// Grown in waves: the faces and edges a wave of new cells needs are tested together, in
/// parallel, then the wave is applied in order. The region is the least closed one whatever the
/// order, so the waves change only how fast it is found.
pub(crate) fn grow(seeds: &[Cell], checks: &mut Checks) -> FxHashSet<Cell> {
    let mut region: FxHashSet<Cell> = seeds.iter().copied().collect();
    let mut queue: Vec<Cell> = seeds.to_vec();
    queue.sort_unstable();
    queue.dedup();
    while !queue.is_empty() {
        let wave = std::mem::take(&mut queue);
        let known = &region;
        let faces: Vec<GridFace> = wave
            .iter()
            .flat_map(|&cell| {
                (0..6)
                    .filter(move |&f| !known.contains(&cell_neighbour(cell, f)))
                    .map(move |f| cell_face(cell, f))
            })
            .collect();
        let edges: Vec<GridEdge> = wave
            .iter()
            .flat_map(|&cell| (0..12).map(move |e| cell_edge(cell, e)))
            .filter(|edge| edge.cells().iter().any(|c| !known.contains(c)))
            .collect();
        checks.test_all(faces, edges);
        for cell in wave {
            for f in 0..6 {
                let across = cell_neighbour(cell, f);
                if !region.contains(&across) && checks.face(cell_face(cell, f)).is_none() {
                    region.insert(across);
                    queue.push(across);
                }
            }
            for e in 0..12 {
                let edge = cell_edge(cell, e);
                let around = edge.cells();
                if around.iter().any(|c| !region.contains(c)) && !checks.edge(edge) {
                    for c in around {
                        if region.insert(c) {
                            queue.push(c);
                        }
                    }
                }
            }
        }
    }
    region
}
