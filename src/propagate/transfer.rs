//! Values for the start frame from an attribute of another mesh file: the frame itself edited in
//! Blender or Houdini (matched by persistent id), or any mesh near it (matched by closest point).

use super::PropagateError;
use crate::compute::Backend;
use crate::io::read_frame;
use crate::mesh::{Attribute, IndexedMesh};
use crate::project::{Bvh, closest_points};
use std::collections::HashMap;
use std::path::Path;

/// The attribute `name` of the mesh in `path`, re-sampled onto `mesh`'s vertices.
///
/// When the file carries persistent ids covering every vertex of `mesh`, values are copied by id.
/// Otherwise each vertex takes the value at its closest point on the file's surface, interpolated
/// barycentrically: painting a copy of the frame, or a nearby mesh, both work.
pub fn transfer(path: &Path, name: &str, mesh: &IndexedMesh) -> Result<Attribute, PropagateError> {
    let source = read_frame(path)?.mesh;
    let Some(attribute) = source.attributes.iter().find(|a| a.name == name) else {
        let names: Vec<&str> = source.attributes.iter().map(|a| a.name.as_str()).collect();
        return Err(PropagateError::NoAttribute {
            path: path.to_path_buf(),
            name: name.to_string(),
            available: if names.is_empty() {
                "no attributes".to_string()
            } else {
                names.join(", ")
            },
        });
    };
    let k = attribute.components;
    if attribute.values.len() != k * source.positions.len() {
        return Err(PropagateError::Inconsistent {
            path: path.to_path_buf(),
            what: format!(
                "attribute '{name}' has {} values for {} vertices × {k} components",
                attribute.values.len(),
                source.positions.len()
            ),
        });
    }
    if let Some(values) = by_id(&source, attribute, mesh) {
        return Ok(Attribute {
            name: name.to_string(),
            components: k,
            values,
        });
    }
    let failed = |source| PropagateError::Transfer {
        path: path.to_path_buf(),
        name: name.to_string(),
        source,
    };
    let bvh = Bvh::build_unsigned(&source).map_err(failed)?;
    let found =
        closest_points(&Backend::Cpu, &bvh, &mesh.positions, f32::INFINITY).map_err(failed)?;
    let mut values = Vec::with_capacity(mesh.positions.len() * k);
    for hit in &found {
        let Some(triangle) = hit.hit_triangle() else {
            return Err(PropagateError::Inconsistent {
                path: path.to_path_buf(),
                what: "a tracked vertex has no closest point on this mesh".to_string(),
            });
        };
        let corners = source.triangles[triangle as usize];
        let w = hit.barycentric.to_array();
        for c in 0..k {
            values.push(
                (0..3)
                    .map(|i| w[i] * attribute.values[corners[i] as usize * k + c])
                    .sum(),
            );
        }
    }
    Ok(Attribute {
        name: name.to_string(),
        components: k,
        values,
    })
}

/// The values copied by persistent id, when the source has an id for every vertex of `mesh`.
fn by_id(source: &IndexedMesh, attribute: &Attribute, mesh: &IndexedMesh) -> Option<Vec<f32>> {
    let (source_ids, ids) = (source.ids.as_ref()?, mesh.ids.as_ref()?);
    let k = attribute.components;
    let slot: HashMap<u64, usize> = source_ids
        .iter()
        .enumerate()
        .map(|(i, &id)| (id, i))
        .collect();
    let mut values = Vec::with_capacity(ids.len() * k);
    for id in ids {
        let s = *slot.get(id)?;
        values.extend_from_slice(attribute.values.get(s * k..(s + 1) * k)?);
    }
    Some(values)
}
