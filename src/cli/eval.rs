//! `surftrack eval`: per-frame quality of a tracked sequence against its input, as a table and JSON.

use super::CliError;
use clap::{Args, Parser};
use std::path::{Path, PathBuf};
use surftrack::compute::{Backend, BackendChoice};
use surftrack::eval::{EvalOptions, EvalReport, evaluate, plot, stage_times};
use surftrack::io::atomic_write;

#[derive(Debug, Args)]
pub struct EvalArgs {
    /// The output directory of `surftrack track`.
    tracked: PathBuf,
    /// The input sequence (directory or pattern). Default: the input frames listed in track.json.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Where to write the JSON report; `-` prints it instead of the table. Default: TRACKED/eval.json.
    #[arg(long, value_name = "PATH")]
    json: Option<PathBuf>,
    /// Where the closest-point queries run.
    #[arg(long, value_enum, default_value_t = BackendChoice::Cpu)]
    backend: BackendChoice,
    /// Minimum angle (degrees) of a good triangle (paper §4.1: 10).
    #[arg(long, default_value_t = EvalOptions::default().angle_threshold)]
    min_angle: f32,
    /// Largest Hausdorff distance to the input, in its mean edge lengths, a frame may have.
    #[arg(long, default_value_t = EvalOptions::default().max_hausdorff)]
    max_hausdorff: f32,
    /// A folder written by `propagate --checker` for this run: report, per frame, the share of
    /// vertices whose carried colour is still one of the checker's two (within 10% of its range).
    #[arg(long, value_name = "DIR")]
    checker: Option<PathBuf>,
    /// Exit non-zero when any frame fails: not a closed manifold, topology unlike the input's,
    /// Hausdorff above --max-hausdorff, or under 99% of triangles above --min-angle.
    #[arg(long)]
    strict: bool,
    /// Also draw the per-frame coherence, Hausdorff distance, topology and stage times as a chart
    /// (PNG or SVG by the extension).
    #[arg(long, value_name = "FILE.png|FILE.svg")]
    plot: Option<PathBuf>,
    /// Replace an existing --plot file.
    #[arg(long, requires = "plot")]
    force: bool,
}

pub fn run(args: &EvalArgs) -> Result<(), CliError> {
    if let Some(path) = &args.plot {
        check_plot_path(path, args.force)?;
    }
    let report = report(args)?;
    match &args.json {
        Some(path) if path.as_os_str() == "-" => {
            println!(
                "{}",
                String::from_utf8_lossy(&serde_json::to_vec_pretty(&report)?)
            )
        }
        _ => {
            print!("{}", report.table());
            let path = write_report(&report, args)?;
            println!("JSON report: {}", path.display());
        }
    }
    if let Some(path) = &args.plot {
        plot(&report, &stage_times(&args.tracked)?, path)?;
        println!("chart: {}", path.display());
    }
    if args.strict && !report.summary.failing_frames.is_empty() {
        return Err(CliError::EvalFailed {
            failing: report.summary.failing_frames.len(),
            total: report.summary.frames,
        });
    }
    Ok(())
}

/// `batch --eval`: this command with its defaults on the tracked folder `tracked`, the report
/// written to `TRACKED/eval.json`.
#[derive(Debug, Parser)]
#[command(name = "--eval", no_binary_name = true)]
struct BatchEval {
    #[command(flatten)]
    args: EvalArgs,
}

/// Evaluates the tracked folder `tracked` with this command's defaults and writes its JSON report.
pub(super) fn evaluate_tracked(tracked: &Path) -> Result<EvalReport, CliError> {
    let args = BatchEval::try_parse_from([tracked.as_os_str()])
        .map_err(|e| CliError::FollowUpArgs {
            flag: "--eval",
            message: e.to_string(),
        })?
        .args;
    let report = report(&args)?;
    write_report(&report, &args)?;
    Ok(report)
}

fn report(args: &EvalArgs) -> Result<EvalReport, CliError> {
    let options = EvalOptions {
        input: args.input.clone(),
        backend: Backend::select(args.backend)?,
        angle_threshold: args.min_angle,
        max_hausdorff: args.max_hausdorff,
        checker: args.checker.clone(),
        ..EvalOptions::default()
    };
    Ok(evaluate(&args.tracked, &options)?)
}

/// Writes the JSON report where `--json` says (default `TRACKED/eval.json`); returns the path.
fn write_report(report: &EvalReport, args: &EvalArgs) -> Result<PathBuf, CliError> {
    let path = args
        .json
        .clone()
        .unwrap_or_else(|| args.tracked.join("eval.json"));
    let json = serde_json::to_vec_pretty(report)?;
    atomic_write(&path, |w| w.write_all(&json))?;
    Ok(path)
}

/// Refuses a chart file that is neither PNG nor SVG, or that exists without --force, before the
/// evaluation runs.
fn check_plot_path(path: &Path, force: bool) -> Result<(), CliError> {
    let refuse = |message: &str| CliError::Manifest {
        path: path.to_path_buf(),
        message: message.to_string(),
    };
    if !matches!(
        path.extension().and_then(|e| e.to_str()),
        Some("png" | "svg")
    ) {
        return Err(refuse("the chart's file must end in .png or .svg"));
    }
    if path.exists() && !force {
        return Err(refuse("exists; pass --force to replace it"));
    }
    Ok(())
}
