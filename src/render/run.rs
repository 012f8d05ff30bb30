//! `render`: every frame of a tracked, propagated or wave folder to PNG from one camera, then a
//! contact sheet and an animated GIF. Frames are read one at a time (twice: once to frame the camera
//! and size the colour map, once to draw), so memory does not depend on the length of the sequence.

use super::RenderError;
use super::camera::Camera;
use super::colour::{Colouring, MissingChannel, PLAIN, vertex_colours};
use super::corners::{Shading, corners};
use super::gpu::Renderer;
use super::image::{Animation, contact_sheet};
use crate::compute::GpuContext;
use crate::io::{ReadOptions, atomic_write, prepare_output_dir, read_frame_with};
use crate::mesh::IndexedMesh;
use crate::propagate::Texture;
use crate::sequence::{FRAMES_DIR, frame_number};
use glam::Vec3;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The contact sheet's file name in the output folder.
pub const SHEET_FILE: &str = "sheet.png";
/// The animation's file name in the output folder.
pub const ANIMATION_FILE: &str = "animation.gif";
/// The summary's file name in the output folder.
pub const RENDER_FILE: &str = "render.json";

/// Thumbnails on a contact sheet, at most.
const SHEET_FRAMES: usize = 16;
/// Widest thumbnail on the sheet, in pixels.
const THUMBNAIL_WIDTH: u32 = 320;
/// Widest frame of the animation, in pixels.
const ANIMATION_WIDTH: u32 = 480;

/// What to colour the surface by.
#[derive(Debug, Clone, PartialEq)]
pub enum ColourChoice {
    /// `color` when the first frame has it, else `height`, else plain grey.
    Auto,
    /// The `color` attribute.
    Vertex,
    /// A PNG looked up through the `uv` attribute.
    Texture(PathBuf),
    /// A one-component attribute through a colour map.
    Attribute(String),
    /// Plain grey.
    Plain,
}

/// How to render.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub shading: Shading,
    pub colour: ColourChoice,
    /// Direction from the sequence's centre toward the camera, when the camera is framed
    /// automatically.
    pub view: Vec3,
    /// A camera given by the user instead of the automatic one.
    pub camera: Option<Camera>,
    pub background: [f32; 3],
    /// Write the contact sheet.
    pub sheet: bool,
    /// Write the animated GIF, at this many frames per second.
    pub gif: Option<f32>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            shading: Shading::Smooth,
            colour: ColourChoice::Auto,
            view: Vec3::new(0.6, 0.45, 1.0),
            camera: None,
            background: [1.0, 1.0, 1.0],
            sheet: true,
            gif: Some(12.0),
        }
    }
}

/// What a run did, also written as `render.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RenderSummary {
    pub frames: usize,
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    pub adapter: String,
    /// Mean wall time to colour, draw, read back and write one frame.
    pub seconds_per_frame: f64,
    pub sheet: Option<PathBuf>,
    pub animation: Option<PathBuf>,
}

/// The frame files of `dir` (or of `dir/frames/`, a tracked folder's), `frame_NNNN.ply`, in
/// numeric order.
pub fn frame_files(dir: &Path) -> Result<Vec<(usize, PathBuf)>, RenderError> {
    let frames_dir = dir.join(FRAMES_DIR);
    let folder = if frames_dir.is_dir() {
        frames_dir
    } else {
        dir.to_path_buf()
    };
    let entries = std::fs::read_dir(&folder).map_err(|e| RenderError::Unreadable {
        path: folder.clone(),
        reason: e.to_string(),
    })?;
    let mut frames: Vec<(usize, PathBuf)> = entries
        .filter_map(|entry| entry.ok())
        .filter_map(|entry| {
            let number = frame_number(&entry.file_name().to_string_lossy())?;
            Some((number, entry.path()))
        })
        .collect();
    frames.sort();
    if frames.is_empty() {
        return Err(RenderError::NoFrames {
            dir: dir.to_path_buf(),
        });
    }
    Ok(frames)
}

