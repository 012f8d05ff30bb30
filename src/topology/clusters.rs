//! Clusters of grid cells and the Euler characteristic of a patch of triangles: how the steps that
//! re-sample a surface inside a set of cells tell a change of topology (a cluster whose
//! replacement changes χ) from a change of shape only (paper §4.3: only differences that change
//! the topology should re-sample the surface).

use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};

use super::keys::{Cell, NEIGHBOURS};
use crate::mesh::IndexedMesh;

/// The clusters of `cells` (sorted, without repeats): the groups of cells that touch
/// (26-neighbours), each sorted, numbered in the order of their first cell.
pub(crate) fn clusters(cells: &[Cell]) -> Vec<Vec<Cell>> {
    Adjacent::of(cells).clusters(|_| true)
}

/// Which cells of a set touch which (26-neighbours): looked up once, so the clusters of each of
/// the many subsets a cluster is cut into (`subgrid::seeds`) are found without searching again.
pub(crate) struct Adjacent<'a> {
    cells: &'a [Cell],
    /// The neighbours (indices into `cells`) of cell `i`: `next[first[i]..first[i + 1]]`.
    first: Vec<u32>,
    next: Vec<u32>,
}

impl<'a> Adjacent<'a> {
    /// The adjacency of `cells` (sorted, without repeats).
    pub fn of(cells: &'a [Cell]) -> Self {
        let mut first = Vec::with_capacity(cells.len() + 1);
        let mut next = Vec::new();
        for c in cells {
            first.push(next.len() as u32);
            for d in NEIGHBOURS.iter().filter(|d| **d != [0, 0, 0]) {
                let n = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                if let Ok(j) = cells.binary_search(&n) {
                    next.push(j as u32);
                }
            }
        }
        first.push(next.len() as u32);
        Self { cells, first, next }
    }

    /// The clusters of the cells that `keep` holds, the groups that touch, each sorted, numbered
    /// in the order of their first cell.
    pub fn clusters(&self, keep: impl Fn(&Cell) -> bool) -> Vec<Vec<Cell>> {
        const NONE: u32 = u32::MAX;
        let kept: Vec<bool> = self.cells.iter().map(&keep).collect();
        let mut label = vec![NONE; self.cells.len()];
        let mut count = 0;
        let mut stack = Vec::new();
        for start in 0..self.cells.len() {
            if !kept[start] || label[start] != NONE {
                continue;
            }
            label[start] = count;
            stack.push(start as u32);
            while let Some(i) = stack.pop() {
                let i = i as usize;
                for &j in &self.next[self.first[i] as usize..self.first[i + 1] as usize] {
                    if kept[j as usize] && label[j as usize] == NONE {
                        label[j as usize] = count;
                        stack.push(j);
                    }
                }
            }
            count += 1;
        }
        let mut members: Vec<Vec<Cell>> = vec![Vec::new(); count as usize];
        for (&c, &k) in self.cells.iter().zip(&label) {
            if k != NONE {
                members[k as usize].push(c);
            }
        }
        members
    }
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

/// The edges of a mesh's triangles, numbered: edge `of[3t + k]` runs from corner `k` of
/// triangle `t` to corner `k + 1`, and the two triangles of an edge share its number.
pub(crate) struct EdgeNumbers {
    of: Vec<u32>,
    count: usize,
}

impl EdgeNumbers {
    pub fn of(mesh: &IndexedMesh) -> Self {
        let mut ends: Vec<(u64, u32)> = mesh
            .triangles
            .par_iter()
            .enumerate()
            .flat_map_iter(|(t, tri)| {
                (0..3).map(move |k| {
                    let (a, b) = (tri[k], tri[(k + 1) % 3]);
                    let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
                    (key, (3 * t + k) as u32)
                })
            })
            .collect();
        ends.par_sort_unstable();
        let mut of = vec![0u32; ends.len()];
        let mut count = 0usize;
        for (i, &(key, slot)) in ends.iter().enumerate() {
            if i > 0 && ends[i - 1].0 != key {
                count += 1;
            }
            of[slot as usize] = count as u32;
        }
        let count = if ends.is_empty() { 0 } else { count + 1 };
        Self { of, count }
    }
}

/// [`euler`] of each list of triangles of `mesh` (edges numbered by `edges`): each vertex and
/// edge is counted once per list by marking it with the list's number, instead of hashing.
pub(crate) fn eulers(mesh: &IndexedMesh, edges: &EdgeNumbers, lists: &[Vec<u32>]) -> Vec<i64> {
    lists
        .par_iter()
        .enumerate()
        .map_init(
            || {
                (
                    vec![u32::MAX; mesh.positions.len()],
                    vec![u32::MAX; edges.count],
                )
            },
            |(vertex_mark, edge_mark), (k, triangles)| {
                let mark = k as u32;
                let (mut vertices, mut edge_count) = (0i64, 0i64);
                for &t in triangles {
                    let tri = mesh.triangles[t as usize];
                    for (c, &v) in tri.iter().enumerate() {
                        if std::mem::replace(&mut vertex_mark[v as usize], mark) != mark {
                            vertices += 1;
                        }
                        let e = edges.of[3 * t as usize + c] as usize;
                        if std::mem::replace(&mut edge_mark[e], mark) != mark {
                            edge_count += 1;
                        }
                    }
                }
                vertices - edge_count + triangles.len() as i64
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Marking gives what hashing gives: a whole sphere (2), caps (1), a band (0), a lone
    /// triangle (1), nothing (0), and lists sharing vertices with one another.
    #[test]
    fn marked_counts_are_hashed_counts() {
        let sphere = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let z = |t: &[u32; 3]| {
            t.iter()
                .map(|&v| sphere.positions[v as usize].z)
                .sum::<f32>()
                / 3.0
        };
        let all: Vec<u32> = (0..sphere.triangles.len() as u32).collect();
        let pick = |keep: &dyn Fn(f32) -> bool| -> Vec<u32> {
            all.iter()
                .copied()
                .filter(|&t| keep(z(&sphere.triangles[t as usize])))
                .collect()
        };
        let lists = vec![
            all.clone(),
            pick(&|z| z > 0.5),
            pick(&|z| z.abs() < 0.3),
            pick(&|z| z < -0.2),
            vec![7],
            Vec::new(),
            all.iter().copied().step_by(3).collect(),
        ];
        let edges = EdgeNumbers::of(&sphere);
        let hashed: Vec<i64> = lists.iter().map(|l| euler(&sphere, l)).collect();
        assert_eq!(eulers(&sphere, &edges, &lists), hashed);
        assert_eq!(&hashed[..6], &[2, 1, 0, 1, 1, 0]);
    }
}
