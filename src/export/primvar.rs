//! How a carried vertex channel becomes a USD primvar: the names and roles renderers look for where
//! there is one (`displayColor`, `displayOpacity`, `st`), plain float tuples otherwise.

use crate::mesh::Attribute;

/// One primvar of vertex interpolation: its name without the `primvars:` namespace, its USD value
/// type, and which components of the attribute it takes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Primvar {
    pub name: String,
    /// `color3f[]`, `texCoord2f[]`, `float[]`, `float2[]`, `float3[]` or `float4[]`.
    pub type_name: &'static str,
    /// First component of the attribute this primvar takes.
    pub first: usize,
    /// Components per vertex the primvar takes (a `float[]` with more than one has that
    /// `elementSize`).
    pub components: usize,
}

/// The primvars of an attribute: `color` (3 or 4) is `displayColor` (and `displayOpacity`), `uv`
/// (2) is `st`, anything else a float tuple of its own name; `None` when the name is not a USD
/// identifier or the attribute has no components.
pub fn primvar_of(attribute: &Attribute) -> Option<Vec<Primvar>> {
    let k = attribute.components;
    let whole = |name: &str, type_name| Primvar {
        name: name.to_string(),
        type_name,
        first: 0,
        components: k,
    };
    match (attribute.name.as_str(), k) {
        ("color", 3) => return Some(vec![whole("displayColor", "color3f[]")]),
        ("color", 4) => {
            return Some(vec![
                Primvar {
                    components: 3,
                    ..whole("displayColor", "color3f[]")
                },
                Primvar {
                    name: "displayOpacity".into(),
                    type_name: "float[]",
                    first: 3,
                    components: 1,
                },
            ]);
        }
        ("uv", 2) => return Some(vec![whole("st", "texCoord2f[]")]),
        _ => {}
    }
    if k == 0 || !is_identifier(&attribute.name) {
        return None;
    }
    let type_name = match k {
        2 => "float2[]",
        3 => "float3[]",
        4 => "float4[]",
        _ => "float[]",
    };
    Some(vec![whole(&attribute.name, type_name)])
}

/// A USD identifier: ASCII letters, digits and `_`, not starting with a digit.
fn is_identifier(name: &str) -> bool {
    let mut bytes = name.bytes();
    bytes
        .next()
        .is_some_and(|b| b.is_ascii_alphabetic() || b == b'_')
        && bytes.all(|b| b.is_ascii_alphanumeric() || b == b'_')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attribute(name: &str, components: usize) -> Attribute {
        Attribute {
            name: name.into(),
            components,
            values: Vec::new(),
        }
    }

    #[test]
    fn colours_and_uvs_take_the_names_renderers_read() {
        let rgba = primvar_of(&attribute("color", 4)).unwrap();
        assert_eq!(
            rgba.iter()
                .map(|p| (p.name.as_str(), p.type_name, p.first, p.components))
                .collect::<Vec<_>>(),
            [
                ("displayColor", "color3f[]", 0, 3),
                ("displayOpacity", "float[]", 3, 1)
            ]
        );
        assert_eq!(primvar_of(&attribute("uv", 2)).unwrap()[0].name, "st");
        assert_eq!(
            primvar_of(&attribute("wetness", 1)).unwrap()[0].type_name,
            "float[]"
        );
        assert_eq!(
            primvar_of(&attribute("stress", 6)).unwrap()[0].components,
            6
        );
        assert!(primvar_of(&attribute("2d", 1)).is_none());
        assert!(primvar_of(&attribute("a-b", 1)).is_none());
    }
}
