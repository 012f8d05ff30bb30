//! The deformation graph (Sumner et al. 2007, as used in paper §4.2 and Birger's thesis §3.3.1):
//! nodes sampled evenly over the surface by geodesic distance, edges between nodes whose geodesic
//! Voronoi cells touch, and every vertex skinned by its nearest nodes.

use glam::{DVec3, Vec3};

use super::RegisterError;
use super::adjacency::VertexAdjacency;
use super::geodesic::{NearestNodes, sample};
use crate::mesh::{IndexedMesh, MeshError};

/// How densely to sample the graph and how many nodes move each vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GraphOptions {
    /// Geodesic distance between nodes in mean edge lengths (paper §4.2: 4).
    pub spacing: f32,
    /// Nodes skinning each vertex (paper §4.2: k = 4).
    pub skinning_nodes: usize,
    /// The graph gets about this many nodes at most: on a surface finer than that at `spacing`,
    /// the nodes are spaced wider (see [`GraphOptions::spacing_for`]).
    pub max_nodes: usize,
}

impl Default for GraphOptions {
    /// `max_nodes` 5,000 leaves the paper's spacing alone up to about 110k vertices (the ~100k
    /// bench frames have 4,380 nodes) and keeps a 1M-vertex frame's coarse system that size.
    fn default() -> Self {
        Self {
            spacing: 4.0,
            skinning_nodes: 4,
            max_nodes: 5000,
        }
    }
}

/// Surface area one node's geodesic Poisson-disk cell covers, in squared node spacings: measured
/// 1.03 on synth `blobs` (4,380 nodes at spacing 4 over 71,882 squared mean edge lengths).
const NODE_CELL_AREA: f64 = 1.0;

impl GraphOptions {
    /// Node spacing in mean edge lengths for a surface of `area` squared mean edge lengths.
    ///
    /// The paper's spacing (§4.2) ties the graph to the mesh's resolution, so a frame ten times
    /// finer gets ten times the nodes and a coarse system whose factorization grows faster than
    /// that, while the motion the graph has to express — the shape's — is the same. Past
    /// `max_nodes` the spacing widens instead: the graph stays the coarse level of a two-level
    /// registration whose fine level, the per-vertex stage, follows the mesh's resolution.
    pub fn spacing_for(&self, area: f64) -> f32 {
        let widest = (area / (NODE_CELL_AREA * self.max_nodes as f64)).sqrt();
        self.spacing.max(widest as f32)
    }

    pub fn check(&self) -> Result<(), RegisterError> {
        if !(self.spacing.is_finite() && self.spacing > 0.0) {
            return Err(RegisterError::Option {
                name: "graph spacing",
                expected: "finite and positive",
                value: f64::from(self.spacing),
            });
        }
        if self.max_nodes == 0 {
            return Err(RegisterError::Option {
                name: "graph max nodes",
                expected: "at least 1",
                value: 0.0,
            });
        }
        if !(1..=16).contains(&self.skinning_nodes) {
            return Err(RegisterError::Option {
                name: "skinning nodes",
                expected: "between 1 and 16",
                value: self.skinning_nodes as f64,
            });
        }
        Ok(())
    }
}

/// A deformation graph over one mesh: its nodes (mesh vertices), its edges and the skinning weights
/// that carry node transformations to the vertices by linear blend skinning (thesis eq. 3.2).
#[derive(Debug, Clone, PartialEq)]
pub struct DeformationGraph {
    node_vertices: Vec<u32>,
    node_positions: Vec<Vec3>,
    edges: Vec<[u32; 2]>,
    skin_offsets: Vec<u32>,
    skin_nodes: Vec<u32>,
    skin_weights: Vec<f32>,
}

impl DeformationGraph {
    /// Samples the graph of `mesh` (closed; indices must be in range).
    pub fn build(mesh: &IndexedMesh, options: &GraphOptions) -> Result<Self, RegisterError> {
        options.check()?;
        check_indices(mesh, "source")?;
        let unit = mesh.mean_edge_length();
        if !(unit.is_finite() && unit > 0.0) {
            return Err(RegisterError::NoScale { which: "source" });
        }
        let adjacency = VertexAdjacency::new(mesh.positions.len(), &mesh.triangles);
        let area = surface_area(&mesh.positions, &mesh.triangles) / f64::from(unit).powi(2);
        Ok(Self::from_adjacency(
            &mesh.positions,
            &adjacency,
            options.spacing_for(area) * unit,
            options.skinning_nodes,
        ))
    }

