//! Wall time spent in the stages the GPU path runs as kernels — correspondence projection,
//! closest points, triangle bounds, rasterization, sweeps, the narrow-band distance and the fine
//! stage's solve — on whichever backend runs them. On the CPU path its share of a frame (`bench`'s `gpu_share`) is
//! the most of that frame a GPU could speed up, whatever its kernels' speed.
//!
//! One process-wide clock: stages that run beside each other (Φ(T) is sampled while the mesh
//! registers) both count, so the share can overstate what a faster kernel would save.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

static NANOS: AtomicU64 = AtomicU64::new(0);

/// Runs `stage`, adding its wall time to the clock.
pub fn timed<T>(stage: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = stage();
    let nanos = u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX);
    NANOS.fetch_add(nanos, Ordering::Relaxed);
    out
}

/// Everything the clock has counted since the process started.
pub fn total() -> Duration {
    Duration::from_nanos(NANOS.load(Ordering::Relaxed))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_timed_stage_adds_at_least_its_own_time() {
        let before = total();
        let out = timed(|| {
            std::thread::sleep(Duration::from_millis(5));
            7
        });
        assert_eq!(out, 7);
        assert!(total() - before >= Duration::from_millis(5));
    }
}
