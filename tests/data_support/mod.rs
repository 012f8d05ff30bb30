//! The shared real data set (`../shared/data/…`, beside the checkout in CI, absent from a user's
//! clone). Tests that need it skip with a message when it is absent, unless
//! `SURFTRACK_REQUIRE_DATA=1` (set by `.ci/run`), which makes its absence a failure, so a CI run
//! cannot pass such a test without running it.

use std::path::{Path, PathBuf};

/// The environment variable that turns a missing data set into a failure.
pub const REQUIRE_DATA_ENV: &str = "SURFTRACK_REQUIRE_DATA";

/// The shared SPH dam break, or `None` (after saying so) when it is absent and not required.
pub fn dambreak() -> Option<PathBuf> {
    shared("dambreak_sph_warp")
}

fn shared(name: &str) -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/data")
        .join(name);
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var(REQUIRE_DATA_ENV).as_deref() != Ok("1"),
        "{} is absent and {REQUIRE_DATA_ENV}=1",
        dir.display()
    );
    eprintln!("skipped: {} is absent", dir.display());
    None
}
