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
///
/// The payload is decompressed section by section, each only as far as its count asks and the
/// stream delivers: memory follows the data actually present, so neither a forged count nor a
/// small file that inflates to gigabytes (deflate expands up to 1032:1) can claim more.
pub(crate) fn read_bobj_gz(path: &Path) -> Result<IndexedMesh, IoError> {
    let compressed = read_bytes(path)?;
    let mut payload = Payload {
        path,
        stream: MultiGzDecoder::new(compressed.as_slice()),
        offset: 0,
    };
    let vertex_count = payload.count("vertex")?;
    let positions = payload.records(vertex_count, "vertex")?;
    let normal_count = payload.count("normal")?;
    payload.records(normal_count, "normal")?;
    let triangle_count = payload.count("triangle")?;
    let corners = payload.records(triangle_count, "triangle")?;
    payload.end()?;
    if vertex_count == 0 && triangle_count == 0 {
        return Err(IoError::Empty {
            path: path.to_path_buf(),
        });
    }
    mesh(path, &positions, vertex_count, &corners)
}

/// The decompressed payload, read in order.
struct Payload<'a, R> {
    path: &'a Path,
    stream: R,
    /// Bytes of the payload read so far.
    offset: usize,
}

impl<R: Read> Payload<'_, R> {
    /// Up to `len` bytes, fewer only where the payload ends.
    fn take(&mut self, len: usize) -> Result<Vec<u8>, IoError> {
        let mut bytes = Vec::new();
        (&mut self.stream)
            .take(len as u64)
            .read_to_end(&mut bytes)
            .map_err(|source| IoError::Gzip {
                path: self.path.to_path_buf(),
                source,
            })?;
        self.offset += bytes.len();
        Ok(bytes)
    }

    /// An `i32` count; negative counts are corrupt data.
    fn count(&mut self, what: &'static str) -> Result<usize, IoError> {
        let offset = self.offset;
        let bytes = self.take(4)?;
        let Ok(bytes) = <[u8; 4]>::try_from(bytes.as_slice()) else {
            return Err(IoError::Truncated {
                path: self.path.to_path_buf(),
                at: Location::Byte(offset),
                expected: format!("a 4-byte {what} count, found {} bytes", bytes.len()),
            });
        };
        let count = i32::from_le_bytes(bytes);
        usize::try_from(count).map_err(|_| IoError::InvalidCount {
            path: self.path.to_path_buf(),
            at: Location::Byte(offset),
            what,
            count: i64::from(count),
        })
    }

    /// `count` records of 12 bytes (three 4-byte values each).
    fn records(&mut self, count: usize, what: &'static str) -> Result<Vec<u8>, IoError> {
        let len = count.saturating_mul(12);
        let bytes = self.take(len)?;
        if bytes.len() < len {
            return Err(IoError::Truncated {
                path: self.path.to_path_buf(),
                at: Location::Element {
                    element: what.into(),
                    index: bytes.len() / 12,
                },
                expected: format!(
                    "{count} {what} records ({len} bytes), found {} bytes",
                    bytes.len()
                ),
            });
        }
        Ok(bytes)
    }

    /// Fails if anything follows the triangles.
    fn end(&mut self) -> Result<(), IoError> {
        if self.take(1)?.is_empty() {
            Ok(())
        } else {
            Err(IoError::Malformed {
                path: self.path.to_path_buf(),
                at: Location::Byte(self.offset - 1),
                reason: "unexpected bytes after the triangles".into(),
            })
        }
    }
}

/// The mesh of the decoded sections: coordinates must be finite, corners in range.
fn mesh(
    path: &Path,
    positions: &[u8],
    vertex_count: usize,
    corners: &[u8],
) -> Result<IndexedMesh, IoError> {
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
    let mut triangles = Vec::with_capacity(corners.len() / 12);
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
