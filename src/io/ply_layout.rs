//! What each PLY property means to the mesh: coordinates, the persistent id, an attribute channel,
//! the face corner list, or nothing (skipped).

use super::IoError;
use super::ply_channels::group_channels;
use super::ply_header::{Header, PropertyKind, Scalar};
use std::path::Path;

#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Role {
    Ignore,
    Coordinate(usize),
    Id,
    /// Slot in the per-vertex channel record, and the divisor applied to the stored value.
    Channel {
        slot: usize,
        divisor: f64,
    },
    Corners,
}

/// Roles for the properties of every element, and the attributes the channels form.
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    /// `roles[element][property]`.
    pub roles: Vec<Vec<Role>>,
    pub vertex_element: usize,
    pub vertex_count: usize,
    pub has_id: bool,
    /// Attribute names and component counts, in slot order.
    pub attributes: Vec<(String, usize)>,
    /// Channel slots per vertex (sum of attribute components).
    pub channels: usize,
}

impl Layout {
    /// Assigns roles: the `vertex` element must have scalar `x`, `y`, `z`; its other scalar
    /// properties become `id` and attribute channels; the `face` element, if any, must have an
    /// integer `vertex_indices` (or `vertex_index`) list. Integer colour channels are scaled to
    /// [0, 1] (`uchar` by 1/255, `ushort` by 1/65535), as colours are stored as fractions.
    pub(crate) fn new(path: &Path, header: &Header) -> Result<Layout, IoError> {
        let bad = |line: usize, reason: String| IoError::BadHeader {
            path: path.to_path_buf(),
            line,
            reason,
        };
        let mut roles: Vec<Vec<Role>> = header
            .elements
            .iter()
            .map(|e| vec![Role::Ignore; e.properties.len()])
            .collect();
        let vertex_element = header
            .elements
            .iter()
            .position(|e| e.name == "vertex")
            .ok_or_else(|| bad(header.lines, "no vertex element".into()))?;
        let vertex = &header.elements[vertex_element];

        let mut candidates = Vec::new();
        let mut has_id = false;
        for (p, property) in vertex.properties.iter().enumerate() {
            let axis = ["x", "y", "z"].iter().position(|&a| a == property.name);
            match (property.kind, axis) {
                (PropertyKind::Scalar(_), Some(axis)) => {
                    roles[vertex_element][p] = Role::Coordinate(axis)
                }
                (PropertyKind::List { .. }, Some(_)) => {
                    return Err(bad(
                        property.line,
                        format!(
                            "vertex property {} must be a scalar, not a list",
                            property.name
                        ),
                    ));
                }
                (PropertyKind::Scalar(_), None) if property.name == "id" => {
                    roles[vertex_element][p] = Role::Id;
                    has_id = true;
                }
                (PropertyKind::Scalar(ty), None) => candidates.push((p, ty)),
                (PropertyKind::List { .. }, None) => {}
            }
        }
        for axis in ["x", "y", "z"] {
            if !vertex.properties.iter().any(|p| p.name == axis) {
                return Err(bad(
                    header.lines,
                    format!("the vertex element has no property {axis}"),
                ));
            }
        }

        let names: Vec<&str> = candidates
            .iter()
            .map(|&(p, _)| vertex.properties[p].name.as_str())
            .collect();
        let mut attributes = Vec::new();
        let mut slot = 0;
        for (name, members) in group_channels(&names) {
            for &m in &members {
                let (p, ty) = candidates[m];
                let divisor = match (name.as_str(), ty) {
                    ("color", Scalar::U8) => 255.0,
                    ("color", Scalar::U16) => 65535.0,
                    _ => 1.0,
                };
                roles[vertex_element][p] = Role::Channel { slot, divisor };
                slot += 1;
            }
            attributes.push((name, members.len()));
        }

        if let Some(face_element) = header.elements.iter().position(|e| e.name == "face") {
            let face = &header.elements[face_element];
            let corners = face
                .properties
                .iter()
                .position(|p| p.name == "vertex_indices")
                .or_else(|| {
                    face.properties
                        .iter()
                        .position(|p| p.name == "vertex_index")
                })
                .ok_or_else(|| {
                    bad(
                        header.lines,
                        "the face element has no vertex_indices list".into(),
                    )
                })?;
            let property = &face.properties[corners];
            match property.kind {
                PropertyKind::List { item, .. } if item.is_integer() => {
                    roles[face_element][corners] = Role::Corners;
                }
                _ => {
                    return Err(bad(
                        property.line,
                        format!("face property {} must be a list of integers", property.name),
                    ));
                }
            }
        }

        Ok(Layout {
            roles,
            vertex_element,
            vertex_count: vertex.count,
            has_id,
            attributes,
            channels: slot,
        })
    }
}
