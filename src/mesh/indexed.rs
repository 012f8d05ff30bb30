use glam::Vec3;

/// A named per-vertex channel of `components` f32 values per vertex (colour, UV, displacement …),
/// stored vertex-major: `values[v * components + c]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Attribute {
    pub name: String,
    pub components: usize,
    pub values: Vec<f32>,
}

impl Attribute {
    /// The channel on the vertices `order` names, in that order: vertex `i` of the result takes
    /// the values of vertex `order[i]`.
    pub fn gather(&self, order: &[usize]) -> Attribute {
        let k = self.components;
        Attribute {
            name: self.name.clone(),
            components: k,
            values: order
                .iter()
                .flat_map(|&v| &self.values[v * k..(v + 1) * k])
                .copied()
                .collect(),
        }
    }
}

/// The exchange form of a triangle mesh: what readers produce and writers consume.
///
/// It may be broken in any way a file can be (open, non-manifold, degenerate); `validate` says how.
/// `ids` carries persistent vertex ids when the mesh comes from (or goes to) a tracked sequence.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IndexedMesh {
    pub positions: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    pub ids: Option<Vec<u64>>,
    pub attributes: Vec<Attribute>,
}

impl IndexedMesh {
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            triangles,
            ids: None,
            attributes: Vec::new(),
        }
    }
}
