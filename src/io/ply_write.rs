use super::IoError;
use super::atomic::atomic_write;
use super::obj_write::check_triangles;
use super::ply_channels::{channel_names, group_channels};
use super::ply_header::{PlyEncoding, Scalar};
use crate::mesh::IndexedMesh;
use std::io::Write;
use std::path::Path;

/// Largest id a `double` property holds exactly.
const MAX_EXACT_ID: u64 = 1 << 53;

/// Writes `mesh` as binary little-endian PLY, atomically (the layout is described in the module
/// documentation of `surftrack::io`).
pub fn write_ply(path: &Path, mesh: &IndexedMesh) -> Result<(), IoError> {
    write_ply_with(path, mesh, PlyEncoding::BinaryLittleEndian)
}

/// Writes `mesh` as PLY in the given encoding, atomically.
pub fn write_ply_with(
    path: &Path,
    mesh: &IndexedMesh,
    encoding: PlyEncoding,
) -> Result<(), IoError> {
    let layout = VertexLayout::new(mesh).map_err(|reason| IoError::Unwritable {
        path: path.to_path_buf(),
        reason,
    })?;
    let header = header(mesh, &layout, encoding);
    atomic_write(path, |w| {
        w.write_all(header.as_bytes())?;
        match encoding {
            PlyEncoding::Ascii => write_ascii(w, mesh, &layout),
            PlyEncoding::BinaryLittleEndian => write_binary::<false>(w, mesh, &layout),
            PlyEncoding::BinaryBigEndian => write_binary::<true>(w, mesh, &layout),
        }
    })
}

/// The vertex properties after x, y, z: how ids are stored and the channel names.
struct VertexLayout {
    id: Option<Scalar>,
    channels: Vec<String>,
}

impl VertexLayout {
    /// Checks that the mesh fits the format and that its attribute names read back as the same
    /// attributes.
    fn new(mesh: &IndexedMesh) -> Result<VertexLayout, String> {
        check_triangles(mesh)?;
        let n = mesh.positions.len();
        if i32::try_from(n).is_err() {
            return Err("more vertices than an int index holds".into());
        }
        let id = match &mesh.ids {
            None => None,
            Some(ids) if ids.len() != n => {
                return Err(format!("{} ids for {n} vertices", ids.len()));
            }
            Some(ids) => {
                let max = ids.iter().copied().max().unwrap_or(0);
                if max <= u64::from(u32::MAX) {
                    Some(Scalar::U32)
                } else if max <= MAX_EXACT_ID {
                    Some(Scalar::F64)
                } else {
                    return Err(format!(
                        "vertex id {max} exceeds 2^53, the largest a PLY double holds exactly"
                    ));
                }
            }
        };
        let mut channels = Vec::new();
        for attribute in &mesh.attributes {
            if attribute.components == 0 || attribute.values.len() != attribute.components * n {
                return Err(format!(
                    "attribute {:?} has {} values for {n} vertices of {} components",
                    attribute.name,
                    attribute.values.len(),
                    attribute.components
                ));
            }
            let names = channel_names(attribute);
            if let Some(bad) = names
                .iter()
                .find(|name| name.is_empty() || !name.bytes().all(|b| b.is_ascii_graphic()))
            {
                return Err(format!(
                    "attribute channel name {bad:?} is not a PLY property name"
                ));
            }
            channels.extend(names);
        }
        let names: Vec<&str> = channels.iter().map(String::as_str).collect();
        if let Some((k, _)) = names
            .iter()
            .enumerate()
            .find(|(k, name)| names[..*k].contains(name))
        {
            return Err(format!("two attribute channels are named {:?}", names[k]));
        }
        if let Some(reserved) = names.iter().find(|n| ["x", "y", "z", "id"].contains(n)) {
            return Err(format!(
                "attribute channel {reserved:?} collides with a vertex property"
            ));
        }
        let expected: Vec<(String, usize)> = mesh
            .attributes
            .iter()
            .map(|a| (a.name.clone(), a.components))
            .collect();
        let read_back: Vec<(String, usize)> = group_channels(&names)
            .into_iter()
            .map(|(name, members)| (name, members.len()))
            .collect();
        if read_back != expected {
            return Err(format!(
                "attribute names {expected:?} would read back as {read_back:?}"
            ));
        }
        Ok(VertexLayout { id, channels })
    }
}

fn header(mesh: &IndexedMesh, layout: &VertexLayout, encoding: PlyEncoding) -> String {
    let mut header = format!(
        "ply\nformat {} 1.0\ncomment written by surftrack\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\n",
        encoding.keyword(),
        mesh.positions.len()
    );
    if let Some(id) = layout.id {
        header += &format!("property {} id\n", id.name());
    }
    for channel in &layout.channels {
        header += &format!("property float {channel}\n");
    }
    header += &format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.triangles.len()
    );
    header
}

/// Channel values of vertex `v`, attribute after attribute.
fn channels(mesh: &IndexedMesh, v: usize) -> impl Iterator<Item = f32> + '_ {
    mesh.attributes.iter().flat_map(move |a| {
        a.values[v * a.components..(v + 1) * a.components]
            .iter()
            .copied()
    })
}

fn write_binary<const BIG: bool>(
    w: &mut dyn Write,
    mesh: &IndexedMesh,
    layout: &VertexLayout,
) -> std::io::Result<()> {
    fn put<const BIG: bool, const N: usize>(out: &mut Vec<u8>, le: [u8; N]) {
        if BIG {
            out.extend(le.iter().rev());
        } else {
            out.extend_from_slice(&le);
        }
    }
    let mut out = Vec::with_capacity(
        mesh.positions.len() * (12 + 8 + 4 * layout.channels.len()) + mesh.triangles.len() * 13,
    );
    for (v, p) in mesh.positions.iter().enumerate() {
        for c in p.to_array() {
            put::<BIG, 4>(&mut out, c.to_le_bytes());
        }
        if let Some(ids) = &mesh.ids {
            match layout.id {
                Some(Scalar::F64) => put::<BIG, 8>(&mut out, (ids[v] as f64).to_le_bytes()),
                // At most u32::MAX, as chosen by VertexLayout.
                _ => put::<BIG, 4>(&mut out, (ids[v] as u32).to_le_bytes()),
            }
        }
        for value in channels(mesh, v) {
            put::<BIG, 4>(&mut out, value.to_le_bytes());
        }
    }
    for tri in &mesh.triangles {
        out.push(3);
        for &v in tri {
            // Below the vertex count, which fits an int.
            put::<BIG, 4>(&mut out, (v as i32).to_le_bytes());
        }
    }
    w.write_all(&out)
}

fn write_ascii(
    w: &mut dyn Write,
    mesh: &IndexedMesh,
    layout: &VertexLayout,
) -> std::io::Result<()> {
    for (v, p) in mesh.positions.iter().enumerate() {
        write!(w, "{} {} {}", p.x, p.y, p.z)?;
        if let (Some(ids), Some(_)) = (&mesh.ids, layout.id) {
            write!(w, " {}", ids[v])?;
        }
        for value in channels(mesh, v) {
            write!(w, " {value}")?;
        }
        writeln!(w)?;
    }
    for [a, b, c] in &mesh.triangles {
        writeln!(w, "3 {a} {b} {c}")?;
    }
    Ok(())
}
