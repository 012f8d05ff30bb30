//! The evaluation report: one record per frame, a summary, and the text table.

use super::EvalOptions;
use super::distance::SurfaceDistances;
use super::drift::Drift;
use super::quality::{ASPECT_BUCKETS, TriangleQuality};
use crate::geometry::ANGLE_BUCKETS;
use crate::track::StageChurn;
use serde::Serialize;
use std::fmt::Write;
use std::path::PathBuf;

/// What `eval` measures on one tracked frame against its input frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrameReport {
    pub frame: usize,
    pub input: PathBuf,
    pub vertices: usize,
    pub triangles: usize,
    pub input_vertices: usize,
    /// Δ: the input frame's mean edge length, the unit of the distances below.
    pub delta: f32,
    /// Two-sided Hausdorff distance in Δ.
    pub hausdorff: f32,
    /// Largest tracked → input and input → tracked distances in Δ.
    pub tracked_to_input: f32,
    pub input_to_tracked: f32,
    /// Mean distance over samples of both surfaces in Δ.
    pub mean_distance: f32,
    /// `None` when the tracked frame is a closed, oriented 2-manifold; otherwise why not.
    pub defect: Option<String>,
    pub components: usize,
    pub input_components: usize,
    pub euler: i64,
    pub input_euler: i64,
    pub quality: TriangleQuality,
    /// Pairs of triangles passing through each other, in the tracked frame and in the input
    /// (`intersections`): validity does not see a surface crossing itself, a renderer does.
    pub crossing_pairs: usize,
    pub input_crossing_pairs: usize,
    /// Fraction of this frame's vertices present (same id) in the previous frame; none for frame 0.
    pub coherence: Option<f64>,
    /// Where the previous frame's vertices were lost, by stage, as the tracker recorded it.
    pub lost: Option<StageChurn>,
    /// Share of the vertices whose carried checker colour is still pure (see `pure_share`).
    pub checker_pure: Option<f64>,
    /// Drift of the frame-0 material points from the ground truth, when a synth manifest gives it.
    pub drift: Option<Drift>,
}

impl FrameReport {
    pub(super) fn distances(&mut self, d: &SurfaceDistances) {
        let unit = if self.delta > 0.0 { self.delta } else { 1.0 };
        self.hausdorff = d.hausdorff() / unit;
        self.tracked_to_input = d.tracked_to_input / unit;
        self.input_to_tracked = d.input_to_tracked / unit;
        self.mean_distance = d.mean / unit;
    }

    pub fn topology_matches(&self) -> bool {
        self.components == self.input_components && self.euler == self.input_euler
    }

    /// Whether the frame meets the tracker's bar: closed manifold with the input's topology,
    /// Hausdorff ≤ `max_hausdorff` Δ, and at least `min_good` of the triangles above the angle
    /// threshold.
    pub fn passes(&self, max_hausdorff: f32, min_good: f64) -> bool {
        self.defect.is_none()
            && self.topology_matches()
            && self.hausdorff <= max_hausdorff
            && self.quality.above_threshold >= min_good
    }
}

/// Figures over the whole sequence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub frames: usize,
    /// Input frames beyond the last tracked one (a run still going or stopped early).
    pub untracked_input_frames: usize,
    pub max_hausdorff: f32,
    pub mean_distance: f32,
    pub not_manifold: usize,
    pub topology_mismatches: usize,
    /// Smallest per-frame fraction of triangles above the angle threshold.
    pub min_above_threshold: f64,
    /// Tracked frames with triangles passing through each other, the most pairs in one frame,
    /// and the most in one input frame.
    pub crossing_frames: usize,
    pub max_crossing_pairs: usize,
    pub max_input_crossing_pairs: usize,
    /// Mean coherence over frames 1…n−1.
    pub mean_coherence: Option<f64>,
    pub min_coherence: Option<f64>,
    /// What each stage created, removed and lost over the run (frames whose run recorded it).
    pub lost: Option<StageChurn>,
    /// The carried checker's pure share in the last frame, and its lowest over the frames.
    pub final_checker_pure: Option<f64>,
    pub min_checker_pure: Option<f64>,
    /// Drift in the last frame, and the largest mean drift of any frame.
    pub final_drift: Option<Drift>,
    pub max_mean_drift_percent: Option<f32>,
    /// Frames failing `FrameReport::passes` with the report's bars.
    pub failing_frames: Vec<usize>,
}

