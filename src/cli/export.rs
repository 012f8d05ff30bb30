//! `surftrack export TRACKED --usd OUT.usdc --ply DIR`: the tracked sequence with persistent ids,
//! carried channels and velocities, in the forms renderers and DCCs read.

use super::CliError;
use clap::{ArgGroup, Args, ValueEnum};
use std::path::PathBuf;
use surftrack::export::{ExportOptions, UpAxis, UsdSettings, export};

#[derive(Debug, Args)]
#[command(group(ArgGroup::new("output").required(true).multiple(true).args(["usd", "ply"])))]
pub struct ExportArgs {
    /// The output directory of `surftrack track` (frames/ with persistent ids).
    tracked: PathBuf,
    /// Write one USD Mesh prim sampled per frame: points, topology, extent, velocities and the
    /// `id` primvar (.usdc or .usd: binary; .usda: text). Written frame by frame.
    #[arg(long, value_name = "FILE")]
    usd: Option<PathBuf>,
    /// Write PLY frames with `id` and velocities as `vx vy vz` into DIR.
    #[arg(long, value_name = "DIR")]
    ply: Option<PathBuf>,
    /// A folder `surftrack propagate` wrote from TRACKED: its channels become primvars (`color` as
    /// displayColor, `uv` as st, others by name) and its positions are used (a carried
    /// displacement moves them).
    #[arg(long, value_name = "DIR")]
    from: Option<PathBuf>,
    /// Frames per second: time codes per second of the stage; velocities are in units per second
    /// at this rate.
    #[arg(long, default_value_t = UsdSettings::default().fps)]
    fps: f64,
    /// Time code of tracked frame 0 (frame k is at START + k).
    #[arg(long, value_name = "START", default_value_t = UsdSettings::default().start)]
    start_time_code: f64,
    /// The stage's up axis.
    #[arg(long, value_enum, default_value_t = Axis::Y)]
    up_axis: Axis,
    /// Metres per scene unit of the stage.
    #[arg(long, default_value_t = UsdSettings::default().meters_per_unit)]
    meters_per_unit: f64,
    /// Replace an existing USD file and write into a non-empty PLY folder.
    #[arg(long)]
    force: bool,
}

/// `--up-axis`.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum Axis {
    Y,
    Z,
}

pub fn run(args: &ExportArgs) -> Result<(), CliError> {
    let options = ExportOptions {
        usd: args.usd.clone(),
        ply: args.ply.clone(),
        from: args.from.clone(),
        settings: UsdSettings {
            fps: args.fps,
            start: args.start_time_code,
            up_axis: match args.up_axis {
                Axis::Y => UpAxis::Y,
                Axis::Z => UpAxis::Z,
            },
            meters_per_unit: args.meters_per_unit,
        },
        force: args.force,
    };
    let summary = export(&args.tracked, &options)?;
    let written: Vec<String> = [&args.usd, &args.ply]
        .into_iter()
        .flatten()
        .map(|p| p.display().to_string())
        .collect();
    let channels = super::channel_names(&summary.channels);
    println!(
        "exported {} frames (up to {} vertices) with ids and velocities{}{} -> {}",
        summary.frames,
        summary.max_vertices,
        if channels.is_empty() {
            ""
        } else {
            ", channels "
        },
        channels.join(", "),
        written.join(", ")
    );
    Ok(())
}
