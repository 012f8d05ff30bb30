//! `surftrack demo`: the whole pipeline on built-in scenes with a merge and a split — generate,
//! track, propagate a checker texture forward, evaluate and chart, simulate waves from the merge,
//! render previews — written under `./surftrack-demo/`.

use super::{Cli, CliError};
use clap::{Args, Parser};
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Where to write everything.
    #[arg(short, long, default_value = "surftrack-demo")]
    out: PathBuf,
    /// Replace an earlier demo's output.
    #[arg(long)]
    force: bool,
    /// Grid resolution of the generated scenes.
    #[arg(long, default_value_t = 64)]
    resolution: usize,
    /// Frames per scene.
    #[arg(long, default_value_t = 24)]
    frames: usize,
}

/// Runs one subcommand as if typed on the command line, so the demo exercises exactly what users run.
fn run_command(words: &[&str]) -> Result<(), CliError> {
    println!("\n$ surftrack {}", words.join(" "));
    let cli = Cli::try_parse_from(std::iter::once("surftrack").chain(words.iter().copied()))
        .map_err(|e| CliError::Manifest {
            path: PathBuf::from("demo"),
            message: e.to_string(),
        })?;
    super::run(cli)
}

fn text(p: &Path) -> String {
    p.display().to_string()
}

pub fn run(args: &DemoArgs) -> Result<(), CliError> {
    surftrack::io::prepare_output_dir(&args.out, args.force)?;
    let resolution = args.resolution.to_string();
    let frames = args.frames.to_string();
    let mut charts = Vec::new();
    let mut previews_written = Vec::new();
    for scene in ["merge", "split"] {
        let dir = args.out.join(scene);
        let (input, tracked, checker) = (
            text(&dir.join("input")),
            text(&dir.join("tracked")),
            text(&dir.join("checker")),
        );
        let force: &[&str] = if args.force { &["--force"] } else { &[] };
        let synth = [
            &[
                "synth",
                scene,
                "-o",
                &input,
                "--resolution",
                &resolution,
                "--frames",
                &frames,
            ][..],
            force,
        ]
        .concat();
        run_command(&synth)?;
        run_command(
            &[
                &["track", &input, "-o", &tracked, "--backend", "cpu"][..],
                force,
            ]
            .concat(),
        )?;
        run_command(
            &[
                &[
                    "propagate",
                    &tracked,
                    "--forward",
                    "--checker",
                    "-o",
                    &checker,
                    "--format",
                    "both",
                ][..],
                force,
            ]
            .concat(),
        )?;
        let chart = text(&dir.join("eval.png"));
        run_command(&[&["eval", &tracked, "--plot", &chart][..], force].concat())?;
        charts.push(chart);
        let mut shown = vec![(checker.clone(), text(&dir.join("previews")))];
        if scene == "merge" {
            let waves = text(&dir.join("waves"));
            run_command(&[&["waves", &tracked, "-o", &waves][..], force].concat())?;
            shown.push((waves, text(&dir.join("wave-previews"))));
        }
        for (frames, previews) in shown {
            let render = [&["render", &frames, "-o", &previews][..], force].concat();
            match run_command(&render) {
                Ok(()) => previews_written.push(previews),
                Err(CliError::Compute(error)) => {
                    println!("no previews of {frames}: {error}");
                }
                Err(error) => return Err(error),
            }
        }
    }
    println!(
        "\nDone. Look at:\n  {0}/*/tracked/frames/  the coherent tracked meshes (PLY, persistent `id` per vertex)\n  {0}/*/tracked/events/  the per-frame event lists (docs/event_format.md)\n  {0}/*/checker/         the checker texture carried forward (OBJ with vertex colours, PLY)\n  {0}/*/tracked/eval.json the evaluation above as JSON",
        args.out.display()
    );
    for chart in &charts {
        println!("  {chart}  per-frame coherence, Hausdorff, topology and stage times");
    }
    for previews in &previews_written {
        println!(
            "  {0}/sheet.png  {0}/animation.gif  {0}/frame_*.png  the rendered previews",
            previews
        );
    }
    Ok(())
}
