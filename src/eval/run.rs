//! `eval`: every tracked frame against its input frame, one frame at a time.

use super::EvalError;
use super::checker::pure_share;
use super::distance::surface_distances;
use super::drift::MaterialPoints;
use super::intersections::intersecting_pairs;
use super::options::EvalOptions;
use super::quality::triangle_quality;
use super::report::{EvalReport, FrameReport};
use crate::io::{ReadOptions, discover_sequence, read_frame, read_frame_with};
use crate::mesh::IndexedMesh;
use crate::propagate::{TrackedSequence, frame_name};
use crate::synth::{MANIFEST_FILE, Manifest, RigidTransform};
use std::path::{Path, PathBuf};

/// Evaluates the tracked sequence in `tracked` against its input frames (see [`FrameReport`]).
///
/// Input frame `k` (in numeric order) is compared with tracked frame `k`. When a synth
/// `manifest.json` lies beside the input frames and gives a rigid motion for each frame, the drift
/// of the frame-0 vertices from their ground-truth positions is measured too.
pub fn evaluate(tracked: &Path, options: &EvalOptions) -> Result<EvalReport, EvalError> {
    let sequence = TrackedSequence::open(tracked)?;
    let inputs = input_frames(&sequence, options)?;
    if inputs.len() < sequence.len() {
        return Err(EvalError::TooFewInputFrames {
            tracked: sequence.len(),
            input: inputs.len(),
        });
    }
    let manifest = inputs
        .first()
        .and_then(|p| p.parent())
        .map(|dir| dir.join(MANIFEST_FILE))
        .filter(|p| p.is_file());
    let truth = manifest
        .as_deref()
        .and_then(read_manifest)
        .map(|m| rigid_motions(&m, &inputs[..sequence.len()]))
        .filter(|motions| motions.iter().all(Option::is_some));
    let mut frames = Vec::with_capacity(sequence.len());
    let mut previous_ids: Vec<u64> = Vec::new();
    let mut material: Option<MaterialPoints> = None;
    for (frame, input_path) in inputs.iter().enumerate().take(sequence.len()) {
        let mesh = sequence.read_frame(frame)?;
        let input = read_frame(input_path)?.mesh;
        let mut report = measure(frame, input_path, &mesh, &input, options)?;
        let mut ids = mesh.ids.clone().unwrap_or_default();
        ids.sort_unstable();
        if frame > 0 {
            let carried = ids
                .iter()
                .filter(|id| previous_ids.binary_search(id).is_ok())
                .count();
            report.coherence = Some(carried as f64 / ids.len().max(1) as f64);
            report.lost = sequence.churn(frame);
        }
        previous_ids = ids;
        if let Some(dir) = &options.checker {
            let path = dir.join(frame_name(frame));
            let carried = read_frame_with(
                &path,
                &ReadOptions {
                    repair: false,
                    ..ReadOptions::default()
                },
            )?
            .mesh;
            report.checker_pure = Some(pure_share(&carried).ok_or(EvalError::NoColour { path })?);
        }
        if let Some(Some(transform)) = truth.as_ref().map(|t| t[frame]) {
            if frame == 0 {
                material = MaterialPoints::new(&mesh, transform);
            }
            report.drift = material.as_ref().map(|m| m.drift(&mesh, &transform));
        }
        frames.push(report);
    }
    Ok(EvalReport::new(
        tracked.to_path_buf(),
        truth.and(manifest),
        options,
        frames,
        inputs.len() - sequence.len(),
    ))
}

/// Everything measured on one frame pair except what needs the previous frames.
fn measure(
    frame: usize,
    input_path: &Path,
    mesh: &IndexedMesh,
    input: &IndexedMesh,
    options: &EvalOptions,
) -> Result<FrameReport, EvalError> {
    let (topology, input_topology) = (mesh.topology(), input.topology());
    let mut report = FrameReport {
        frame,
        input: input_path.to_path_buf(),
        vertices: mesh.positions.len(),
        triangles: mesh.triangles.len(),
        input_vertices: input.positions.len(),
        delta: input.mean_edge_length(),
        hausdorff: 0.0,
        tracked_to_input: 0.0,
        input_to_tracked: 0.0,
        mean_distance: 0.0,
        defect: mesh.validate().err().map(|e| e.to_string()),
        components: topology.components.len(),
        input_components: input_topology.components.len(),
        euler: topology.euler(),
        input_euler: input_topology.euler(),
        quality: triangle_quality(mesh, options.angle_threshold),
        crossing_pairs: intersecting_pairs(mesh),
        input_crossing_pairs: intersecting_pairs(input),
        coherence: None,
        lost: None,
        checker_pure: None,
        drift: None,
    };
    let distances =
        surface_distances(&options.backend, mesh, input).map_err(|source| EvalError::Distance {
            path: input_path.to_path_buf(),
            source,
        })?;
    report.distances(&distances);
    Ok(report)
}

/// The input frames, from the options or from `track.json`.
fn input_frames(
    sequence: &TrackedSequence,
    options: &EvalOptions,
) -> Result<Vec<PathBuf>, EvalError> {
    match (&options.input, sequence.input()) {
        (Some(input), _) if input.is_file() => Ok(vec![input.clone()]),
        (Some(input), _) => Ok(discover_sequence(input)?
            .without_empty_ends()?
            .0
            .frames
            .into_iter()
            .map(|(_, path)| path)
            .collect()),
        (None, Some(list)) if !list.is_empty() => Ok(list.to_vec()),
        (None, _) => Err(EvalError::NoInput {
            dir: sequence.dir().to_path_buf(),
        }),
    }
}

/// A synth manifest; other `manifest.json` files (other tools write them too) give no ground truth.
fn read_manifest(path: &Path) -> Option<Manifest> {
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

/// The ground-truth motion of each input frame, matched by file name.
fn rigid_motions(manifest: &Manifest, inputs: &[PathBuf]) -> Vec<Option<RigidTransform>> {
    inputs
        .iter()
        .map(|path| {
            let name = path.file_name()?.to_str()?;
            manifest
                .frames
                .iter()
                .find(|f| f.file == name)
                .and_then(|f| f.truth.transform)
        })
        .collect()
}