/// The whole evaluation, as written to JSON.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EvalReport {
    pub tracked: PathBuf,
    /// The synth manifest giving ground truth, when one was found.
    pub manifest: Option<PathBuf>,
    /// Minimum angle (degrees) counted as good triangle quality.
    pub angle_threshold: f32,
    /// Largest Hausdorff distance (Δ) and smallest fraction of good triangles a frame may have.
    pub max_hausdorff: f32,
    pub min_good_triangles: f64,
    pub angle_buckets: Vec<f32>,
    pub aspect_buckets: Vec<f32>,
    pub frames: Vec<FrameReport>,
    pub summary: Summary,
}

impl Summary {
    pub(super) fn of(
        frames: &[FrameReport],
        untracked_input_frames: usize,
        max_hausdorff: f32,
        min_good: f64,
    ) -> Self {
        let coherence: Vec<f64> = frames.iter().filter_map(|f| f.coherence).collect();
        let drifts: Vec<Drift> = frames.iter().filter_map(|f| f.drift).collect();
        Self {
            frames: frames.len(),
            untracked_input_frames,
            max_hausdorff: frames.iter().map(|f| f.hausdorff).fold(0.0, f32::max),
            mean_distance: mean(frames.iter().map(|f| f64::from(f.mean_distance))).unwrap_or(0.0)
                as f32,
            not_manifold: frames.iter().filter(|f| f.defect.is_some()).count(),
            topology_mismatches: frames.iter().filter(|f| !f.topology_matches()).count(),
            min_above_threshold: frames
                .iter()
                .map(|f| f.quality.above_threshold)
                .fold(1.0, f64::min),
            crossing_frames: frames.iter().filter(|f| f.crossing_pairs > 0).count(),
            max_crossing_pairs: frames.iter().map(|f| f.crossing_pairs).max().unwrap_or(0),
            max_input_crossing_pairs: frames
                .iter()
                .map(|f| f.input_crossing_pairs)
                .max()
                .unwrap_or(0),
            mean_coherence: mean(coherence.iter().copied()),
            min_coherence: coherence.iter().copied().reduce(f64::min),
            lost: frames
                .iter()
                .filter_map(|f| f.lost)
                .reduce(|total, frame| total.plus(&frame)),
            final_checker_pure: frames.last().and_then(|f| f.checker_pure),
            min_checker_pure: frames
                .iter()
                .filter_map(|f| f.checker_pure)
                .reduce(f64::min),
            final_drift: frames.last().and_then(|f| f.drift),
            max_mean_drift_percent: drifts.iter().map(|d| d.mean_percent).reduce(f32::max),
            failing_frames: frames
                .iter()
                .filter(|f| !f.passes(max_hausdorff, min_good))
                .map(|f| f.frame)
                .collect(),
        }
    }
}

fn mean(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}

impl EvalReport {
    pub(super) fn new(
        tracked: PathBuf,
        manifest: Option<PathBuf>,
        options: &EvalOptions,
        frames: Vec<FrameReport>,
        untracked_input_frames: usize,
    ) -> Self {
        Self {
            summary: Summary::of(
                &frames,
                untracked_input_frames,
                options.max_hausdorff,
                options.min_good_triangles,
            ),
            tracked,
            manifest,
            angle_threshold: options.angle_threshold,
            max_hausdorff: options.max_hausdorff,
            min_good_triangles: options.min_good_triangles,
            angle_buckets: ANGLE_BUCKETS.to_vec(),
            aspect_buckets: ASPECT_BUCKETS.to_vec(),
            frames,
        }
    }

    /// Why a frame fails the bars, or `ok`.
    fn status(&self, f: &FrameReport) -> String {
        let mut problems = Vec::new();
        if let Some(defect) = &f.defect {
            problems.push(defect.clone());
        }
        if !f.topology_matches() {
            problems.push("topology unlike the input's".to_string());
        }
        if f.hausdorff > self.max_hausdorff {
            problems.push(format!("farther than {} Δ", self.max_hausdorff));
        }
        if f.quality.above_threshold < self.min_good_triangles {
            problems.push(format!(
                "under {:.0}% good triangles",
                100.0 * self.min_good_triangles
            ));
        }
        if problems.is_empty() {
            "ok".to_string()
        } else {
            problems.join("; ")
        }
    }

