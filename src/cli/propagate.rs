//! `surftrack propagate`: carries per-vertex data through a tracked sequence (paper §4.6).

use super::CliError;
use clap::{ArgGroup, Args, Parser, ValueEnum};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use surftrack::propagate::{
    Axis, BlendOptions, Channel, Direction, Displace, Projection, PropagateOptions, Texture, blend,
    propagate,
};

#[derive(Debug, Args)]
#[command(group(ArgGroup::new("direction").required(true).args(["forward", "backward", "blend"])))]
pub struct PropagateArgs {
    /// The output directory of `surftrack track` (frames/ and events/).
    tracked: PathBuf,
    /// Start from frame 0 and carry values forward through each transition.
    #[arg(long)]
    forward: bool,
    /// Start from the last frame and carry values backward to frame 0.
    #[arg(long)]
    backward: bool,
    /// Carry the channels forward from frame 0 and backward from the last frame (painted there by
    /// the same options, or by --end-image / --end-from), and blend the two on every frame by its
    /// position in the sequence (paper §5, morphs). Writes OUT/forward/, OUT/backward/ and the blend
    /// in OUT.
    #[arg(long)]
    blend: bool,
    /// With --blend: the PNG image painted on the last frame instead of --image.
    #[arg(long, value_name = "PNG", requires = "blend", requires = "image")]
    end_image: Option<PathBuf>,
    /// With --blend: the mesh file holding --attribute for the last frame instead of --from.
    #[arg(long, value_name = "MESH", requires = "blend", requires = "attribute")]
    end_from: Option<PathBuf>,
    /// Where to write the frames (created; an existing non-empty one needs --force).
    /// Default: TRACKED/propagated.
    #[arg(short, long)]
    out: Option<PathBuf>,
    /// Write into an existing non-empty output directory, replacing files of the same name.
    #[arg(long)]
    force: bool,
    /// Colour the start frame with a 3-D checkerboard (the default when no other colour is given).
    #[arg(long)]
    checker: bool,
    /// Checker cell size, in mean edge lengths of the start frame.
    #[arg(long, default_value_t = 8.0)]
    checker_size: f32,
    /// Colour the start frame with a PNG image mapped through --projection.
    #[arg(long, value_name = "PNG")]
    image: Option<PathBuf>,
    /// Give the start frame texture coordinates (`uv`) from --projection.
    #[arg(long)]
    uv: bool,
    /// How --image and --uv map the start frame onto the unit square.
    #[arg(long, value_enum, default_value_t = ProjectionArg::Spherical)]
    projection: ProjectionArg,
    /// Carry the vertex attribute NAME of the mesh file given with --from (for example `color`
    /// painted in Blender on a copy of the start frame).
    #[arg(long, value_name = "NAME", requires = "from")]
    attribute: Option<String>,
    /// The mesh file holding --attribute: matched by persistent id when it has them, else by
    /// closest point.
    #[arg(long, value_name = "MESH", requires = "attribute")]
    from: Option<PathBuf>,
    /// Displace vertices along their normals by SCALE mean edge lengths times the carried scalar
    /// (the luminance of the colour, or the --attribute value when it has one component).
    #[arg(long, value_name = "SCALE")]
    displace: Option<f32>,
    /// Frame file format.
    #[arg(long, value_enum, default_value_t = OutputFormat::Ply)]
    format: OutputFormat,
}

/// Projections offered on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum ProjectionArg {
    Spherical,
    PlanarX,
    PlanarY,
    PlanarZ,
}

impl From<ProjectionArg> for Projection {
    fn from(p: ProjectionArg) -> Projection {
        match p {
            ProjectionArg::Spherical => Projection::Spherical,
            ProjectionArg::PlanarX => Projection::Planar(Axis::X),
            ProjectionArg::PlanarY => Projection::Planar(Axis::Y),
            ProjectionArg::PlanarZ => Projection::Planar(Axis::Z),
        }
    }
}

/// Which files are written per frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum OutputFormat {
    /// Binary PLY: persistent `id` and every channel as vertex properties.
    Ply,
    /// OBJ: `vt` from `uv`, vertex colours from `color`.
    Obj,
    /// Both.
    Both,
}

pub fn run(args: &PropagateArgs) -> Result<(), CliError> {
    println!("{}", propagate_tracked(args)?);
    Ok(())
}

