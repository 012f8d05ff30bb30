//! Absurd counts in headers (i32::MAX vertices, billions of faces) are checked against the bytes
//! that remain: the read fails fast and no allocation grows beyond the size of the file.
//!
//! A counting allocator records the largest single allocation; each test resets and reads it, so
//! the tests of this binary run one at a time (`LOCK`).

use flate2::Compression;
use flate2::write::GzEncoder;
use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Write;
use std::sync::atomic::{AtomicUsize, Ordering};
use surftrack::io::{IoError, read_frame};

struct Largest;

static LARGEST: AtomicUsize = AtomicUsize::new(0);

/// Held by each test while it measures.
static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

unsafe impl GlobalAlloc for Largest {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST.fetch_max(new_size, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Largest = Largest;

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = GzEncoder::new(Vec::new(), Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

fn bobj(counts: [i32; 3], filler: usize) -> Vec<u8> {
    let mut payload = Vec::new();
    payload.extend_from_slice(&counts[0].to_le_bytes());
    payload.extend(std::iter::repeat_n(0u8, filler));
    payload.extend_from_slice(&counts[1].to_le_bytes());
    payload.extend_from_slice(&counts[2].to_le_bytes());
    gzip(&payload)
}

fn ply(format: &str, vertices: &str, faces: &str, body: &[u8]) -> Vec<u8> {
    let mut bytes = format!(
        "ply\nformat {format} 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\n\
         property float z\nelement face {faces}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    bytes.extend_from_slice(body);
    bytes
}

#[test]
fn absurd_counts_fail_without_large_allocations() {
    let _measuring = LOCK.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let dir = tempfile::tempdir().unwrap();
    let tetra_vertices: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1.]
        .iter()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let mut list_too_long = tetra_vertices.clone();
    list_too_long.extend_from_slice(&[255, 0, 0, 0, 0]);
    let mut cases: Vec<(&str, Vec<u8>)> = vec![
        ("vertices.bobj.gz", bobj([i32::MAX, 0, 0], 64)),
        ("normals.bobj.gz", bobj([0, i32::MAX, 0], 0)),
        ("triangles.bobj.gz", bobj([0, 0, i32::MAX], 0)),
        (
            "two_to_the_31.ply",
            ply("binary_little_endian", "2147483648", "0", &tetra_vertices),
        ),
        (
            "two_to_the_31_ascii.ply",
            ply("ascii", "2147483648", "0", b"0 0 0\n"),
        ),
        (
            "vertices.ply",
            ply("binary_little_endian", "4294967295", "0", &tetra_vertices),
        ),
        (
            "huge.ply",
            ply("binary_big_endian", "18446744073709551615", "1", &[0; 64]),
        ),
        (
            "faces.ply",
            ply("binary_little_endian", "4", "2000000000", &tetra_vertices),
        ),
        (
            "list.ply",
            ply("binary_little_endian", "4", "1", &list_too_long),
        ),
        (
            "ascii.ply",
            ply("ascii", "3000000000", "3000000000", b"0 0 0\n1 0 0\n"),
        ),
        (
            "ascii_list.ply",
            ply("ascii", "3", "1", b"0 0 0\n1 0 0\n0 1 0\n200 0 1 2\n"),
        ),
    ];
    // Deflate expands up to 1032:1: 64 MiB of zeros after valid empty counts is a 64 KiB file.
    let mut bomb = vec![0u8; 12];
    bomb.resize(64 << 20, 0);
    cases.push(("bomb.bobj.gz", gzip(&bomb)));
    for (name, bytes) in &cases {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        LARGEST.store(0, Ordering::Relaxed);
        let result = read_frame(&path);
        let largest = LARGEST.load(Ordering::Relaxed);
        match &result {
            Err(IoError::Truncated { .. } | IoError::Malformed { .. }) => {}
            other => panic!("{name}: {other:?}"),
        }
        assert!(
            largest < 1 << 20,
            "{name}: allocated {largest} bytes at once"
        );
    }
}

/// An event file whose events all name the whole id table (every range valid on its own) would
/// decode to a list far larger than the file: the ranges must follow each other instead.
#[test]
fn overlapping_event_ranges_are_refused_before_they_multiply() {
    let _measuring = LOCK.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    use surftrack::events::file::{EventFileError, decode};
    let (events, ids) = (1000u32, 1000u32);
    let mut bytes = b"SURFEVT\0".to_vec();
    for v in [1, events, ids, 0, 0, 0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    for _ in 0..events {
        for v in [0u32, 0, ids, ids, 0, 0, 0, 0, 0] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    bytes.extend((0..u64::from(ids)).flat_map(|id| id.to_le_bytes()));
    let crc = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&crc.to_le_bytes());
    LARGEST.store(0, Ordering::Relaxed);
    let result = decode(&bytes);
    assert!(
        matches!(result, Err(EventFileError::Order { event: 1, .. })),
        "{result:?}"
    );
    assert!(LARGEST.load(Ordering::Relaxed) < 2 * bytes.len());
}
