//! Components, Euler characteristic and genus: the quantities `constrain_topology` must match
//! (paper §4.3) and `inspect`/`eval` report.

use super::IndexedMesh;
use super::validate::{find, union};
use serde::Serialize;

/// Topology of one connected component of a closed mesh.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ComponentTopology {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    /// χ = V − E + F.
    pub euler: i64,
    /// g = (2 − χ) / 2, meaningful for a closed orientable component.
    pub genus: i64,
}

/// Topology of a whole mesh, components ordered by their smallest vertex index (deterministic).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Topology {
    pub components: Vec<ComponentTopology>,
}

impl Topology {
    pub fn euler(&self) -> i64 {
        self.components.iter().map(|c| c.euler).sum()
    }

    pub fn total_genus(&self) -> i64 {
        self.components.iter().map(|c| c.genus).sum()
    }
}

impl IndexedMesh {
    /// Connected components (through shared triangle edges) with their V, E, F, χ and genus.
    /// Vertices referenced by no triangle are ignored.
    pub fn topology(&self) -> Topology {
        self.topology_with_labels().0
    }

    /// [`IndexedMesh::topology`] and the component of every vertex, as
    /// [`IndexedMesh::component_labels`] numbers them, from one labelling.
    pub fn topology_with_labels(&self) -> (Topology, Vec<u32>) {
        self.topology_from_edges(&self.sorted_edges())
    }

    /// [`IndexedMesh::topology_with_labels`] from the mesh's [`IndexedMesh::sorted_edges`]
    /// (which [`IndexedMesh::validated_edges`] returns), so a caller that validated the mesh does
    /// not sort them twice.
    pub(crate) fn topology_from_edges(
        &self,
        edges: &[(u32, u32, bool, u32)],
    ) -> (Topology, Vec<u32>) {
        let (labels, count) = self.component_labels();
        let mut components = vec![
            ComponentTopology {
                vertices: 0,
                edges: 0,
                faces: 0,
                euler: 0,
                genus: 0,
            };
            count
        ];
        for &label in labels.iter().filter(|&&l| l != u32::MAX) {
            components[label as usize].vertices += 1;
        }
        for tri in &self.triangles {
            components[labels[tri[0] as usize] as usize].faces += 1;
        }
        for group in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            components[labels[group[0].0 as usize] as usize].edges += 1;
        }
        for c in &mut components {
            c.euler = c.vertices as i64 - c.edges as i64 + c.faces as i64;
            c.genus = (2 - c.euler) / 2;
        }
        (Topology { components }, labels)
    }

    /// The component of every vertex, numbered as in [`IndexedMesh::topology`] (by smallest vertex
    /// index), and the number of components; vertices referenced by no triangle get `u32::MAX`.
    pub fn component_labels(&self) -> (Vec<u32>, usize) {
        let n = self.positions.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        let mut used = vec![false; n];
        for tri in &self.triangles {
            union(&mut parent, tri[0], tri[1]);
            union(&mut parent, tri[1], tri[2]);
            for &v in tri {
                used[v as usize] = true;
            }
        }
        let mut slot = vec![u32::MAX; n];
        let mut labels = vec![u32::MAX; n];
        let mut count = 0u32;
        for v in 0..n {
            if !used[v] {
                continue;
            }
            let root = find(&mut parent, v as u32) as usize;
            if slot[root] == u32::MAX {
                slot[root] = count;
                count += 1;
            }
            labels[v] = slot[root];
        }
        (labels, count as usize)
    }

    /// Mean length of the undirected edges: the unit every relative tolerance is measured in.
    pub fn mean_edge_length(&self) -> f32 {
        let edges = self.sorted_edges();
        let mut sum = 0.0f64;
        let mut count = 0usize;
        for group in edges.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let (a, b) = (group[0].0 as usize, group[0].1 as usize);
            sum += f64::from(self.positions[a].distance(self.positions[b]));
            count += 1;
        }
        if count == 0 {
            0.0
        } else {
            (sum / count as f64) as f32
        }
    }
}
