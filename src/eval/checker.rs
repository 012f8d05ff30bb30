//! How crisp a carried checker still is: the share of a propagated frame's vertices whose colour
//! lies within a tenth of the checker's colour range of one of its two colours. A colour carried
//! by persistent ids stays one of the two; each re-sampling averages neighbours and leaves a blend,
//! so this share is what a user sees as a sharp texture against a smear.

use crate::mesh::IndexedMesh;
use crate::propagate::{DARK, LIGHT};

/// Largest distance from a checker colour, as a share of the distance between the two, that
/// still counts as that colour.
pub const PURE_TOLERANCE: f32 = 0.1;

/// The share of `mesh`'s vertices whose `color` is within [`PURE_TOLERANCE`] of the checker's
/// range from `LIGHT` or `DARK`; `None` when the mesh has no 3-component `color` channel.
pub fn pure_share(mesh: &IndexedMesh) -> Option<f64> {
    let colour = mesh
        .attributes
        .iter()
        .find(|a| a.name == "color" && a.components == 3)?;
    let distance = |a: &[f32], b: [f32; 3]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f32>()
            .sqrt()
    };
    let range = distance(&LIGHT, DARK);
    let vertices = colour.values.len() / 3;
    let pure = colour
        .values
        .chunks_exact(3)
        .filter(|c| distance(c, LIGHT).min(distance(c, DARK)) <= PURE_TOLERANCE * range)
        .count();
    Some(pure as f64 / vertices.max(1) as f64)
}