/// Renders every frame of `dir` into `out` (`frame_NNNN.png`, [`SHEET_FILE`], [`ANIMATION_FILE`],
/// [`RENDER_FILE`]) on `context`'s device. `out` is refused when it holds anything unless `force`
/// is set; each file is written atomically.
pub fn render(
    dir: &Path,
    out: &Path,
    options: &RenderOptions,
    context: &GpuContext,
    force: bool,
) -> Result<RenderSummary, RenderError> {
    let frames = frame_files(dir)?;
    let renderer = Renderer::new(context, options.width, options.height)?;
    let first = read(&frames[0].1)?;
    let choice = resolve(&options.colour, &first);
    let (min, max, limit) = extent(&frames, &choice)?;
    let colouring = match choice {
        ColourChoice::Vertex => Colouring::Vertex,
        ColourChoice::Texture(path) => Colouring::Texture(Texture::read_png(&path)?),
        ColourChoice::Attribute(name) => Colouring::Scalar { name, limit },
        ColourChoice::Auto | ColourChoice::Plain => Colouring::Plain(PLAIN),
    };
    let camera = options
        .camera
        .unwrap_or_else(|| Camera::framing(min, max, options.view, 0.9));
    prepare_output_dir(out, force)?;
    let background = options
        .background
        .map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
    let sheet_frames = sheet_indices(frames.len());
    let mut thumbnails = Vec::new();
    let thumbnail_factor = options.width.div_ceil(THUMBNAIL_WIDTH);
    let animation_factor = options.width.div_ceil(ANIMATION_WIDTH);
    let mut animation = match options.gif {
        Some(fps) => Some(
            Animation::new(
                options.width / animation_factor,
                options.height / animation_factor,
                fps,
            )
            .ok_or(RenderError::Size {
                width: options.width,
                height: options.height,
                limit: u32::from(u16::MAX),
            })?,
        ),
        None => None,
    };
    let animation_path = out.join(ANIMATION_FILE);
    let started = Instant::now();
    for (k, (number, path)) in frames.iter().enumerate() {
        let mesh = read(path)?;
        let colours = vertex_colours(&mesh, &colouring).map_err(|m| missing(path, &mesh, m))?;
        let image = renderer.draw(
            &corners(&mesh, &colours, options.shading),
            &camera,
            options.shading,
            options.background,
        )?;
        image.write_png(&out.join(format!("frame_{number:04}.png")))?;
        if options.sheet && sheet_frames.contains(&k) {
            thumbnails.push(image.shrunk(thumbnail_factor));
        }
        if let Some(animation) = &mut animation {
            animation
                .push(&image.shrunk(animation_factor))
                .map_err(|e| RenderError::Animation {
                    path: animation_path.clone(),
                    reason: e.to_string(),
                })?;
        }
    }
    let seconds_per_frame = started.elapsed().as_secs_f64() / frames.len() as f64;
    let sheet = if options.sheet {
        let path = out.join(SHEET_FILE);
        contact_sheet(
            &thumbnails,
            4,
            [background[0], background[1], background[2], 255],
        )
        .write_png(&path)?;
        Some(path)
    } else {
        None
    };
    let animation = match animation {
        Some(animation) => {
            animation.write(&animation_path)?;
            Some(animation_path)
        }
        None => None,
    };
    let summary = RenderSummary {
        frames: frames.len(),
        width: options.width,
        height: options.height,
        camera,
        adapter: context.adapter_info().name.clone(),
        seconds_per_frame,
        sheet,
        animation,
    };
    let json = serde_json::to_vec_pretty(&summary).map_err(|e| RenderError::Unreadable {
        path: out.join(RENDER_FILE),
        reason: e.to_string(),
    })?;
    atomic_write(&out.join(RENDER_FILE), |w| w.write_all(&json))?;
    Ok(summary)
}

fn read(path: &Path) -> Result<IndexedMesh, RenderError> {
    let options = ReadOptions {
        repair: false,
        ..ReadOptions::default()
    };
    Ok(read_frame_with(path, &options)?.mesh)
}

/// `Auto` decided on the first frame: its colours, else its wave height, else plain.
fn resolve(choice: &ColourChoice, first: &IndexedMesh) -> ColourChoice {
    let has = |name: &str, k: usize| {
        first
            .attributes
            .iter()
            .any(|a| a.name == name && a.components == k)
    };
    match choice {
        ColourChoice::Auto if has("color", 3) => ColourChoice::Vertex,
        ColourChoice::Auto if has("height", 1) => ColourChoice::Attribute("height".to_string()),
        ColourChoice::Auto => ColourChoice::Plain,
        other => other.clone(),
    }
}

/// The bounds of every frame, and the largest |value| of the colour map's attribute over all of
/// them (1 when there is none or it is 0 everywhere), so every frame shares camera and scale.
fn extent(
    frames: &[(usize, PathBuf)],
    choice: &ColourChoice,
) -> Result<(Vec3, Vec3, f32), RenderError> {
    let (mut min, mut max, mut limit) = (Vec3::INFINITY, Vec3::NEG_INFINITY, 0.0f32);
    for (_, path) in frames {
        let mesh = read(path)?;
        for p in &mesh.positions {
            min = min.min(*p);
            max = max.max(*p);
        }
        if let ColourChoice::Attribute(name) = choice {
            let attribute = mesh
                .attributes
                .iter()
                .find(|a| &a.name == name && a.components == 1)
                .ok_or_else(|| {
                    missing(
                        path,
                        &mesh,
                        MissingChannel {
                            name: name.clone(),
                            components: 1,
                        },
                    )
                })?;
            limit = attribute
                .values
                .iter()
                .filter(|v| v.is_finite())
                .fold(limit, |m, v| m.max(v.abs()));
        }
    }
    if !min.is_finite() || !max.is_finite() {
        min = Vec3::splat(-1.0);
        max = Vec3::splat(1.0);
    }
    Ok((min, max, if limit > 0.0 { limit } else { 1.0 }))
}

fn missing(path: &Path, mesh: &IndexedMesh, channel: MissingChannel) -> RenderError {
    let available: Vec<String> = mesh
        .attributes
        .iter()
        .map(|a| format!("{} ({})", a.name, a.components))
        .collect();
    RenderError::MissingChannel {
        path: path.to_path_buf(),
        name: channel.name,
        components: channel.components,
        available: if available.is_empty() {
            "none".to_string()
        } else {
            available.join(", ")
        },
    }
}

/// Which frames (positions in the sequence) the contact sheet shows: all of a short sequence,
/// else [`SHEET_FRAMES`] evenly spaced from the first to the last.
fn sheet_indices(count: usize) -> Vec<usize> {
    if count <= SHEET_FRAMES {
        return (0..count).collect();
    }
    (0..SHEET_FRAMES)
        .map(|k| (k * (count - 1) + (SHEET_FRAMES - 1) / 2) / (SHEET_FRAMES - 1))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sheet_spans_the_sequence() {
        assert_eq!(sheet_indices(3), vec![0, 1, 2]);
        let picked = sheet_indices(100);
        assert_eq!(picked.len(), SHEET_FRAMES);
        assert_eq!((picked[0], picked[SHEET_FRAMES - 1]), (0, 99));
        assert!(picked.windows(2).all(|w| w[0] < w[1]));
    }
}
