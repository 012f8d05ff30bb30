//! The CLI on bad input: every broken file gives a clear error naming the file and what is wrong, a
//! non-zero exit, and never a panic. On good input `inspect` succeeds and agrees with the manifest.

mod data_support;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn surftrack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
        .args(args)
        .output()
        .expect("the surftrack binary runs")
}

fn broken(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/broken")
        .join(name)
}

#[test]
fn every_broken_input_fails_cleanly_with_its_own_message() {
    let cases: &[(&str, &str)] = &[
        ("empty.obj", "empty"),
        ("truncated.ply", "truncated"),
        ("nan.obj", "NaN"),
        ("not_a_number.obj", "number"),
        ("open.obj", "open boundary"),
        ("nonmanifold_edge.obj", "non-manifold edge"),
        ("flipped.obj", "inconsistent orientation"),
        ("index_out_of_range.obj", "out of range"),
        ("garbage.ply", "ply"),
        ("garbage.bobj.gz", "gzip"),
        ("negative_count.bobj.gz", "count"),
        ("bad_header.ply", "header"),
        ("unsupported.stl", "unsupported"),
    ];
    let mut messages = Vec::new();
    for (file, expected) in cases {
        let path = broken(file);
        let out = surftrack(&["inspect", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert!(
            !out.status.success(),
            "{file}: exit status {:?}",
            out.status
        );
        assert_eq!(
            out.status.code(),
            Some(1),
            "{file}: not a clean failure: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{file} panicked: {stderr}");
        assert!(
            stderr.contains(file),
            "{file}: message does not name the file: {stderr}"
        );
        assert!(
            stderr.to_lowercase().contains(&expected.to_lowercase()),
            "{file}: message does not say '{expected}': {stderr}"
        );
        messages.push(stderr);
    }
    let mut unique = messages.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), messages.len(), "messages are not distinct");
}

#[test]
fn a_missing_file_is_named() {
    let out = surftrack(&["inspect", "no/such/frame_0001.obj"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such"));
}

/// The real SPH dam break (12k–25k vertices, up to 50 components): every frame loads as a closed
/// manifold and its topology matches the generator's manifest (inspect fails on any mismatch).
#[test]
fn dambreak_topology_matches_its_manifest() {
    let Some(data) = data_support::dambreak() else {
        return;
    };
    let out = surftrack(&["inspect", data.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let frames: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data.join("manifest.json")).unwrap())
            .unwrap();
    let expected = manifest["frames"].as_array().unwrap();
    let got = frames.as_array().unwrap();
    assert_eq!(got.len(), expected.len());
    for (g, e) in got.iter().zip(expected) {
        assert_eq!(g["components"], e["components"], "{}", e["file"]);
        assert_eq!(g["euler"], e["euler_characteristic"], "{}", e["file"]);
        assert_eq!(g["genus"], e["genus_total"], "{}", e["file"]);
        assert_eq!(g["vertices"], e["vertices"], "{}", e["file"]);
        assert!(g["defect"].is_null(), "{}", e["file"]);
    }
}