    /// The per-frame table and the summary lines, as `eval` prints them.
    pub fn table(&self) -> String {
        let mut s = String::new();
        let pct = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{:.2}", 100.0 * x));
        let threshold = format!("≥{}°%", self.angle_threshold);
        let _ = writeln!(
            s,
            "{:>5} {:>8} {:>8} {:>7} {:>7} {:>7} {:>9} {:>7} {:>7} {:>7} {:>7} {:>23} {:>7} {:>14}  status",
            "frame",
            "verts",
            "Δ",
            "haus Δ",
            "mean Δ",
            "comp",
            "euler",
            "min∠",
            threshold,
            "aspect",
            "coher%",
            "lost imp/topo M+T/sub",
            "pure%",
            "drift% mean/max"
        );
        for f in &self.frames {
            let status = self.status(f);
            let drift = f.drift.map_or("-".to_string(), |d| {
                format!("{:.3}/{:.3}", d.mean_percent, d.max_percent)
            });
            let lost = f.lost.map_or("-".to_string(), |c| {
                format!(
                    "{}/{}+{}/{}",
                    c.improve.lost, c.topology_self.lost, c.topology_target.lost, c.subgrid.lost
                )
            });
            let _ = writeln!(
                s,
                "{:>5} {:>8} {:>8.4} {:>7.3} {:>7.3} {:>7} {:>9} {:>7.2} {:>7.2} {:>7.2} {:>7} {:>23} {:>7} {:>14}  {status}",
                f.frame,
                f.vertices,
                f.delta,
                f.hausdorff,
                f.mean_distance,
                format!("{}/{}", f.components, f.input_components),
                format!("{}/{}", f.euler, f.input_euler),
                f.quality.min_angle,
                100.0 * f.quality.above_threshold,
                f.quality.max_aspect,
                pct(f.coherence),
                lost,
                pct(f.checker_pure),
                drift
            );
        }
        let m = &self.summary;
        let _ = writeln!(
            s,
            "{} frames: max Hausdorff {:.3} Δ, mean distance {:.3} Δ, {} not closed manifold, {} \
             with a topology unlike the input's, worst frame has {:.2}% of triangles ≥ {}°",
            m.frames,
            m.max_hausdorff,
            m.mean_distance,
            m.not_manifold,
            m.topology_mismatches,
            100.0 * m.min_above_threshold,
            self.angle_threshold
        );
        let _ = writeln!(
            s,
            "triangles passing through each other: in {} of {} frames, at most {} pairs in a frame \
             (the input frames: at most {})",
            m.crossing_frames, m.frames, m.max_crossing_pairs, m.max_input_crossing_pairs
        );
        if let (Some(mean), Some(min)) = (m.mean_coherence, m.min_coherence) {
            let _ = writeln!(
                s,
                "coherence: {:.2}% of vertices carried over per frame on average (lowest {:.2}%)",
                100.0 * mean,
                100.0 * min
            );
        }
        if let (Some(last), Some(min)) = (m.final_checker_pure, m.min_checker_pure) {
            let _ = writeln!(
                s,
                "carried checker: {:.2}% of vertices pure at the last frame (lowest {:.2}%)",
                100.0 * last,
                100.0 * min
            );
        }
        if let Some(l) = m.lost {
            let _ = writeln!(
                s,
                "vertices lost to re-sampling over the run: improvement {}, topology on Φ(M) {}, \
                 on Φ(T) {}, sub-grid match {}",
                l.improve.lost, l.topology_self.lost, l.topology_target.lost, l.subgrid.lost
            );
            let _ = writeln!(
                s,
                "vertices re-sampled in place, their ids continued (counted as carried): topology \
                 on Φ(M) {}, on Φ(T) {}, sub-grid match {}",
                l.topology_self.continued, l.topology_target.continued, l.subgrid.continued
            );
        }
        if let (Some(last), Some(worst)) = (m.final_drift, m.max_mean_drift_percent) {
            let _ = writeln!(
                s,
                "drift from ground truth: last frame {:.3}% mean, {:.3}% max of the bounding-box \
                 diagonal ({:.1}% of frame-0 vertices survive); worst frame mean {:.3}%",
                last.mean_percent,
                last.max_percent,
                100.0 * last.survivors,
                worst
            );
        }
        if m.untracked_input_frames > 0 {
            let _ = writeln!(
                s,
                "{} input frames have no tracked frame yet",
                m.untracked_input_frames
            );
        }
        let _ = writeln!(
            s,
            "{}",
            if m.failing_frames.is_empty() {
                format!(
                    "every frame is closed, manifold, of the input's topology, within {} Δ and \
                     with ≥ {:.0}% good triangles",
                    self.max_hausdorff,
                    100.0 * self.min_good_triangles
                )
            } else {
                format!("frames failing the bars: {:?}", m.failing_frames)
            }
        );
        s
    }
}
