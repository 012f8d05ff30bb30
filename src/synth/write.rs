use super::frame::{extract, plan};
use super::manifest::{FrameRecord, Manifest};
use super::scenes::MARGIN_CELLS;
use super::{Scene, SynthError, SynthOptions};
use crate::io::{
    Format, ObjOptions, atomic_write, prepare_output_dir, write_bobj_gz, write_obj, write_ply,
};
use std::path::Path;

/// Name of the manifest written beside the frames.
pub const MANIFEST_FILE: &str = "manifest.json";

/// Generates a scene and writes its frames (`<scene>_0000.<ext>`, …) and `manifest.json` into
/// `out_dir`, one frame at a time.
///
/// Options are checked before anything is written. `out_dir` is created if missing; an existing
/// non-empty directory is refused unless `force` is set. Every file is written atomically.
pub fn write_sequence(
    scene: Scene,
    options: &SynthOptions,
    out_dir: &Path,
    format: Format,
    force: bool,
) -> Result<Manifest, SynthError> {
    let truths = plan(scene, options)?;
    prepare_output_dir(out_dir, force)?;
    let mut frames = Vec::with_capacity(truths.len());
    for truth in truths {
        let mesh = extract(&truth)?;
        let file = format!("{}_{:04}{}", scene.name(), truth.index, format.extension());
        let path = out_dir.join(&file);
        match format {
            Format::Obj => write_obj(&path, &mesh, &ObjOptions::default())?,
            Format::Ply => write_ply(&path, &mesh)?,
            Format::BobjGz => write_bobj_gz(&path, &mesh)?,
        }
        frames.push(FrameRecord {
            file,
            vertices: mesh.positions.len(),
            triangles: mesh.triangles.len(),
            truth,
        });
    }
    let [lo, hi] = scene.bounds();
    let manifest = Manifest {
        scene: scene.name().to_string(),
        description: scene.description().to_string(),
        resolution: options.resolution,
        frame_count: options.frames,
        iso: 0.0,
        margin_cells: MARGIN_CELLS,
        bounds: [lo.to_array(), hi.to_array()],
        frames,
    };
    let json = serde_json::to_vec_pretty(&manifest)?;
    atomic_write(&out_dir.join(MANIFEST_FILE), |w| w.write_all(&json))?;
    Ok(manifest)
}