    /// The graph of a mesh given by its adjacency, with `spacing` in the mesh's own units.
    pub(crate) fn from_adjacency(
        positions: &[Vec3],
        adjacency: &VertexAdjacency,
        spacing: f32,
        skinning_nodes: usize,
    ) -> Self {
        let node_vertices = sample(adjacency, positions, spacing);
        let nearest =
            NearestNodes::search(adjacency, positions, &node_vertices, skinning_nodes + 1);
        let mut edges: Vec<[u32; 2]> = adjacency
            .edges()
            .filter_map(|[a, b]| {
                let (na, nb) = (nearest.of(a as usize)[0].0, nearest.of(b as usize)[0].0);
                (na != nb).then(|| [na.min(nb), na.max(nb)])
            })
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let mut skin_offsets = Vec::with_capacity(positions.len() + 1);
        skin_offsets.push(0u32);
        let mut skin_nodes = Vec::with_capacity(positions.len() * skinning_nodes);
        let mut skin_weights = Vec::with_capacity(positions.len() * skinning_nodes);
        for v in 0..positions.len() {
            let labels = nearest.of(v);
            let used = &labels[..labels.len().min(skinning_nodes)];
            let weights = skinning_weights(labels, skinning_nodes, spacing);
            skin_nodes.extend(used.iter().map(|&(node, _)| node));
            skin_weights.extend(weights);
            skin_offsets.push(skin_nodes.len() as u32);
        }
        let node_positions = node_vertices
            .iter()
            .map(|&v| positions[v as usize])
            .collect();
        Self {
            node_vertices,
            node_positions,
            edges,
            skin_offsets,
            skin_nodes,
            skin_weights,
        }
    }

    pub fn node_count(&self) -> usize {
        self.node_vertices.len()
    }

    pub fn vertex_count(&self) -> usize {
        self.skin_offsets.len() - 1
    }

    /// The mesh vertex each node sits on.
    pub fn node_vertices(&self) -> &[u32] {
        &self.node_vertices
    }

    /// Node positions `g_i` (those of their vertices when the graph was built).
    pub fn node_positions(&self) -> &[Vec3] {
        &self.node_positions
    }

    /// Graph edges `[i, j]` with `i < j`, sorted: pairs of nodes whose geodesic Voronoi cells share
    /// a mesh edge.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// The nodes skinning vertex `v` (nearest first) and their weights, which sum to 1.
    pub fn skinning(&self, v: usize) -> (&[u32], &[f32]) {
        let range = self.skin_offsets[v] as usize..self.skin_offsets[v + 1] as usize;
        (&self.skin_nodes[range.clone()], &self.skin_weights[range])
    }
}

/// Total area of `triangles`, summed in order in `f64` (the same for any thread count).
pub(crate) fn surface_area<P: Copy + Into<DVec3>>(positions: &[P], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize].into());
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

/// Thesis eq. 3.3–3.4 with geodesic distances: `w_i = (1 − d_i / d_max)²`, normalized to sum 1,
/// where `d_max` is the distance to the (k+1)-th nearest node. The weight of a node fades to zero
/// just as it stops being among the k nearest, so the skinning varies continuously over the
/// surface, which inverse distances (paper §4.2) do not. A component with at most k nodes has no
/// (k+1)-th one; there `d_max` is the farthest node's distance plus one node spacing.
fn skinning_weights(labels: &[(u32, f32)], k: usize, spacing: f32) -> Vec<f32> {
    let used = &labels[..labels.len().min(k)];
    let d_max = match labels.get(k) {
        Some(&(_, d)) => d,
        None => used.last().map_or(0.0, |&(_, d)| d) + spacing,
    };
    let raw: Vec<f32> = used
        .iter()
        .map(|&(_, d)| {
            let s = (1.0 - d / d_max).max(0.0);
            s * s
        })
        .collect();
    let sum: f32 = raw.iter().sum();
    if sum > 0.0 && sum.is_finite() {
        raw.iter().map(|w| w / sum).collect()
    } else {
        vec![1.0 / used.len() as f32; used.len()]
    }
}

