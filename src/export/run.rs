//! `export`: one pass over a tracked sequence that feeds a USD layer and/or PLY frames.

use super::ExportError;
use super::source::ExportSource;
use super::usd::UsdSettings;
use super::usd_file::{UsdFile, UsdForm};
use crate::apps::VelocityStream;
use crate::io::{prepare_output_dir, write_ply};
use crate::mesh::Attribute;
use crate::sequence::frame_name;
use std::path::{Path, PathBuf};

/// Name of the PLY vertex attribute holding velocities (written as `vx vy vz`).
pub const VELOCITY: &str = "velocity";

/// What to write and how.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportOptions {
    /// USD file to write: `.usda` text, `.usdc` or `.usd` binary.
    pub usd: Option<PathBuf>,
    /// Folder of PLY frames with velocities to write.
    pub ply: Option<PathBuf>,
    /// Folder `surftrack propagate` wrote: its channels (and positions) are exported.
    pub from: Option<PathBuf>,
    pub settings: UsdSettings,
    /// Replace an existing USD file, write into a non-empty PLY folder.
    pub force: bool,
}

/// What an export wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct ExportSummary {
    pub frames: usize,
    /// Vertices of the largest frame.
    pub max_vertices: usize,
    /// `(name, components)` of the channels exported beside positions and ids.
    pub channels: Vec<(String, usize)>,
}

/// Exports the tracked sequence in `tracked` as `options` asks. Nothing is read before the
/// options and outputs are checked; each file is written atomically.
pub fn export(tracked: &Path, options: &ExportOptions) -> Result<ExportSummary, ExportError> {
    let form = check(options)?;
    let source = ExportSource::open(tracked, options.from.as_deref())?;
    if let Some(dir) = &options.ply {
        prepare_output_dir(dir, options.force)?;
    }
    let fps = options.settings.fps as f32;
    let mut usd = options
        .usd
        .as_ref()
        .zip(form)
        .map(|(path, form)| UsdFile::new(path, form, options.settings));
    let mut summary = ExportSummary {
        frames: 0,
        max_vertices: 0,
        channels: Vec::new(),
    };
    for frame in VelocityStream::new(|k| source.read(k), source.len(), fps) {
        let frame = frame?;
        if let Some(usd) = &mut usd {
            usd.push(&frame, &source.frame_path(frame.index))?;
        }
        summary.frames += 1;
        summary.max_vertices = summary.max_vertices.max(frame.mesh.positions.len());
        summary.channels = frame
            .mesh
            .attributes
            .iter()
            .map(|a| (a.name.clone(), a.components))
            .collect();
        if let Some(dir) = &options.ply {
            let mut mesh = frame.mesh;
            mesh.attributes.push(Attribute {
                name: VELOCITY.into(),
                components: 3,
                values: frame.velocities.iter().flat_map(|v| v.to_array()).collect(),
            });
            write_ply(&dir.join(frame_name(frame.index)), &mesh)?;
        }
    }
    if let Some(usd) = usd {
        usd.finish()?;
    }
    Ok(summary)
}

/// Refuses what cannot give a useful result before anything is read or written; the form of the
/// USD file, if one is asked for.
fn check(options: &ExportOptions) -> Result<Option<UsdForm>, ExportError> {
    let s = &options.settings;
    let positive = |what: &'static str, value: f64| {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(ExportError::Parameter { what, value })
        }
    };
    positive("frames per second", s.fps)?;
    positive("meters per unit", s.meters_per_unit)?;
    if !s.start.is_finite() {
        return Err(ExportError::Parameter {
            what: "start time code",
            value: s.start,
        });
    }
    if options.usd.is_none() && options.ply.is_none() {
        return Err(ExportError::NoOutput);
    }
    let Some(path) = &options.usd else {
        return Ok(None);
    };
    let form = UsdForm::of(path).ok_or_else(|| ExportError::UsdExtension { path: path.clone() })?;
    if path.exists() && !options.force {
        return Err(ExportError::OutputExists { path: path.clone() });
    }
    Ok(Some(form))
}
