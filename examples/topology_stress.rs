//! Long stress run of `constrain_topology` on random adversarial cases (the test suite runs a
//! shorter one): `cargo run --release --example topology_stress -- --cases N [--from SEED] [--kind KIND]`
//! (KIND one of the case kinds, e.g. `SelfIntersecting`: only the seeds of that kind run).
//!
//! Prints the number of cases, failures (each with its seed, which reproduces it), whole-surface
//! replacements, the attempt that succeeded, the worst distance of a fill vertex from Θ's zero set
//! and the mean share of input vertices replaced, per case kind.

#[path = "../tests/topology_support/mod.rs"]
pub mod topology_support;

use std::time::Instant;

use topology_support::{KINDS, Kind, case, check};

#[derive(Default)]
struct Tally {
    cases: usize,
    changed: usize,
    whole: usize,
    later_attempts: usize,
    worst: f64,
    replaced: f64,
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let value = |flag: &str, default: u64| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .and_then(|s| s.parse().ok())
            .unwrap_or(default)
    };
    let cases = value("--cases", 10_000);
    let from = value("--from", 0);
    let only = args
        .iter()
        .position(|a| a == "--kind")
        .and_then(|i| args.get(i + 1))
        .cloned();
    let start = Instant::now();
    let mut tallies: Vec<(Kind, Tally)> = KINDS.iter().map(|&k| (k, Tally::default())).collect();
    let mut failures = 0usize;
    for seed in from..from + cases {
        let c = case(seed);
        if only.as_ref().is_some_and(|k| *k != format!("{:?}", c.kind)) {
            continue;
        }
        let tally = &mut tallies
            .iter_mut()
            .find(|(k, _)| *k == c.kind)
            .expect("every kind is tallied")
            .1;
        tally.cases += 1;
        match check(&c) {
            Ok(o) => {
                tally.changed += usize::from(o.changed);
                tally.whole += usize::from(o.whole);
                tally.later_attempts += usize::from(o.attempt > 0);
                tally.worst = tally.worst.max(o.fill_error);
                tally.replaced += o.replaced;
            }
            Err(e) => {
                failures += 1;
                println!("FAIL seed {seed} ({:?}): {e}", c.kind);
            }
        }
    }
    println!(
        "{cases} cases from seed {from} in {:.1} s: {failures} failures",
        start.elapsed().as_secs_f64()
    );
    println!(
        "kind              cases changed whole later-attempt worst-fill-error(cells) mean-replaced"
    );
    for (kind, t) in &tallies {
        println!(
            "{:<17} {:>5} {:>7} {:>5} {:>13} {:>23.4} {:>13.4}",
            format!("{kind:?}"),
            t.cases,
            t.changed,
            t.whole,
            t.later_attempts,
            t.worst,
            t.replaced / t.cases.max(1) as f64
        );
    }
    if failures > 0 {
        std::process::exit(1);
    }
}
