//! Subcommands and their arguments (clap); each subcommand lives in its own file.

mod batch;
mod bench;
mod demo;
mod error;
mod eval;
mod export;
mod inspect;
mod propagate;
mod render;
mod synth;
mod track;
mod waves;

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
    /// Track a frame sequence (Algorithm 1): write one coherent deforming mesh (persistent vertex
    /// ids) and per-frame event lists into OUT.
    Track(track::TrackArgs),
    /// Track every cache of a manifest (one folder or frame pattern per line) into OUTROOT/NAME/,
    /// several at once, each resumable, with optional propagate and eval steps; caches done
    /// before are skipped, failures recorded. `--index N` (or SLURM_ARRAY_TASK_ID,
    /// JOB_COMPLETION_INDEX) runs one cache, for farm engines; OUTROOT/batch.json reports.
    Batch(batch::BatchArgs),
    /// Time every stage of tracking on ~16k- and ~100k-vertex synthetic sequences, CPU and GPU
    /// paths side by side, and report peak memory.
    Bench(bench::BenchArgs),
    /// Run the whole pipeline on built-in scenes with a merge and a split: generate, track,
    /// propagate a checker texture forward, evaluate and chart, simulate waves from the merge,
    /// render previews; everything goes under ./surftrack-demo/.
    Demo(demo::DemoArgs),
    /// Carry per-vertex data through a tracked sequence using its event lists (paper §4.6): a
    /// checkerboard or image colour, texture coordinates, an attribute painted on a mesh, optionally
    /// as a displacement along normals. Writes PLY (id + channels) and/or OBJ (vt, vertex colours).
    Propagate(propagate::PropagateArgs),
    /// Per-frame quality of a tracked sequence against its input: Hausdorff and mean distance (in the
    /// input's mean edge length), components and Euler characteristic, triangle quality, coherence,
    /// and drift from a synth manifest's ground truth. Prints a table, writes JSON.
    Eval(eval::EvalArgs),
    /// Write a tracked sequence for renderers and DCCs: a USD Mesh sampled per frame with the
    /// persistent `id` primvar, carried channels and `velocities` (motion blur), and/or PLY frames
    /// with velocities as `vx vy vz`.
    Export(export::ExportArgs),
    /// Simulate waves on a tracked surface (paper §5): the wave equation with the cotangent
    /// Laplacian, its state carried through the event lists, waves started where the topology
    /// changes. Writes PLY frames with a `height` vertex property.
    Waves(waves::WavesArgs),
    /// Render every frame of a tracked, propagated or wave folder to PNG off-screen with wgpu
    /// (any Vulkan device; lavapipe will do): vertex colours, a texture through `uv`, or a scalar
    /// such as `height` through a colour map; plus a contact sheet and an animated GIF.
    Render(render::RenderArgs),
}

/// `name (components)` for each carried channel, as the summaries print them.
fn channel_names(channels: &[(String, usize)]) -> Vec<String> {
    channels
        .iter()
        .map(|(name, k)| format!("{name} ({k})"))
        .collect()
}

pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Inspect(args) => inspect::run(&args),
        Command::Synth(args) => synth::run(&args),
        Command::Track(args) => track::run(&args),
        Command::Batch(args) => batch::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Demo(args) => demo::run(&args),
        Command::Propagate(args) => propagate::run(&args),
        Command::Eval(args) => eval::run(&args),
        Command::Export(args) => export::run(&args),
        Command::Waves(args) => waves::run(&args),
        Command::Render(args) => render::run(&args),
    }
}
