//! `surftrack synth`: writes a synthetic incoherent sequence with its ground-truth manifest.

use super::CliError;
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use surftrack::io::Format;
use surftrack::synth::{Scene, SynthOptions, write_sequence};

#[derive(Debug, Args)]
pub struct SynthArgs {
    /// Scene: blobs, merge, split, droplets, morph or rigid.
    scene: Scene,
    /// Output directory (created; an existing non-empty one needs --force).
    #[arg(short, long)]
    out: PathBuf,
    /// Grid cells across the scene's longest side.
    #[arg(long, default_value_t = SynthOptions::default().resolution)]
    resolution: usize,
    /// Number of frames.
    #[arg(long, default_value_t = SynthOptions::default().frames)]
    frames: usize,
    /// Frame file format.
    #[arg(long, value_enum, default_value_t = FrameFormat::Ply)]
    format: FrameFormat,
    /// Write into an existing non-empty output directory, replacing files of the same name.
    #[arg(long)]
    force: bool,
}

/// The frame formats `synth` writes.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum FrameFormat {
    Obj,
    Ply,
    #[value(name = "bobj.gz")]
    BobjGz,
}

impl From<FrameFormat> for Format {
    fn from(f: FrameFormat) -> Format {
        match f {
            FrameFormat::Obj => Format::Obj,
            FrameFormat::Ply => Format::Ply,
            FrameFormat::BobjGz => Format::BobjGz,
        }
    }
}

pub fn run(args: &SynthArgs) -> Result<(), CliError> {
    let options = SynthOptions {
        resolution: args.resolution,
        frames: args.frames,
    };
    let manifest = write_sequence(
        args.scene,
        &options,
        &args.out,
        args.format.into(),
        args.force,
    )?;
    let vertices: Vec<usize> = manifest.frames.iter().map(|f| f.vertices).collect();
    println!(
        "wrote {} frames of '{}' ({}) to {} — {}..{} vertices per frame; ground truth in manifest.json",
        manifest.frames.len(),
        manifest.scene,
        manifest.description,
        args.out.display(),
        vertices.iter().min().unwrap_or(&0),
        vertices.iter().max().unwrap_or(&0),
    );
    Ok(())
}
