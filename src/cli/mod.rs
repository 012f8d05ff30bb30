//! Subcommands and their arguments (clap); each subcommand lives in its own file.

mod error;
mod inspect;
mod synth;

pub use error::CliError;

use clap::{Parser, Subcommand};

/// Turns an incoherent sequence of closed triangle meshes (one per frame, triangulated from scratch
/// each frame) into one temporally coherent deforming mesh plus per-frame event lists.
#[derive(Debug, Parser)]
#[command(name = "surftrack", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print a frame's or a sequence's summary: vertices, faces, components, genus, closed/manifold
    /// status and edge-length statistics. Exits non-zero when a frame cannot be read or is not a closed
    /// 2-manifold.
    Inspect(inspect::InspectArgs),
    /// Generate a synthetic incoherent sequence (marching cubes of an analytic field, re-extracted on a
    /// jittered grid every frame) plus a manifest.json with its ground truth: blobs, merge, split,
    /// droplets, morph, rigid.
    Synth(synth::SynthArgs),
}

pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Inspect(args) => inspect::run(&args),
        Command::Synth(args) => synth::run(&args),
    }
}
