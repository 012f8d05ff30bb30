//! Blender/Mantaflow fluid mesh caches (`.bobj.gz`): a gzip stream holding an `i32` vertex count,
//! that many `f32 × 3` positions, an `i32` normal count and normals, an `i32` triangle count and
//! `i32 × 3` corner indices, all little-endian. Normals are skipped on reading (the tracker
//! recomputes them) and written as area-weighted vertex normals for Blender.

use super::IoError;
use super::atomic::atomic_write;
use super::error::Location;
use super::file::read_bytes;
use super::obj_write::check_triangles;
use crate::mesh::IndexedMesh;
use flate2::Compression;
use flate2::read::MultiGzDecoder;
use flate2::write::GzEncoder;
use glam::Vec3;
use std::io::{Read, Write};
use std::path::Path;

/// Reads a `.bobj.gz` frame without repairing it.
pub(crate) fn read_bobj_gz(path: &Path) -> Result<IndexedMesh, IoError> {
    let compressed = read_bytes(path)?;
    let mut data = Vec::with_capacity(uncompressed_size_hint(&compressed));
    MultiGzDecoder::new(compressed.as_slice())
        .read_to_end(&mut data)
        .map_err(|source| IoError::Gzip {
            path: path.to_path_buf(),
            source,
        })?;
    parse(path, &data)
}

/// The uncompressed size a gzip stream records in its last four bytes, bounded by the largest
/// expansion deflate allows (1032:1) so a forged trailer cannot force a huge allocation.
fn uncompressed_size_hint(compressed: &[u8]) -> usize {
    let recorded = compressed
        .last_chunk::<4>()
        .map_or(0, |&trailer| u32::from_le_bytes(trailer) as usize);
    recorded.min(compressed.len().saturating_mul(1032))
}

/// Decodes the uncompressed payload, checking every count against the bytes that remain before
/// allocating for it.
fn parse(path: &Path, data: &[u8]) -> Result<IndexedMesh, IoError> {
    let mut rest = data;
    let vertex_count = take_count(path, &mut rest, data.len(), "vertex")?;
    let positions = take_records(path, &mut rest, vertex_count, "vertex")?;
    let normal_count = take_count(path, &mut rest, data.len(), "normal")?;
    take_records(path, &mut rest, normal_count, "normal")?;
    let triangle_count = take_count(path, &mut rest, data.len(), "triangle")?;
    let corners = take_records(path, &mut rest, triangle_count, "triangle")?;
    if !rest.is_empty() {
        return Err(IoError::Malformed {
            path: path.to_path_buf(),
            at: Location::Section("end of data"),
            reason: format!("{} unexpected bytes after the triangles", rest.len()),
        });
    }
    if vertex_count == 0 && triangle_count == 0 {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    }

    let positions: Vec<Vec3> = bytemuck::pod_collect_to_vec::<u8, [u32; 3]>(positions)
        .into_iter()
        .map(|p| Vec3::from_array(p.map(|bits| f32::from_bits(u32::from_le(bits)))))
        .collect();
    if let Some((i, p)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(IoError::NonFinite {
            path: path.to_path_buf(),
            at: Location::Element {
                element: "vertex".into(),
                index: i,
            },
            value: format!("{p}"),
        });
    }
    let mut triangles = Vec::with_capacity(triangle_count);
    for (t, corner) in bytemuck::pod_collect_to_vec::<u8, [i32; 3]>(corners)
        .into_iter()
        .enumerate()
    {
        let mut tri = [0u32; 3];
        for (slot, &index) in tri.iter_mut().zip(&corner) {
            let index = i32::from_le(index);
            *slot = u32::try_from(index)
                .ok()
                .filter(|&v| (v as usize) < vertex_count)
                .ok_or_else(|| IoError::IndexOutOfRange {
                    path: path.to_path_buf(),
                    at: Location::Element {
                        element: "triangle".into(),
                        index: t,
                    },
                    index: i64::from(index),
                    count: vertex_count,
                })?;
        }
        triangles.push(tri);
    }
    Ok(IndexedMesh::new(positions, triangles))
}

