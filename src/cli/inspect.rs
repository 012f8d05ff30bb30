//! `surftrack inspect`: per-frame summary of a file or a sequence, checked against the sequence's
//! `manifest.json` when one lies beside the frames.

use super::CliError;
use clap::Args;
use serde::Serialize;
use std::path::{Path, PathBuf};
use surftrack::io::{Frame, discover_sequence, read_frame};
use surftrack::mesh::{MeshError, QualityStats, Topology};

#[derive(Debug, Args)]
pub struct InspectArgs {
    /// A frame file (.obj, .ply, .bobj.gz), a directory of frames, or a pattern like `fluid_####.obj`.
    input: PathBuf,
    /// Print one JSON document instead of the table.
    #[arg(long)]
    json: bool,
}

/// What `inspect` knows about one frame.
#[derive(Debug, Serialize)]
struct FrameSummary {
    file: PathBuf,
    vertices: usize,
    faces: usize,
    components: usize,
    euler: i64,
    genus: i64,
    /// `None` when the frame is a closed, oriented 2-manifold; otherwise why not.
    defect: Option<String>,
    #[serde(skip)]
    error: Option<MeshError>,
    welded_vertices: usize,
    dropped_faces: usize,
    split_edges: usize,
    split_vertices: usize,
    quality: QualityStats,
}

pub fn run(args: &InspectArgs) -> Result<(), CliError> {
    let files = frame_files(&args.input)?;
    let mut summaries = Vec::with_capacity(files.len());
    for file in &files {
        let frame = read_frame(file)?;
        summaries.push(summarize(file, &frame));
    }
    let mismatches = match manifest_beside(&args.input) {
        Some(path) => check_manifest(&path, &summaries)?,
        None => Vec::new(),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summaries)?);
    } else {
        print_table(&summaries);
    }
    for m in &mismatches {
        eprintln!("manifest mismatch: {m}");
    }
    let failed = summaries.iter().filter(|s| s.defect.is_some()).count();
    if let [only] = summaries.as_slice()
        && let Some(error) = &only.error
    {
        return Err(CliError::InvalidMesh {
            path: only.file.clone(),
            source: error.clone(),
        });
    }
    if failed > 0 {
        return Err(CliError::InvalidFrames {
            failed,
            total: summaries.len(),
        });
    }
    if let (false, Some(path)) = (mismatches.is_empty(), manifest_beside(&args.input)) {
        return Err(CliError::ManifestMismatch {
            path,
            count: mismatches.len(),
        });
    }
    Ok(())
}

fn frame_files(input: &Path) -> Result<Vec<PathBuf>, CliError> {
    if input.is_file() {
        return Ok(vec![input.to_path_buf()]);
    }
    let sequence = discover_sequence(input)?;
    for range in sequence.gap_ranges() {
        eprintln!(
            "warning: frames {range} are missing from {}",
            input.display()
        );
    }
    Ok(sequence.frames.into_iter().map(|(_, p)| p).collect())
}

fn summarize(file: &Path, frame: &Frame) -> FrameSummary {
    let mesh = &frame.mesh;
    let topology: Topology = mesh.topology();
    let error = mesh.validate().err();
    FrameSummary {
        file: file.to_path_buf(),
        vertices: mesh.positions.len(),
        faces: mesh.triangles.len(),
        components: topology.components.len(),
        euler: topology.euler(),
        genus: topology.total_genus(),
        defect: error.as_ref().map(|e| e.to_string()),
        error,
        welded_vertices: frame.repairs.welded_vertices,
        dropped_faces: frame.repairs.degenerate_faces,
        split_edges: frame.repairs.split_edges,
        split_vertices: frame.repairs.split_vertices,
        quality: mesh.quality(),
    }
}

fn print_table(summaries: &[FrameSummary]) {
    println!(
        "{:<28} {:>8} {:>8} {:>5} {:>6} {:>5} {:>9} {:>9} {:>9} {:>7}  status",
        "file",
        "verts",
        "faces",
        "comp",
        "euler",
        "genus",
        "edge min",
        "edge mean",
        "edge max",
        "min ang"
    );
    for s in summaries {
        let name = s.file.file_name().map_or_else(
            || s.file.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        let status = match &s.defect {
            None => "closed manifold".to_string(),
            Some(d) => d.clone(),
        };
        let mut repairs = Vec::new();
        if s.welded_vertices + s.dropped_faces > 0 {
            repairs.push(format!(
                "{} welded, {} dropped",
                s.welded_vertices, s.dropped_faces
            ));
        }
        if s.split_vertices > 0 {
            repairs.push(format!(
                "touching parts split: {} edges, {} vertices",
                s.split_edges, s.split_vertices
            ));
        }
        let repaired = if repairs.is_empty() {
            String::new()
        } else {
            format!(" (repaired: {})", repairs.join("; "))
        };
        println!(
            "{:<28} {:>8} {:>8} {:>5} {:>6} {:>5} {:>9.4} {:>9.4} {:>9.4} {:>7.2}  {status}{repaired}",
            name,
            s.vertices,
            s.faces,
            s.components,
            s.euler,
            s.genus,
            s.quality.edge_min,
            s.quality.edge_mean,
            s.quality.edge_max,
            s.quality.min_angle
        );
    }
}

/// The `manifest.json` of a sequence directory (or of a pattern's directory), if there is one.
fn manifest_beside(input: &Path) -> Option<PathBuf> {
    let dir = if input.is_dir() {
        input.to_path_buf()
    } else {
        input.parent()?.to_path_buf()
    };
    let dir = if dir.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        dir
    };
    let path = dir.join("manifest.json");
    path.is_file().then_some(path)
}

/// Compares each inspected frame with the manifest entry of the same file name: component count,
/// Euler characteristic and total genus, where the manifest states them.
fn check_manifest(path: &Path, summaries: &[FrameSummary]) -> Result<Vec<String>, CliError> {
    let err = |message: String| CliError::Manifest {
        path: path.to_path_buf(),
        message,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
    let json: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| err(format!("not valid JSON: {e}")))?;
    let Some(frames) = json.get("frames").and_then(|f| f.as_array()) else {
        return Ok(Vec::new());
    };
    let mut mismatches = Vec::new();
    for s in summaries {
        let name = s.file.file_name().map(|n| n.to_string_lossy().into_owned());
        let Some(entry) = frames
            .iter()
            .find(|f| f.get("file").and_then(|v| v.as_str()) == name.as_deref())
        else {
            continue;
        };
        let expect = |keys: &[&str]| {
            keys.iter()
                .find_map(|k| entry.get(*k).and_then(|v| v.as_i64()))
        };
        let checks = [
            ("components", expect(&["components"]), s.components as i64),
            ("euler", expect(&["euler_characteristic", "euler"]), s.euler),
            ("genus", expect(&["genus_total", "genus"]), s.genus),
        ];
        for (what, expected, got) in checks {
            if let Some(expected) = expected
                && expected != got
            {
                mismatches.push(format!(
                    "{}: {what} is {got}, manifest says {expected}",
                    s.file.display()
                ));
            }
        }
    }
    Ok(mismatches)
}
