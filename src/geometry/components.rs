//! The connected components of a triangle mesh, by union-find over each triangle's corners (no
//! edge list needed): the topology step counts them and finds the ones the grid cannot see.

/// Every vertex's component, named by its least vertex.
pub struct Components {
    parent: Vec<u32>,
}

impl Components {
    /// The components of `vertices` vertices joined by `triangles`, whose indices must be below
    /// `vertices`.
    pub fn new(vertices: usize, triangles: &[[u32; 3]]) -> Self {
        let mut components = Self {
            parent: (0..vertices as u32).collect(),
        };
        for t in triangles {
            for k in 1..3 {
                components.join(t[0], t[k]);
            }
        }
        components
    }

    /// Joins the components of `a` and `b`.
    pub fn join(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.max(b) as usize] = a.min(b);
        }
    }

    /// The least vertex of `x`'s component (halving the path on the way).
    pub fn find(&mut self, mut x: u32) -> u32 {
        let parent = &mut self.parent;
        while parent[x as usize] != x {
            parent[x as usize] = parent[parent[x as usize] as usize];
            x = parent[x as usize];
        }
        x
    }

    /// Whether `v` names its component.
    pub fn is_root(&self, v: u32) -> bool {
        self.parent[v as usize] == v
    }
}
