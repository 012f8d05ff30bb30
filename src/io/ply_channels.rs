//! How attribute channels are named as PLY vertex properties, one convention shared by the reader
//! and the writer so that every attribute `write_ply` accepts reads back unchanged:
//!
//! | attribute | components | properties |
//! | --- | --- | --- |
//! | `color` | 3 or 4 | `red green blue [alpha]` |
//! | `normal` | 3 | `nx ny nz` |
//! | `uv` | 2 | `u v` (also read: `s t`, `texture_u texture_v`, `texture_s texture_t`) |
//! | `velocity` | 3 | `vx vy vz` (what Houdini and Blender PLY importers read as velocity) |
//! | any name | 1 | the name itself |
//! | any name | k ≥ 2 | `name_0 … name_{k-1}` |

use crate::mesh::Attribute;

/// Named channel groups, tried in this order; the first of each list is what is written.
const CONVENTIONS: [(&str, &[&str]); 8] = [
    ("color", &["red", "green", "blue", "alpha"]),
    ("color", &["red", "green", "blue"]),
    ("normal", &["nx", "ny", "nz"]),
    ("uv", &["u", "v"]),
    ("uv", &["s", "t"]),
    ("uv", &["texture_u", "texture_v"]),
    ("uv", &["texture_s", "texture_t"]),
    ("velocity", &["vx", "vy", "vz"]),
];

/// The vertex property names of an attribute's channels, in component order.
pub(crate) fn channel_names(attribute: &Attribute) -> Vec<String> {
    if let Some((_, names)) = CONVENTIONS
        .iter()
        .find(|(name, names)| *name == attribute.name && names.len() == attribute.components)
    {
        return names.iter().map(|n| n.to_string()).collect();
    }
    if attribute.components == 1 {
        return vec![attribute.name.clone()];
    }
    (0..attribute.components)
        .map(|c| format!("{}_{c}", attribute.name))
        .collect()
}

/// Groups vertex property names (in file order) into attributes: each group is the attribute's
/// name and the positions in `names` of its components, in component order. Groups appear in the
/// order of their first property in the file; a group needs all its members, else they stay
/// single channels.
pub(crate) fn group_channels(names: &[&str]) -> Vec<(String, Vec<usize>)> {
    let mut used = vec![false; names.len()];
    let position = |used: &[bool], wanted: &str| {
        names
            .iter()
            .zip(used)
            .position(|(name, &u)| !u && *name == wanted)
    };
    let mut groups = Vec::new();
    for i in 0..names.len() {
        if used[i] {
            continue;
        }
        let mut group: Option<(String, Vec<usize>)> = None;
        for (attribute, channels) in CONVENTIONS {
            if !channels.contains(&names[i]) {
                continue;
            }
            let found: Option<Vec<usize>> = channels.iter().map(|c| position(&used, c)).collect();
            if let Some(found) = found {
                group = Some((attribute.to_string(), found));
                break;
            }
        }
        if group.is_none()
            && let Some((base, _)) = names[i].rsplit_once('_').filter(|(base, k)| {
                !base.is_empty() && !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit())
            })
        {
            let found: Vec<usize> = (0..)
                .map_while(|c| position(&used, &format!("{base}_{c}")))
                .collect();
            if found.len() >= 2 && found.contains(&i) {
                group = Some((base.to_string(), found));
            }
        }
        let (name, members) = group.unwrap_or_else(|| (names[i].to_string(), vec![i]));
        for &m in &members {
            used[m] = true;
        }
        groups.push((name, members));
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grouped(names: &[&str]) -> Vec<(String, usize)> {
        group_channels(names)
            .into_iter()
            .map(|(name, members)| (name, members.len()))
            .collect()
    }

    #[test]
    fn conventions_group_in_any_order() {
        let expected = [("color", 4), ("uv", 2), ("k", 2)].map(|(n, c)| (n.to_string(), c));
        assert_eq!(
            grouped(&["blue", "u", "green", "v", "red", "k_1", "k_0", "alpha"]),
            expected
        );
        let members = &group_channels(&["blue", "green", "red"])[0].1;
        assert_eq!(members, &[2, 1, 0]);
    }

    #[test]
    fn incomplete_groups_stay_single_channels() {
        assert_eq!(
            grouped(&["nx", "ny", "k_0", "k_2", "s"]),
            ["nx", "ny", "k_0", "k_2", "s"].map(|n| (n.to_string(), 1))
        );
    }

    #[test]
    fn written_names_read_back_as_the_attribute() {
        for (name, components) in [
            ("color", 3),
            ("color", 4),
            ("color", 2),
            ("uv", 2),
            ("uv", 3),
            ("normal", 3),
            ("w", 1),
            ("w_0", 1),
            ("w", 5),
        ] {
            let attribute = Attribute {
                name: name.into(),
                components,
                values: Vec::new(),
            };
            let names = channel_names(&attribute);
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            assert_eq!(grouped(&names), [(name.to_string(), components)]);
        }
    }
}
