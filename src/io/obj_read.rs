//! Reading Wavefront OBJ frames with `tobj`. Only `v` and `f` statements are handed to it: normals,
//! texture coordinates, groups and materials do not describe the surface, and dropping groups keeps
//! tobj from splitting the mesh (and duplicating shared vertices) into one model per group.
//!
//! tobj numbers vertices in order of first use by a face; a leading synthetic face that uses every
//! vertex in file order makes that order the file's, so vertex `k` of the mesh is the `k`-th `v`
//! line. tobj reports errors without a location, so on failure the text is scanned again to name
//! the offending line.

use super::IoError;
use super::error::Location;
use super::file::read_bytes;
use crate::mesh::{Attribute, IndexedMesh};
use glam::Vec3;
use std::fmt::Write as _;
use std::path::Path;

/// Reads an OBJ frame without repairing it: polygons are fan-triangulated, `f` statements with one
/// or two corners become degenerate triangles (which repair drops and counts), and per-vertex
/// colours (`v x y z r g b`) become the `color` attribute.
pub(crate) fn read_obj(path: &Path) -> Result<IndexedMesh, IoError> {
    let bytes = read_bytes(path)?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|e| not_obj(path, format!("byte {} is not UTF-8 text", e.valid_up_to())))?;
    if let Some(at) = text.find('\0') {
        return Err(not_obj(
            path,
            format!("byte {at} is a NUL byte (binary data)"),
        ));
    }
    let (statements, vertex_count, face_count) = geometry_statements(text);
    if vertex_count == 0 && face_count == 0 {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    }
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: true,
        ignore_points: false,
        ignore_lines: false,
    };
    let (models, _) = tobj::load_obj_buf(&mut statements.as_bytes(), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|error| diagnose(path, text, vertex_count, error))?;
    let Some(model) = models.into_iter().next() else {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    };
    let mesh = model.mesh;

    let positions: Vec<Vec3> = mesh
        .positions
        .chunks_exact(3)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect();
    if let Some(k) = positions.iter().position(|p| !p.is_finite()) {
        return Err(IoError::NonFinite {
            path: path.to_path_buf(),
            at: Location::Line(nth_vertex_line(text, k)),
            value: format!("{}", positions[k]),
        });
    }
    let synthetic = synthetic_triangles(vertex_count);
    let triangles = mesh.indices[3 * synthetic..]
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let mut result = IndexedMesh::new(positions, triangles);
    if !mesh.vertex_color.is_empty() && mesh.vertex_color.len() == 3 * vertex_count {
        result.attributes.push(Attribute {
            name: "color".into(),
            components: 3,
            values: mesh.vertex_color,
        });
    }
    Ok(result)
}

/// The `v` and `f` lines of `text` behind a synthetic face using every vertex in file order, with
/// the numbers of vertices and faces.
fn geometry_statements(text: &str) -> (String, usize, usize) {
    let mut vertices = 0;
    let mut faces = 0;
    let mut kept = String::new();
    for line in text.lines() {
        match line.split_ascii_whitespace().next() {
            Some("v") => vertices += 1,
            Some("f") => faces += 1,
            _ => continue,
        }
        kept.push_str(line);
        kept.push('\n');
    }
    let mut statements = String::with_capacity(kept.len() + 8 * vertices + 8);
    if vertices > 0 {
        statements.push('f');
        for v in 1..=vertices {
            // Writing into a String cannot fail.
            let _ = write!(statements, " {v}");
        }
        statements.push('\n');
    }
    statements.push_str(&kept);
    (statements, vertices, faces)
}

/// Triangles the synthetic face becomes: a fan of `n - 2` for `n ≥ 3` corners, else one (a point
/// or a line, as a degenerate triangle).
fn synthetic_triangles(vertices: usize) -> usize {
    match vertices {
        0 => 0,
        1 | 2 => 1,
        n => n - 2,
    }
}

/// The 1-based line of the `k`-th (0-based) `v` statement.
fn nth_vertex_line(text: &str, k: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, line)| line.split_ascii_whitespace().next() == Some("v"))
        .nth(k)
        .map_or(0, |(n, _)| n + 1)
}

/// Finds the first line with a problem tobj could have stumbled on; falls back to tobj's own
/// message when none is found.
fn diagnose(path: &Path, text: &str, vertex_count: usize, error: tobj::LoadError) -> IoError {
    let path_buf = path.to_path_buf();
    let mut seen_vertices = 0usize;
    let colored = text.lines().any(|line| {
        line.split_ascii_whitespace().next() == Some("v")
            && line.split_ascii_whitespace().count() == 7
    });
    for (n, line) in text.lines().enumerate() {
        let at = Location::Line(n + 1);
        let mut words = line.split_ascii_whitespace();
        match words.next() {
            Some("v") => {
                seen_vertices += 1;
                let values: Vec<&str> = words.collect();
                if let Some(bad) = values.iter().find(|w| w.parse::<f32>().is_err()) {
                    return IoError::NotANumber {
                        path: path_buf,
                        at,
                        text: (*bad).to_string(),
                    };
                }
                let reason = match values.len() {
                    3 if colored => "this vertex has no colour, but others have one",
                    4 if values[3].parse::<f32>() == Ok(0.0) => "the vertex weight w is zero",
                    3 | 4 | 6 => continue,
                    _ => "a vertex needs x y z, x y z w or x y z r g b",
                };
                return IoError::Malformed {
                    path: path_buf,
                    at,
                    reason: reason.into(),
                };
            }
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                if corners.is_empty() {
                    return IoError::Malformed {
                        path: path_buf,
                        at,
                        reason: "a face without corners".into(),
                    };
                }
                for corner in corners {
                    let parts: Vec<&str> = corner.split('/').collect();
                    let index = parts[0].parse::<i64>();
                    let Ok(index) = index.map_err(|_| ()).and_then(|i| {
                        if parts.len() <= 3
                            && parts[1..]
                                .iter()
                                .all(|p| p.is_empty() || p.parse::<i64>().is_ok())
                        {
                            Ok(i)
                        } else {
                            Err(())
                        }
                    }) else {
                        return IoError::NotANumber {
                            path: path_buf,
                            at,
                            text: corner.to_string(),
                        };
                    };
                    let resolved = if index < 0 {
                        seen_vertices as i64 + index
                    } else {
                        index - 1
                    };
                    if !(0..vertex_count as i64).contains(&resolved) {
                        return IoError::IndexOutOfRange {
                            path: path_buf,
                            at,
                            index,
                            count: vertex_count,
                        };
                    }
                }
            }
            _ => {}
        }
    }
    IoError::Malformed {
        path: path_buf,
        at: Location::Section("file"),
        reason: error.to_string(),
    }
}

fn not_obj(path: &Path, reason: String) -> IoError {
    IoError::WrongFormat {
        path: path.to_path_buf(),
        format: "OBJ",
        reason,
    }
}
