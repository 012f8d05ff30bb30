//! `waves`: the wave equation run over a whole tracked sequence (paper §5), its state carried from
//! frame to frame through the event lists like any per-vertex attribute (§4.6), one frame held at a
//! time.

use super::integrate::{WaveParameters, WaveState, advance};
use super::seed::{PointSeed, nearest_vertex, patch_vertices};
use super::{Laplacian, WaveError};
use crate::events::{EventList, VertexValues, forward};
use crate::io::{atomic_write, prepare_output_dir, write_ply};
use crate::mesh::{Attribute, IndexedMesh, NormalWeighting};
use crate::propagate::TrackedSequence;
use crate::sequence::frame_name;
use serde::Serialize;
use std::path::Path;

/// Name of the per-vertex wave height written into every frame (world units along the normal).
pub const HEIGHT: &str = "height";
/// Name of the summary written beside the frames.
pub const WAVES_FILE: &str = "waves.json";

/// The simulation's parameters; lengths in the first frame's mean edge length Δ, times in frames.
#[derive(Debug, Clone, PartialEq)]
pub struct WaveOptions {
    /// Wave speed c, in Δ per frame.
    pub speed: f64,
    /// Damping d of `− d ∂h/∂t`, per frame (0: none, as in the paper).
    pub damping: f64,
    /// Height added at each seeded vertex, in Δ.
    pub amplitude: f64,
    /// Least number of sub-steps per frame (more are taken when stability needs them).
    pub min_substeps: usize,
    /// Seed at the vertices of the patches topology changes create.
    pub topology_seeds: bool,
    /// Further seeds at given points.
    pub points: Vec<PointSeed>,
    /// Move each vertex along its normal by its height in the written frames.
    pub displace: bool,
}

impl Default for WaveOptions {
    fn default() -> Self {
        Self {
            speed: 1.0,
            damping: 0.0,
            amplitude: 1.0,
            min_substeps: 4,
            topology_seeds: true,
            points: Vec::new(),
            displace: false,
        }
    }
}

/// One frame of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WaveFrame {
    pub vertices: usize,
    /// Vertices given the seed height in this frame.
    pub seeded: usize,
    /// Sub-steps taken to reach this frame from the previous one.
    pub substeps: usize,
    /// Largest |h|, in Δ.
    pub max_height: f64,
    /// The discrete energy `½ Σ m v² + ½ c² Σ w (h_i − h_j)²` on this frame, in Δ and frames.
    pub energy: f64,
}

/// What a run did, also written as `waves.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WaveSummary {
    /// Δ: the first frame's mean edge length, in world units.
    pub unit: f64,
    pub speed: f64,
    pub damping: f64,
    pub amplitude: f64,
    pub frames: Vec<WaveFrame>,
}

/// Runs the wave simulation over the tracked sequence in `tracked` and writes one PLY per frame
/// into `out` (`frame_NNNN.ply` with the persistent `id` and [`HEIGHT`]) and the summary last.
///
/// `out` is created if missing and refused when it holds anything unless `force` is set; every write
/// is atomic, and nothing is written before the parameters and the first frame are checked.
pub fn waves(
    tracked: &Path,
    out: &Path,
    options: &WaveOptions,
    force: bool,
) -> Result<WaveSummary, WaveError> {
    let sequence = TrackedSequence::open(tracked)?;
    check(options, sequence.len())?;
    let first = sequence.read_frame(0)?;
    let unit = f64::from(first.mean_edge_length());
    prepare_output_dir(out, force)?;
    let parameters = WaveParameters {
        speed: options.speed * unit,
        damping: options.damping,
        min_substeps: options.min_substeps,
    };
    let mut summary = WaveSummary {
        unit,
        speed: options.speed,
        damping: options.damping,
        amplitude: options.amplitude,
        frames: Vec::with_capacity(sequence.len()),
    };
    let mut first = Some(first);
    let mut carried: Option<VertexValues> = None;
    for frame in 0..sequence.len() {
        let mesh = match first.take() {
            Some(mesh) => mesh,
            None => sequence.read_frame(frame)?,
        };
        let ids = mesh.ids.clone().unwrap_or_default();
        let laplacian = Laplacian::of(&mesh);
        let (mut state, substeps, events) = match carried.take() {
            None => (WaveState::rest(ids.len()), 0, EventList::new()),
            Some(mut values) => {
                let events = sequence.read_events(frame)?;
                forward(&events, &mut values).map_err(|source| WaveError::Events {
                    path: sequence.events_path(frame),
                    source,
                })?;
                let mut state = unpack(&values, &ids, sequence.frame_path(frame))?;
                let substeps = advance(&laplacian, &mut state, &parameters, 1.0);
                (state, substeps, events)
            }
        };
        let seeded = seed(&mesh, &ids, &events, frame, options, &mut state, unit);
        summary.frames.push(WaveFrame {
            vertices: ids.len(),
            seeded,
            substeps,
            max_height: state.height.iter().fold(0.0, |m: f64, h| m.max(h.abs())) / unit,
            energy: state.energy(&laplacian, parameters.speed) / unit.powi(4),
        });
        carried = Some(pack(&state, &ids, sequence.frame_path(frame))?);
        let written = with_height(mesh, &state.height, options.displace);
        write_ply(&out.join(frame_name(frame)), &written)?;
    }
    let json = serde_json::to_vec_pretty(&summary)?;
    atomic_write(&out.join(WAVES_FILE), |w| w.write_all(&json))?;
    Ok(summary)
}

