use super::IoError;
use super::atomic::atomic_write;
use crate::mesh::{Attribute, IndexedMesh};
use std::path::Path;

/// What `write_obj` adds to positions and faces.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ObjOptions {
    /// Write texture coordinates (`vt u v`, one per vertex, faces `f a/a b/b c/c`) from the
    /// 2-component attribute `uv`.
    pub uv: bool,
    /// Write per-vertex colours (`v x y z r g b`, the extension Blender, MeshLab and tobj read)
    /// from the 3-component attribute `color`.
    pub color: bool,
}

/// Writes `mesh` as an OBJ file, atomically. Coordinates are written in the shortest form that
/// reads back to the same `f32`, so positions round-trip exactly; ids cannot be stored in OBJ.
pub fn write_obj(path: &Path, mesh: &IndexedMesh, options: &ObjOptions) -> Result<(), IoError> {
    let unwritable = |reason: String| IoError::Unwritable {
        path: path.to_path_buf(),
        reason,
    };
    check_triangles(mesh).map_err(unwritable)?;
    let uv = options
        .uv
        .then(|| attribute(mesh, "uv", 2))
        .transpose()
        .map_err(unwritable)?;
    let color = options
        .color
        .then(|| attribute(mesh, "color", 3))
        .transpose()
        .map_err(unwritable)?;
    atomic_write(path, |w| {
        writeln!(
            w,
            "# surftrack: {} vertices, {} triangles",
            mesh.positions.len(),
            mesh.triangles.len()
        )?;
        for (v, p) in mesh.positions.iter().enumerate() {
            write!(w, "v {} {} {}", p.x, p.y, p.z)?;
            if let Some(color) = color {
                let c = &color.values[3 * v..3 * v + 3];
                write!(w, " {} {} {}", c[0], c[1], c[2])?;
            }
            writeln!(w)?;
        }
        if let Some(uv) = uv {
            for t in uv.values.chunks_exact(2) {
                writeln!(w, "vt {} {}", t[0], t[1])?;
            }
        }
        for [a, b, c] in mesh.triangles.iter().map(|t| t.map(|v| v + 1)) {
            if uv.is_some() {
                writeln!(w, "f {a}/{a} {b}/{b} {c}/{c}")?;
            } else {
                writeln!(w, "f {a} {b} {c}")?;
            }
        }
        Ok(())
    })
}

/// Every corner names an existing vertex.
pub(crate) fn check_triangles(mesh: &IndexedMesh) -> Result<(), String> {
    match mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, tri)| tri.iter().any(|&v| v as usize >= mesh.positions.len()))
    {
        Some((t, _)) => Err(format!(
            "triangle {t} references a vertex beyond the {} vertices",
            mesh.positions.len()
        )),
        None => Ok(()),
    }
}

/// The attribute `name`, required to have `components` values per vertex.
fn attribute<'a>(
    mesh: &'a IndexedMesh,
    name: &str,
    components: usize,
) -> Result<&'a Attribute, String> {
    mesh.attributes
        .iter()
        .find(|a| {
            a.name == name
                && a.components == components
                && a.values.len() == components * mesh.positions.len()
        })
        .ok_or_else(|| {
            format!("no {components}-component attribute {name:?} with one value per vertex")
        })
}
