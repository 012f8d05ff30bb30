use rayon::prelude::*;

/// The triangles around each vertex, in triangle order (compressed rows), built by a counting
/// sort so the rows are the same whatever the thread count.
pub(super) struct VertexFaces {
    start: Vec<u32>,
    faces: Vec<u32>,
}

impl VertexFaces {
    /// Indices must be below `vertices`.
    pub(super) fn new(vertices: usize, triangles: &[[u32; 3]]) -> Self {
        let mut start = vec![0u32; vertices + 1];
        for tri in triangles {
            for &v in tri {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..vertices {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut faces = vec![0u32; start[vertices] as usize];
        for (t, tri) in triangles.iter().enumerate() {
            for &v in tri {
                faces[next[v as usize] as usize] = t as u32;
                next[v as usize] += 1;
            }
        }
        Self { start, faces }
    }

    pub(super) fn vertices(&self) -> usize {
        self.start.len() - 1
    }

    /// The triangles having vertex `v` as a corner, ascending.
    pub(super) fn around(&self, v: u32) -> &[u32] {
        &self.faces[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// The first triangle (in mesh order) with the directed edge `a → b`.
    pub(super) fn face_with_edge(&self, triangles: &[[u32; 3]], a: u32, b: u32) -> Option<usize> {
        self.around(a).iter().map(|&f| f as usize).find(|&f| {
            let tri = triangles[f];
            (0..3).any(|k| tri[k] == a && tri[(k + 1) % 3] == b)
        })
    }

    /// For each vertex, the distinct neighbours with a larger index: every undirected edge once.
    pub(super) fn edges_per_vertex<'a>(
        &'a self,
        triangles: &'a [[u32; 3]],
    ) -> impl IndexedParallelIterator<Item = (u32, Vec<u32>)> + 'a {
        (0..self.vertices() as u32).into_par_iter().map(move |a| {
            let mut higher: Vec<u32> = self
                .around(a)
                .iter()
                .flat_map(|&f| triangles[f as usize])
                .filter(|&b| b > a)
                .collect();
            higher.sort_unstable();
            higher.dedup();
            (a, higher)
        })
    }
}
