//! `surftrack render`: pictures of every frame of a tracked, propagated or wave folder, a contact
//! sheet and an animated GIF, drawn off-screen with wgpu.

use super::CliError;
use clap::{Args, ValueEnum};
use glam::Vec3;
use std::path::PathBuf;
use surftrack::compute::{Backend, BackendChoice, ComputeError};
use surftrack::render::{Camera, ColourChoice, RenderOptions, Shading, render};

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A folder of frames: `surftrack track`'s output (its frames/), or what `propagate` or
    /// `waves` wrote.
    dir: PathBuf,
    /// Where to write the PNG frames, sheet.png, animation.gif and render.json (created; an
    /// existing non-empty one needs --force).
    #[arg(short, long)]
    out: PathBuf,
    /// Write into an existing non-empty output directory, replacing files of the same name.
    #[arg(long)]
    force: bool,
    /// Image width in pixels.
    #[arg(long, default_value_t = RenderOptions::default().width)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = RenderOptions::default().height)]
    height: u32,
    /// Normals per triangle (flat), interpolated (smooth), or no lighting (unlit: exact colours).
    #[arg(long, value_enum, default_value_t = ShadingArg::Smooth)]
    shading: ShadingArg,
    /// What to colour by: `auto` takes `color`, else `height`, else grey.
    #[arg(long, value_enum, default_value_t = ColourArg::Auto)]
    colour: ColourArg,
    /// Colour by this PNG looked up through the frames' `uv` attribute.
    #[arg(long, value_name = "PNG", conflicts_with_all = ["attribute"])]
    texture: Option<PathBuf>,
    /// Colour by this one-component attribute through a blue–white–red map (0 is white).
    #[arg(long, value_name = "NAME")]
    attribute: Option<String>,
    /// Direction from the sequence's centre toward the camera, when it is framed automatically.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, default_value = "0.6,0.45,1")]
    view: Vec3,
    /// Put the camera here instead (with --target), looking at --target with Y up.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, requires = "target")]
    eye: Option<Vec3>,
    /// The point the camera given with --eye looks at.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vector, requires = "eye")]
    target: Option<Vec3>,
    /// Background colour, 0..1 per channel.
    #[arg(long, value_name = "R,G,B", value_parser = parse_vector, default_value = "1,1,1")]
    background: Vec3,
    /// Frames per second of the animated GIF.
    #[arg(long, default_value_t = 12.0)]
    fps: f32,
    /// Write no contact sheet.
    #[arg(long)]
    no_sheet: bool,
    /// Write no animated GIF.
    #[arg(long)]
    no_gif: bool,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum ShadingArg {
    Smooth,
    Flat,
    Unlit,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum ColourArg {
    Auto,
    Vertex,
    Plain,
}

/// `1,0.5,-2` → (1, 0.5, −2).
fn parse_vector(text: &str) -> Result<Vec3, String> {
    let values: Vec<f32> = text
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}': expected three numbers X,Y,Z"))?;
    match values[..] {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("'{text}': expected three finite numbers X,Y,Z")),
    }
}

pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let colour = match (&args.texture, &args.attribute, args.colour) {
        (Some(png), _, _) => ColourChoice::Texture(png.clone()),
        (None, Some(name), _) => ColourChoice::Attribute(name.clone()),
        (None, None, ColourArg::Auto) => ColourChoice::Auto,
        (None, None, ColourArg::Vertex) => ColourChoice::Vertex,
        (None, None, ColourArg::Plain) => ColourChoice::Plain,
    };
    let options = RenderOptions {
        width: args.width,
        height: args.height,
        shading: match args.shading {
            ShadingArg::Smooth => Shading::Smooth,
            ShadingArg::Flat => Shading::Flat,
            ShadingArg::Unlit => Shading::Unlit,
        },
        colour,
        view: args.view,
        camera: args.eye.zip(args.target).map(|(eye, target)| Camera {
            eye,
            target,
            up: Vec3::Y,
            fov_degrees: 30.0,
        }),
        background: args.background.to_array(),
        sheet: !args.no_sheet,
        gif: (!args.no_gif).then_some(args.fps),
    };
    let backend = Backend::select(BackendChoice::Gpu)?;
    let context = backend.gpu().ok_or(ComputeError::NoAdapter)?;
    let summary = render(&args.dir, &args.out, &options, context, args.force)?;
    println!(
        "rendered {} frames of {} × {} on {} ({:.3} s per frame) into {}",
        summary.frames,
        summary.width,
        summary.height,
        summary.adapter,
        summary.seconds_per_frame,
        args.out.display()
    );
    for path in summary.sheet.iter().chain(&summary.animation) {
        println!("  {}", path.display());
    }
    Ok(())
}