pub(crate) fn check_indices(mesh: &IndexedMesh, which: &'static str) -> Result<(), RegisterError> {
    if mesh.triangles.is_empty() {
        return Err(RegisterError::Mesh {
            which,
            source: MeshError::Empty,
        });
    }
    let count = mesh.positions.len();
    for (triangle, tri) in mesh.triangles.iter().enumerate() {
        if let Some(&vertex) = tri.iter().find(|&&v| v as usize >= count) {
            return Err(RegisterError::Mesh {
                which,
                source: MeshError::IndexOutOfRange {
                    triangle,
                    vertex,
                    count,
                },
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_spheres(gap: f32) -> IndexedMesh {
        let a = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let b = IndexedMesh::icosphere(Vec3::new(2.0 + gap, 0.0, 0.0), 1.0, 3);
        a.joined(&b)
    }

    #[test]
    fn weights_are_normalized_and_nearest_first() {
        let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
        let graph = DeformationGraph::build(&mesh, &GraphOptions::default()).unwrap();
        assert!(graph.node_count() > 20, "{} nodes", graph.node_count());
        for v in 0..graph.vertex_count() {
            let (nodes, weights) = graph.skinning(v);
            assert_eq!(nodes.len(), 4);
            let sum: f32 = weights.iter().sum();
            assert!((sum - 1.0).abs() < 1e-5, "vertex {v}: weights sum {sum}");
            assert!(weights.windows(2).all(|w| w[0] >= w[1]), "{weights:?}");
        }
        for (i, &v) in graph.node_vertices().iter().enumerate() {
            let (nodes, weights) = graph.skinning(v as usize);
            assert_eq!(nodes[0], i as u32);
            assert!(weights[0] > 0.5);
        }
    }

    #[test]
    fn a_finer_mesh_gets_wider_nodes_past_the_budget() {
        // Icosphere levels 4 and 6: the same sphere with 16× the vertices.
        let coarse = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 4);
        let fine = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 6);
        let paper = GraphOptions::default();
        let unbounded = GraphOptions {
            max_nodes: usize::MAX,
            ..paper
        };
        let nodes = |mesh: &IndexedMesh, o: &GraphOptions| {
            DeformationGraph::build(mesh, o).unwrap().node_count()
        };
        // Under the budget the paper's spacing is kept: the same graph as without one.
        let coarse_nodes = nodes(&coarse, &paper);
        assert_eq!(coarse_nodes, nodes(&coarse, &unbounded));
        // The fine mesh at the paper's spacing has about 16× the nodes; a budget of the coarse
        // mesh's count keeps it about there.
        let budget = GraphOptions {
            max_nodes: coarse_nodes,
            ..paper
        };
        let fine_nodes = nodes(&fine, &budget);
        assert!(nodes(&fine, &unbounded) > 10 * coarse_nodes);
        assert!(
            (coarse_nodes as f64 * 0.6..coarse_nodes as f64 * 1.6).contains(&(fine_nodes as f64)),
            "{fine_nodes} nodes for a budget of {coarse_nodes}"
        );
    }

    #[test]
    fn close_components_never_connect() {
        let mesh = two_spheres(0.05);
        let half = mesh.positions.len() / 2;
        let graph = DeformationGraph::build(&mesh, &GraphOptions::default()).unwrap();
        let side = |node: u32| graph.node_vertices()[node as usize] as usize >= half;
        for &[a, b] in graph.edges() {
            assert_eq!(side(a), side(b), "edge {a}-{b} crosses the gap");
        }
        for v in 0..graph.vertex_count() {
            let (nodes, _) = graph.skinning(v);
            assert!(nodes.iter().all(|&n| side(n) == (v >= half)), "vertex {v}");
        }
    }

    #[test]
    fn graph_of_a_component_is_connected() {
        let mesh = IndexedMesh::torus(2.0, 0.6, 64, 24);
        let graph = DeformationGraph::build(&mesh, &GraphOptions::default()).unwrap();
        let mut parent: Vec<usize> = (0..graph.node_count()).collect();
        fn root(parent: &mut [usize], mut x: usize) -> usize {
            while parent[x] != x {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            x
        }
        for &[a, b] in graph.edges() {
            let (ra, rb) = (root(&mut parent, a as usize), root(&mut parent, b as usize));
            parent[ra] = rb;
        }
        let r0 = root(&mut parent, 0);
        assert!((0..graph.node_count()).all(|i| root(&mut parent, i) == r0));
        let mean_degree = 2.0 * graph.edges().len() as f32 / graph.node_count() as f32;
        assert!(
            (4.0..9.0).contains(&mean_degree),
            "mean degree {mean_degree}"
        );
    }

    #[test]
    fn bad_options_are_errors() {
        let mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 1);
        let spacing = GraphOptions {
            spacing: 0.0,
            ..GraphOptions::default()
        };
        assert!(DeformationGraph::build(&mesh, &spacing).is_err());
        let k = GraphOptions {
            skinning_nodes: 0,
            ..GraphOptions::default()
        };
        assert!(DeformationGraph::build(&mesh, &k).is_err());
        let mut broken = mesh.clone();
        broken.triangles[0][1] = 9999;
        assert!(matches!(
            DeformationGraph::build(&broken, &GraphOptions::default()),
            Err(RegisterError::Mesh { .. })
        ));
    }
}
