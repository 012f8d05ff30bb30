//! `summary.json`, written last: the run's totals and its per-frame figures.

use crate::track::FrameLog;
use serde::Serialize;

/// The end-of-run summary.
#[derive(Debug, Serialize)]
pub struct Summary<'a> {
    pub frames: usize,
    pub seconds: f64,
    pub backend: String,
    pub edge_length: f32,
    pub total_events: usize,
    pub topology_changes: usize,
    pub max_residual: f64,
    pub per_frame: &'a [FrameLog],
}

impl<'a> Summary<'a> {
    pub fn of(per_frame: &'a [FrameLog], seconds: f64, backend: String, edge_length: f32) -> Self {
        Self {
            frames: per_frame.len(),
            seconds,
            backend,
            edge_length,
            total_events: per_frame
                .iter()
                .map(|f| {
                    let e = &f.events;
                    e.split_edge
                        + e.split_face
                        + e.collapse
                        + e.merge
                        + e.patch_created
                        + e.patch_deleted
                })
                .sum(),
            topology_changes: per_frame.iter().filter(|f| f.topology_changed).count(),
            max_residual: per_frame.iter().map(|f| f.residual_max).fold(0.0, f64::max),
            per_frame,
        }
    }
}