/// `batch --propagate ARGS` takes this command's arguments as one string, split at spaces.
#[derive(Debug, Parser)]
#[command(name = "--propagate", no_binary_name = true)]
struct BatchPropagate {
    #[command(flatten)]
    args: PropagateArgs,
}

impl PropagateArgs {
    /// The arguments `text` of `batch --propagate` for the tracked folder `tracked`. The carried
    /// frames go into the cache's own folder (`TRACKED/propagated`), which the batch owns and a
    /// rerun rewrites, so `--out` is refused and `--force` implied.
    pub(super) fn for_batch(tracked: &Path, text: &str) -> Result<Self, CliError> {
        let words = std::iter::once(tracked.as_os_str().to_owned())
            .chain(text.split_whitespace().map(OsString::from));
        let bad = |message: String| CliError::FollowUpArgs {
            flag: "--propagate",
            message,
        };
        let mut args = BatchPropagate::try_parse_from(words)
            .map_err(|e| {
                bad(e
                    .to_string()
                    .trim_start_matches("error: ")
                    .trim()
                    .to_string())
            })?
            .args;
        if args.out.is_some() {
            return Err(bad(
                "takes no --out: each cache's carried frames go into OUTROOT/NAME/propagated"
                    .to_string(),
            ));
        }
        args.force = true;
        Ok(args)
    }
}

/// The channels the options paint on one end, with its image and attribute file.
fn channels(
    args: &PropagateArgs,
    image: Option<&PathBuf>,
    from: Option<&PathBuf>,
) -> Result<Vec<Channel>, CliError> {
    let projection = Projection::from(args.projection);
    let mut channels = Vec::new();
    if let Some(path) = image {
        channels.push(Channel::image(Texture::read_png(path)?, projection));
    }
    if let (Some(name), Some(path)) = (&args.attribute, from) {
        channels.push(Channel::attribute(path.clone(), name));
    }
    let has_colour = channels.iter().any(|c| c.name == "color");
    if args.checker || !has_colour && args.attribute.is_none() {
        channels.push(Channel::checker(args.checker_size));
    }
    if args.uv {
        channels.push(Channel::uv(projection));
    }
    Ok(channels)
}

/// Carries the data `args` asks for through the tracked folder (or blends it, with `--blend`);
/// returns the line that says so.
pub(super) fn propagate_tracked(args: &PropagateArgs) -> Result<String, CliError> {
    let channels = channels(args, args.image.as_ref(), args.from.as_ref())?;
    let displace = args.displace.map(|scale| Displace {
        channel: match &args.attribute {
            Some(name) if !channels.iter().any(|c| c.name == "color") => name.clone(),
            _ => "color".to_string(),
        },
        scale,
    });
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| args.tracked.join("propagated"));
    if args.blend {
        let last = channels_at_end(args)?;
        let options = BlendOptions {
            first: channels,
            last,
            displace,
            ply: args.format != OutputFormat::Obj,
            obj: args.format != OutputFormat::Ply,
        };
        let summary = blend(&args.tracked, &out, &options, args.force)?;
        return Ok(format!(
            "blended {} carried forward from frame 0 with the same carried backward from frame {} over {} frames into {}",
            super::channel_names(&summary.forward.channels).join(", "),
            summary.backward.start.frame,
            summary.weights.len(),
            out.display()
        ));
    }
    let options = PropagateOptions {
        direction: if args.backward {
            Direction::Backward
        } else {
            Direction::Forward
        },
        channels,
        displace,
        ply: args.format != OutputFormat::Obj,
        obj: args.format != OutputFormat::Ply,
    };
    let summary = propagate(&args.tracked, &out, &options, args.force)?;
    let names = super::channel_names(&summary.channels);
    Ok(format!(
        "carried {} {} from frame {} through {} frames into {}",
        if names.len() == 1 {
            "channel"
        } else {
            "channels"
        },
        names.join(", "),
        summary.start.frame,
        summary.vertices.len(),
        out.display()
    ))
}

/// The channels painted on the last frame of a blend.
fn channels_at_end(args: &PropagateArgs) -> Result<Vec<Channel>, CliError> {
    channels(
        args,
        args.end_image.as_ref().or(args.image.as_ref()),
        args.end_from.as_ref().or(args.from.as_ref()),
    )
}
