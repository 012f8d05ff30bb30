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
    let (mesh, repairs) = repair(mesh, options.weld_tolerance);
    Ok(Frame { mesh, repairs })
}
