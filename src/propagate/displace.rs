//! Scalar displacement (paper §4.6): each vertex moved along its normal by a carried scalar, so that
//! detail painted on the start frame stays on the material as the surface deforms.

use super::PropagateError;
use crate::mesh::{IndexedMesh, NormalWeighting};

/// Displace along a carried channel, `scale` start-frame mean edge lengths per unit of the scalar.
#[derive(Debug, Clone, PartialEq)]
pub struct Displace {
    /// One-component channels are the scalar itself; colours (3 or 4 components) give their
    /// luminance (Rec. 709 weights).
    pub channel: String,
    pub scale: f32,
}

/// The scalar of one vertex's value.
fn scalar(value: &[f32]) -> f32 {
    match value {
        [s] => *s,
        [r, g, b, ..] => 0.2126 * r + 0.7152 * g + 0.0722 * b,
        _ => 0.0,
    }
}

/// Moves each vertex of `mesh` by `distance · scalar(channel)` along its area-weighted normal.
pub fn displace(
    mesh: &mut IndexedMesh,
    channel: &str,
    distance: f32,
) -> Result<(), PropagateError> {
    let Some(attribute) = mesh.attributes.iter().find(|a| a.name == channel) else {
        return Err(PropagateError::NoDisplaceChannel {
            name: channel.to_string(),
        });
    };
    let k = attribute.components;
    if !matches!(k, 1 | 3 | 4) {
        return Err(PropagateError::DisplaceChannel {
            name: channel.to_string(),
            components: k,
        });
    }
    let offsets: Vec<f32> = attribute
        .values
        .chunks_exact(k)
        .map(|v| distance * scalar(v))
        .collect();
    let normals = mesh.vertex_normals(NormalWeighting::Area);
    for ((p, n), d) in mesh.positions.iter_mut().zip(normals).zip(offsets) {
        *p += n * d;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Attribute;
    use glam::Vec3;

    #[test]
    fn a_unit_sphere_grows_by_the_displacement() {
        let mut mesh = IndexedMesh::icosphere(Vec3::ZERO, 1.0, 3);
        let n = mesh.positions.len();
        mesh.attributes.push(Attribute {
            name: "height".to_string(),
            components: 1,
            values: vec![0.5; n],
        });
        displace(&mut mesh, "height", 0.2).unwrap();
        for p in &mesh.positions {
            assert!((p.length() - 1.1).abs() < 1e-3, "{p}");
        }
        mesh.attributes[0].components = 2;
        mesh.attributes[0].values.truncate(2 * (n / 2));
        assert!(matches!(
            displace(&mut mesh, "height", 1.0),
            Err(PropagateError::DisplaceChannel { components: 2, .. })
        ));
        assert!(matches!(
            displace(&mut mesh, "color", 1.0),
            Err(PropagateError::NoDisplaceChannel { .. })
        ));
    }
}
