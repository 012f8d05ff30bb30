//! Vertex adjacency of a closed triangle mesh in compressed rows: the walk the geodesic searches
//! take and the edge set the fine stage regularizes.

/// Neighbours of every vertex, sorted, each undirected edge stored in both directions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct VertexAdjacency {
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
}

impl VertexAdjacency {
    /// Adjacency of `vertex_count` vertices joined by the edges of `triangles` (indices are taken
    /// as valid: callers pass meshes that passed validation).
    pub fn new(vertex_count: usize, triangles: &[[u32; 3]]) -> Self {
        let mut degree = vec![0u32; vertex_count + 1];
        for tri in triangles {
            for &v in tri {
                degree[v as usize + 1] += 2;
            }
        }
        let mut offsets = degree;
        for v in 0..vertex_count {
            offsets[v + 1] += offsets[v];
        }
        let mut fill: Vec<u32> = offsets[..vertex_count].to_vec();
        let mut neighbours = vec![0u32; offsets[vertex_count] as usize];
        for tri in triangles {
            for k in 0..3 {
                let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let slot = &mut fill[a as usize];
                neighbours[*slot as usize] = b;
                neighbours[*slot as usize + 1] = c;
                *slot += 2;
            }
        }
        let mut compact_offsets = Vec::with_capacity(vertex_count + 1);
        compact_offsets.push(0u32);
        let mut write = 0usize;
        for v in 0..vertex_count {
            let (start, end) = (offsets[v] as usize, offsets[v + 1] as usize);
            neighbours[start..end].sort_unstable();
            let mut last = None;
            for read in start..end {
                let n = neighbours[read];
                if last != Some(n) {
                    neighbours[write] = n;
                    write += 1;
                    last = Some(n);
                }
            }
            compact_offsets.push(write as u32);
        }
        neighbours.truncate(write);
        Self {
            offsets: compact_offsets,
            neighbours,
        }
    }

    pub fn vertex_count(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Vertex `v`'s neighbours are `all_neighbours()[offsets()[v]..offsets()[v + 1]]`.
    pub fn offsets(&self) -> &[u32] {
        &self.offsets
    }

    /// Every vertex's neighbours, one list after another.
    pub fn all_neighbours(&self) -> &[u32] {
        &self.neighbours
    }

    pub fn neighbours(&self, v: usize) -> &[u32] {
        &self.neighbours[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }

    /// Every undirected edge once, as `(a, b)` with `a < b`, in increasing order.
    pub fn edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        (0..self.vertex_count()).flat_map(move |a| {
            self.neighbours(a)
                .iter()
                .filter(move |&&b| b as usize > a)
                .map(move |&b| [a as u32, b])
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tetrahedron_is_complete() {
        let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        let adj = VertexAdjacency::new(4, &tris);
        for v in 0..4u32 {
            let expected: Vec<u32> = (0..4).filter(|&u| u != v).collect();
            assert_eq!(adj.neighbours(v as usize), expected.as_slice());
        }
        assert_eq!(adj.edges().count(), 6);
        assert!(adj.edges().all(|[a, b]| a < b));
    }
}