/// Reads an `i32` count from the `rest` of a payload of `total` bytes; negative counts are corrupt
/// data.
fn take_count(
    path: &Path,
    rest: &mut &[u8],
    total: usize,
    what: &'static str,
) -> Result<usize, IoError> {
    let offset = total - rest.len();
    let Some((bytes, tail)) = rest.split_first_chunk::<4>() else {
        return Err(IoError::Truncated {
            path: path.to_path_buf(),
            at: Location::Byte(offset),
            expected: format!("a 4-byte {what} count, found {} bytes", rest.len()),
        });
    };
    *rest = tail;
    let count = i32::from_le_bytes(*bytes);
    usize::try_from(count).map_err(|_| IoError::InvalidCount {
        path: path.to_path_buf(),
        at: Location::Byte(offset),
        what,
        count: i64::from(count),
    })
}

/// Splits off `count` records of 12 bytes (three 4-byte values each).
fn take_records<'a>(
    path: &Path,
    rest: &mut &'a [u8],
    count: usize,
    what: &'static str,
) -> Result<&'a [u8], IoError> {
    let len = count.saturating_mul(12);
    if rest.len() < len {
        return Err(IoError::Truncated {
            path: path.to_path_buf(),
            at: Location::Element {
                element: what.into(),
                index: rest.len() / 12,
            },
            expected: format!(
                "{count} {what} records ({len} bytes), found {} bytes",
                rest.len()
            ),
        });
    }
    let (records, tail) = rest.split_at(len);
    *rest = tail;
    Ok(records)
}

/// Writes `mesh` as a `.bobj.gz` frame, atomically. Vertex ids and attributes have no place in
/// this format and are not written.
pub fn write_bobj_gz(path: &Path, mesh: &IndexedMesh) -> Result<(), IoError> {
    let unwritable = |reason: String| IoError::Unwritable {
        path: path.to_path_buf(),
        reason,
    };
    let vertex_count = i32::try_from(mesh.positions.len())
        .map_err(|_| unwritable("more vertices than an i32 count holds".into()))?;
    let triangle_count = i32::try_from(mesh.triangles.len())
        .map_err(|_| unwritable("more triangles than an i32 count holds".into()))?;
    check_triangles(mesh).map_err(unwritable)?;

    let mut data = Vec::with_capacity(12 + 24 * mesh.positions.len() + 12 * mesh.triangles.len());
    data.extend_from_slice(&vertex_count.to_le_bytes());
    for value in mesh.positions.iter().flat_map(|p| p.to_array()) {
        data.extend_from_slice(&value.to_le_bytes());
    }
    data.extend_from_slice(&vertex_count.to_le_bytes());
    for value in area_weighted_normals(mesh)
        .iter()
        .flat_map(|n| n.to_array())
    {
        data.extend_from_slice(&value.to_le_bytes());
    }
    data.extend_from_slice(&triangle_count.to_le_bytes());
    for &index in mesh.triangles.iter().flatten() {
        // In range of `vertex_count`, itself an i32, as checked above.
        data.extend_from_slice(&(index as i32).to_le_bytes());
    }
    atomic_write(path, |w| {
        let mut encoder = GzEncoder::new(w, Compression::fast());
        encoder.write_all(&data)?;
        encoder.finish()?;
        Ok(())
    })
}

/// Unit vertex normals, each the sum of its triangles' area vectors (cross products), so large
/// triangles weigh more. Vertices without area get a zero normal.
fn area_weighted_normals(mesh: &IndexedMesh) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; mesh.positions.len()];
    for tri in &mesh.triangles {
        let [a, b, c] = tri.map(|v| mesh.positions[v as usize]);
        let area = (b - a).cross(c - a);
        for &v in tri {
            normals[v as usize] += area;
        }
    }
    normals.iter().map(|n| n.normalize_or_zero()).collect()
}
