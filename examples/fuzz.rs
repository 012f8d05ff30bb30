//! Long fuzz runs of the readers of outside data (`surftrack::fuzz`):
//!
//! ```text
//! cargo run --release --example fuzz -- --target ply-binary --inputs 100000 --seed 1
//! cargo run --release --example fuzz -- --target all --inputs 100000 --saved fuzz-failures
//! ```
//!
//! Prints, per target, the inputs run, how many were accepted and refused, the failures (panics
//! and broken invariants, each saved under `--saved` with its seed and index), the slowest input
//! and the inputs over one second. Exits non-zero when anything failed.

use clap::Parser;
use std::path::PathBuf;
use std::process::ExitCode;
use surftrack::fuzz::{Options, Target, run};

#[derive(Parser)]
struct Args {
    /// obj, ply-ascii, ply-binary, bobj, events, resume, manifest, or all.
    #[arg(long, default_value = "all")]
    target: String,
    #[arg(long, default_value_t = 10_000)]
    inputs: u64,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Folder for the failing inputs.
    #[arg(long, default_value = "fuzz-failures")]
    saved: PathBuf,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let targets: Vec<Target> = if args.target == "all" {
        Target::ALL.to_vec()
    } else if let Some(target) = Target::from_name(&args.target) {
        vec![target]
    } else {
        eprintln!("unknown target {:?}", args.target);
        return ExitCode::FAILURE;
    };
    // Panics are caught and reported per input; the default hook would print each one.
    std::panic::set_hook(Box::new(|_| {}));
    let scratch = match tempfile::tempdir() {
        Ok(dir) => dir,
        Err(e) => {
            eprintln!("cannot make a scratch folder: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut failed = false;
    for target in targets {
        let options = Options {
            inputs: args.inputs,
            seed: args.seed,
            scratch: scratch.path().join(target.name()),
            saved: Some(args.saved.clone()),
        };
        let report = match run(target, &options) {
            Ok(report) => report,
            Err(e) => {
                eprintln!("{}: {e}", target.name());
                failed = true;
                continue;
            }
        };
        println!(
            "{:<10} inputs {:>7}  accepted {:>6}  refused {:>7}  failures {}  slowest {:.2} ms (input {})  over 1 s {}  total {:.1} s",
            target.name(),
            report.inputs,
            report.accepted,
            report.refused,
            report.failures.len(),
            report.slowest.1.as_secs_f64() * 1e3,
            report.slowest.0,
            report.over_one_second,
            report.total.as_secs_f64()
        );
        for failure in &report.failures {
            failed = true;
            println!(
                "  input {}: {}{}",
                failure.index,
                failure.message,
                failure
                    .saved
                    .as_ref()
                    .map(|p| format!(" (saved in {})", p.display()))
                    .unwrap_or_default()
            );
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
