//! `surftrack waves`: a wave simulation on a tracked surface, seeded where its topology changes
//! (paper §5).

use super::CliError;
use clap::Args;
use glam::Vec3;
use std::path::PathBuf;
use surftrack::apps::waves::{PointSeed, WaveOptions, waves};

#[derive(Debug, Args)]
pub struct WavesArgs {
    /// The output directory of `surftrack track` (frames/ and events/).
    tracked: PathBuf,
    /// Where to write the frames (created; an existing non-empty one needs --force).
    #[arg(short, long)]
    out: PathBuf,
    /// Write into an existing non-empty output directory, replacing files of the same name.
    #[arg(long)]
    force: bool,
    /// Wave speed, in mean edge lengths (of the first frame) per frame.
    #[arg(long, default_value_t = WaveOptions::default().speed)]
    speed: f64,
    /// Damping of the wave velocity, per frame (0: none, as in the paper).
    #[arg(long, default_value_t = WaveOptions::default().damping)]
    damping: f64,
    /// Height given to each seeded vertex, in mean edge lengths.
    #[arg(long, default_value_t = WaveOptions::default().amplitude)]
    amplitude: f64,
    /// Least number of integration sub-steps per frame; more are taken when stability needs them.
    #[arg(long, default_value_t = WaveOptions::default().min_substeps)]
    substeps: usize,
    /// Do not seed waves at the patches topology changes create (only at --at points).
    #[arg(long)]
    no_topology_seeds: bool,
    /// Also seed the vertex nearest point X,Y,Z in frame FRAME (repeatable).
    #[arg(long, value_name = "FRAME:X,Y,Z", value_parser = parse_seed)]
    at: Vec<PointSeed>,
    /// Move each vertex along its normal by its wave height in the written frames.
    #[arg(long)]
    displace: bool,
}

/// `12:0.5,0,-1` → frame 12, point (0.5, 0, −1).
fn parse_seed(text: &str) -> Result<PointSeed, String> {
    let usage = || format!("'{text}': expected FRAME:X,Y,Z, for example 0:0.5,0,0");
    let (frame, point) = text.split_once(':').ok_or_else(usage)?;
    let frame = frame.trim().parse().map_err(|_| usage())?;
    let coordinates: Vec<f32> = point
        .split(',')
        .map(|c| c.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| usage())?;
    match coordinates[..] {
        [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(PointSeed {
            frame,
            point: Vec3::new(x, y, z),
        }),
        _ => Err(usage()),
    }
}

pub fn run(args: &WavesArgs) -> Result<(), CliError> {
    let options = WaveOptions {
        speed: args.speed,
        damping: args.damping,
        amplitude: args.amplitude,
        min_substeps: args.substeps,
        topology_seeds: !args.no_topology_seeds,
        points: args.at.clone(),
        displace: args.displace,
    };
    let summary = waves(&args.tracked, &args.out, &options, args.force)?;
    let seeded: usize = summary.frames.iter().map(|f| f.seeded).sum();
    let peak = summary
        .frames
        .iter()
        .fold(0.0f64, |m, f| m.max(f.max_height));
    println!(
        "simulated waves on {} frames ({seeded} vertex seeds, highest wave {peak:.3} mean edge lengths) into {}",
        summary.frames.len(),
        args.out.display()
    );
    Ok(())
}
