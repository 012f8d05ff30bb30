//! The default of `--jobs`: as many caches at once as the cores and the memory allow.

use surftrack::batch::Cache;
use surftrack::io::{Format, discover_sequence};

/// Resident memory of tracking, per vertex of a frame (a frame of 1M vertices held 4.7 GiB).
const RESIDENT_BYTES_PER_VERTEX: u64 = 5_000;

/// Bytes a vertex takes in a frame file (with its two triangles): binary PLY and gzip-compressed
/// `.bobj.gz` about 40, OBJ text about 70. An estimate from the file size alone, so choosing the
/// job count reads no frame.
fn file_bytes_per_vertex(format: Format) -> u64 {
    match format {
        Format::Ply | Format::BobjGz => 40,
        Format::Obj => 70,
    }
}

/// Caches at once: one per two cores (a cache keeps two busy: its tracking, and the field
/// sampling and read-ahead beside it), no more than the available memory holds for the largest
/// first frame, and at least one.
pub(super) fn default_jobs(caches: &[&Cache]) -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let by_cores = (cores / 2).max(1);
    let largest = caches
        .iter()
        .filter_map(|cache| resident_estimate(cache))
        .max()
        .unwrap_or(0);
    let by_memory = match available_memory() {
        Some(bytes) if largest > 0 => (bytes / largest) as usize,
        _ => usize::MAX,
    };
    by_cores.min(by_memory).max(1)
}

/// Resident bytes of tracking `cache`, from the size of its largest frame file (a cache with an
/// inflow starts with empty files, and memory follows the largest frame); `None` when none can be
/// found (the cache then fails on its own when it runs).
fn resident_estimate(cache: &Cache) -> Option<u64> {
    let sequence = discover_sequence(&cache.input).ok()?;
    let (bytes, largest) = sequence
        .frames
        .iter()
        .filter_map(|(_, path)| Some((std::fs::metadata(path).ok()?.len(), path)))
        .max()?;
    let format = Format::from_path(largest).ok()?;
    Some(bytes / file_bytes_per_vertex(format) * RESIDENT_BYTES_PER_VERTEX)
}

/// `MemAvailable` of `/proc/meminfo`, where there is one.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
