//! A fixed-budget fuzz run of every target (`surftrack::fuzz`), seeded so every run tries the same
//! inputs: no input panics or is accepted in a broken state, and each target both refuses and
//! accepts some inputs (its mutations reach past the first check without always breaking the
//! file). Long runs: `cargo run --release --example fuzz` (docs/robustness.md).

use surftrack::fuzz::{Options, Target, run};

#[test]
fn every_target_survives_a_seeded_run() {
    let scratch = tempfile::tempdir().unwrap();
    for target in Target::ALL {
        let options = Options {
            inputs: 600,
            seed: 26,
            scratch: scratch.path().join(target.name()),
            saved: None,
        };
        let report = run(target, &options).unwrap();
        assert_eq!(report.inputs, 600);
        assert!(
            report.failures.is_empty(),
            "{}: {:?}",
            target.name(),
            report.failures
        );
        assert!(report.accepted > 0, "{}: nothing accepted", target.name());
        assert!(report.refused > 0, "{}: nothing refused", target.name());
    }
}
