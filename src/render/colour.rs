//! What colour each vertex is drawn in: the carried `color`, a texture looked up through the
//! carried `uv`, a scalar attribute (the wave `height`, …) through a colour map, or one plain
//! colour.

use crate::mesh::IndexedMesh;
use crate::propagate::Texture;
use glam::Vec2;

/// The grey a mesh with nothing to show is drawn in.
pub const PLAIN: [f32; 3] = [0.72, 0.74, 0.78];

/// How vertex colours are chosen.
#[derive(Debug, Clone, PartialEq)]
pub enum Colouring {
    /// The 3-component attribute `color`.
    Vertex,
    /// The texture sampled at each vertex's `uv` (2 components); between vertices the colour is
    /// interpolated, so the texture shows at the resolution of the mesh.
    Texture(Texture),
    /// A 1-component attribute through a blue–white–red map over `[−limit, limit]` (symmetric, so
    /// 0 is white), `limit` shared by all frames.
    Scalar { name: String, limit: f32 },
    /// One colour for every vertex.
    Plain([f32; 3]),
}

/// Why a frame cannot be coloured as asked: the attribute it needs, and what it has.
#[derive(Debug, Clone, PartialEq)]
pub struct MissingChannel {
    pub name: String,
    pub components: usize,
}

/// The colour of each vertex of `mesh`.
pub fn vertex_colours(
    mesh: &IndexedMesh,
    colouring: &Colouring,
) -> Result<Vec<[f32; 3]>, MissingChannel> {
    let channel = |name: &str, components: usize| {
        mesh.attributes
            .iter()
            .find(|a| a.name == name && a.components == components)
            .ok_or(MissingChannel {
                name: name.to_string(),
                components,
            })
    };
    Ok(match colouring {
        Colouring::Vertex => channel("color", 3)?
            .values
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
        Colouring::Texture(texture) => channel("uv", 2)?
            .values
            .chunks_exact(2)
            .map(|uv| texture.sample(Vec2::new(uv[0], uv[1])))
            .collect(),
        Colouring::Scalar { name, limit } => channel(name, 1)?
            .values
            .iter()
            .map(|&s| diverging(s / limit.max(f32::MIN_POSITIVE)))
            .collect(),
        Colouring::Plain(colour) => vec![*colour; mesh.positions.len()],
    })
}

/// Blue (−1) through white (0) to red (+1), clamped.
pub fn diverging(t: f32) -> [f32; 3] {
    let t = if t.is_finite() {
        t.clamp(-1.0, 1.0)
    } else {
        0.0
    };
    let (blue, red) = ([0.23, 0.30, 0.75], [0.71, 0.02, 0.15]);
    let end = if t < 0.0 { blue } else { red };
    let a = t.abs();
    [0, 1, 2].map(|k| (1.0 - a) * 0.97 + a * end[k])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_is_white_and_the_ends_saturate() {
        assert_eq!(diverging(0.0), [0.97; 3]);
        assert_eq!(diverging(5.0), diverging(1.0));
        assert!(diverging(-1.0)[2] > diverging(-1.0)[0]);
        assert!(diverging(1.0)[0] > diverging(1.0)[2]);
    }
}