/// Rejects parameters that cannot give a useful result before anything is read or written.
fn check(options: &WaveOptions, frames: usize) -> Result<(), WaveError> {
    let parameter = |what, bound, value: f64, ok: bool| {
        if value.is_finite() && ok {
            Ok(())
        } else {
            Err(WaveError::Parameter { what, bound, value })
        }
    };
    parameter("wave speed", "positive", options.speed, options.speed > 0.0)?;
    parameter(
        "damping",
        "non-negative",
        options.damping,
        options.damping >= 0.0,
    )?;
    parameter("amplitude", "finite", options.amplitude, true)?;
    let substeps = options.min_substeps as f64;
    parameter(
        "sub-steps",
        "at least 1",
        substeps,
        options.min_substeps >= 1,
    )?;
    if let Some(seed) = options.points.iter().find(|s| s.frame >= frames) {
        return Err(WaveError::SeedFrame {
            frame: seed.frame,
            frames,
        });
    }
    Ok(())
}

/// Adds the seed height to the vertices of this frame's topology patches and to the vertices
/// nearest its point seeds; returns how many vertices were seeded.
fn seed(
    mesh: &IndexedMesh,
    ids: &[u64],
    events: &EventList,
    frame: usize,
    options: &WaveOptions,
    state: &mut WaveState,
    unit: f64,
) -> usize {
    let height = options.amplitude * unit;
    let mut seeded = vec![false; ids.len()];
    if options.topology_seeds {
        let patch = patch_vertices(events);
        for (s, id) in seeded.iter_mut().zip(ids) {
            *s = patch.contains(id);
        }
    }
    for point in options.points.iter().filter(|s| s.frame == frame) {
        if let Some(v) = nearest_vertex(&mesh.positions, point.point) {
            seeded[v] = true;
        }
    }
    for (h, _) in state.height.iter_mut().zip(&seeded).filter(|(_, s)| **s) {
        *h += height;
    }
    seeded.iter().filter(|s| **s).count()
}

/// The state as per-id values `(h, v)`, what the event lists carry.
fn pack(state: &WaveState, ids: &[u64], path: &Path) -> Result<VertexValues, WaveError> {
    let values: Vec<f32> = state
        .height
        .iter()
        .zip(&state.velocity)
        .flat_map(|(&h, &v)| [h as f32, v as f32])
        .collect();
    VertexValues::from_parts(2, ids, &values).map_err(|source| WaveError::Events {
        path: path.to_path_buf(),
        source,
    })
}

/// The carried values in the vertex order of a frame with `ids`.
fn unpack(values: &VertexValues, ids: &[u64], path: &Path) -> Result<WaveState, WaveError> {
    let mut state = WaveState::rest(ids.len());
    for (i, &id) in ids.iter().enumerate() {
        let value = values.get(id).ok_or(WaveError::Uncovered {
            path: path.to_path_buf(),
            id,
        })?;
        state.height[i] = f64::from(value[0]);
        state.velocity[i] = f64::from(value[1]);
    }
    Ok(state)
}

/// The frame as written: its attributes replaced by the height, positions displaced if asked.
fn with_height(mut mesh: IndexedMesh, height: &[f64], displace: bool) -> IndexedMesh {
    if displace {
        let normals = mesh.vertex_normals(NormalWeighting::Area);
        for ((p, n), &h) in mesh.positions.iter_mut().zip(normals).zip(height) {
            *p += n * h as f32;
        }
    }
    mesh.attributes = vec![Attribute {
        name: HEIGHT.to_string(),
        components: 1,
        values: height.iter().map(|&h| h as f32).collect(),
    }];
    mesh
}
