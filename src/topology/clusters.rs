//! Clusters of grid cells and the Euler characteristic of a patch of triangles: how the steps that
//! re-sample a surface inside a set of cells tell a change of topology (a cluster whose
//! replacement changes χ) from a change of shape only (paper §4.3: only differences that change
//! the topology should re-sample the surface).

use rustc_hash::{FxHashMap, FxHashSet};

use super::keys::{Cell, NEIGHBOURS};
use crate::mesh::IndexedMesh;

/// The clusters of `cells` (sorted, without repeats): the groups of cells that touch
/// (26-neighbours), each sorted, numbered in the order of their first cell.
pub(crate) fn clusters(cells: &[Cell]) -> Vec<Vec<Cell>> {
    const NONE: u32 = u32::MAX;
    let mut label = vec![NONE; cells.len()];
    let mut count = 0;
    let index = |c: &Cell| cells.binary_search(c).ok();
    for start in 0..cells.len() {
        if label[start] != NONE {
            continue;
        }
        label[start] = count;
        let mut stack = vec![start];
        while let Some(i) = stack.pop() {
            let c = cells[i];
            for d in NEIGHBOURS {
                let n = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                if let Some(j) = index(&n).filter(|&j| label[j] == NONE) {
                    label[j] = count;
                    stack.push(j);
                }
            }
        }
        count += 1;
    }
    let mut members: Vec<Vec<Cell>> = vec![Vec::new(); count as usize];
    for (&c, &k) in cells.iter().zip(&label) {
        members[k as usize].push(c);
    }
    members
}

/// For every cell of the clusters `grown` (each a list of cells), the clusters holding it.
pub(crate) fn holders(grown: &[Vec<Cell>]) -> FxHashMap<Cell, Vec<u32>> {
    let mut out: FxHashMap<Cell, Vec<u32>> = FxHashMap::default();
    for (k, cells) in grown.iter().enumerate() {
        for &c in cells {
            out.entry(c).or_default().push(k as u32);
        }
    }
    out
}

/// For each of `count` clusters, the triangles of `triangles` (indices, in order) with a corner in
/// it; `of` gives the clusters holding a vertex.
pub(crate) fn touching<'a>(
    triangles: &[[u32; 3]],
    count: usize,
    of: impl Fn(u32) -> &'a [u32],
) -> Vec<Vec<u32>> {
    let mut out: Vec<Vec<u32>> = vec![Vec::new(); count];
    for (t, tri) in triangles.iter().enumerate() {
        // Most triangles of a surface touch no cluster at all.
        if tri.iter().all(|&v| of(v).is_empty()) {
            continue;
        }
        let mut touched: Vec<u32> = tri.iter().flat_map(|&v| of(v).iter().copied()).collect();
        touched.sort_unstable();
        touched.dedup();
        for k in touched {
            out[k as usize].push(t as u32);
        }
    }
    out
}

/// V − E + F of the triangles `triangles` of `mesh`, as a complex of their own.
pub(crate) fn euler(mesh: &IndexedMesh, triangles: &[u32]) -> i64 {
    let mut vertices: FxHashSet<u32> = FxHashSet::default();
    let mut edges: FxHashSet<(u32, u32)> = FxHashSet::default();
    for &t in triangles {
        let tri = mesh.triangles[t as usize];
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            vertices.insert(a);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    vertices.len() as i64 - edges.len() as i64 + triangles.len() as i64
}
