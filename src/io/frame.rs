use super::bobj::read_bobj_gz;
use super::obj_read::read_obj;
use super::ply_read::read_ply;
use super::repair::{RepairReport, repair};
use super::{Format, IoError};
use crate::mesh::IndexedMesh;
use std::path::Path;

/// One frame as read from disk: the repaired mesh and what the repairs changed.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub mesh: IndexedMesh,
    pub repairs: RepairReport,
}

/// How `read_frame_with` treats a file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReadOptions {
    /// Weld, drop degenerate faces and remove unreferenced vertices. Without it the mesh is exactly
    /// what the file holds (polygons triangulated).
    pub repair: bool,
    /// Weld distance as a fraction of the mean edge length.
    pub weld_tolerance: f32,
}

impl Default for ReadOptions {
    /// Repairs on, welding within 1e-6 × the mean edge length: far below any real feature, so only
    /// copies of one vertex (one per face corner, as many exporters write) are merged.
    fn default() -> Self {
        Self {
            repair: true,
            weld_tolerance: 1e-6,
        }
    }
}

/// Reads and repairs one frame (`.obj`, `.ply` or `.bobj.gz`, by extension) with the default
/// options.
pub fn read_frame(path: &Path) -> Result<Frame, IoError> {
    read_frame_with(path, &ReadOptions::default())
}

/// Reads one frame (`.obj`, `.ply` or `.bobj.gz`, by extension).
pub fn read_frame_with(path: &Path, options: &ReadOptions) -> Result<Frame, IoError> {
    let mesh = match Format::from_path(path)? {
        Format::Obj => read_obj(path)?,
        Format::Ply => read_ply(path)?,
        Format::BobjGz => read_bobj_gz(path)?,
    };
    if !options.repair {
        return Ok(Frame {
            mesh,
            repairs: RepairReport::default(),
        });
    }
    if let Some(outlier) = outlier(&mesh) {
        return Err(IoError::Outlier {
            path: path.to_path_buf(),
            vertex: outlier.vertex,
            position: {
                let p = mesh.positions[outlier.vertex];
                format!("({:e}, {:e}, {:e})", p.x, p.y, p.z)
            },
            spread: outlier.spread,
            limit: MAX_SPREAD,
        });
    }
    let (mesh, repairs) = repair(mesh, options.weld_tolerance);
    if mesh.triangles.is_empty() {
        let path = path.to_path_buf();
        return Err(match repairs.degenerate_faces {
            0 => IoError::NoFaces { path },
            faces => IoError::NothingLeft { path, faces },
        });
    }
    Ok(Frame { mesh, repairs })
}

/// How far, in median edge lengths, a vertex may lie from the frame's per-axis median point. A
/// fluid surface spans thousands of edges, not millions; a vertex beyond this is a garbage
/// coordinate (1e30 written for a lost particle), which would stretch the frame's bounds, the
/// weld distance and the tracking grid over nothing.
const MAX_SPREAD: f64 = 1e6;

struct Outlier {
    vertex: usize,
    spread: f64,
}

/// The vertex farthest beyond [`MAX_SPREAD`] from the median point, if any (medians, unlike means
/// and bounds, are not moved by a few garbage vertices).
fn outlier(mesh: &IndexedMesh) -> Option<Outlier> {
    let mut edges: Vec<f64> = mesh
        .triangles
        .iter()
        .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
        .map(|(u, v)| {
            let p = |i: u32| mesh.positions[i as usize].as_dvec3();
            p(u).distance(p(v))
        })
        .filter(|&d| d > 0.0)
        .collect();
    let edge = median(&mut edges)?;
    let middle: [f64; 3] = std::array::from_fn(|axis| {
        let mut values: Vec<f64> = mesh.positions.iter().map(|p| f64::from(p[axis])).collect();
        median(&mut values).unwrap_or(0.0)
    });
    let middle = glam::DVec3::from_array(middle);
    let (vertex, distance) = mesh
        .positions
        .iter()
        .map(|p| (p.as_dvec3() - middle).abs().max_element())
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let spread = distance / edge;
    (spread > MAX_SPREAD).then_some(Outlier { vertex, spread })
}

fn median(values: &mut [f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mid = values.len() / 2;
    let (_, m, _) = values.select_nth_unstable_by(mid, f64::total_cmp);
    Some(*m)
}
