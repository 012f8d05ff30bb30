//! The stress bar: thousands of random adversarial cases, every guarantee checked on each.

pub mod topology_support;

use topology_support::{case, check};

#[test]
fn random_cases_never_fail() {
    let n: u64 = std::env::var("TOPOLOGY_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000);
    let mut failures = Vec::new();
    let mut whole = 0;
    let mut worst = 0.0f64;
    for seed in 0..n {
        let c = case(seed);
        match check(&c) {
            Ok(o) => {
                whole += usize::from(o.whole);
                worst = worst.max(o.fill_error);
            }
            Err(e) => failures.push(format!("seed {seed} ({:?}): {e}", c.kind)),
        }
    }
    eprintln!(
        "{n} cases, {} failures, {whole} whole replacements, worst fill error {worst:.4} cells",
        failures.len()
    );
    for f in failures.iter().take(30) {
        eprintln!("{f}");
    }
    assert!(failures.is_empty());
}
