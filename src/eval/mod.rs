//! How good a tracked sequence is (the figures a user cares about, issue bars of the tracker): for
//! each frame, the two-sided Hausdorff and mean distance to its input frame in units of the input's
//! mean edge length Δ, components and Euler characteristic against the input's, triangle quality
//! (minimum angle against the improvement threshold of paper §4.1, aspect ratio), coherence (the
//! fraction of vertices carried over from the previous frame), and, when a synth manifest gives the
//! rigid motion, the drift of tracked material points from their true positions (paper §6, Fig. 10).

mod checker;
mod distance;
mod drift;
mod error;
mod intersections;
mod options;
mod plot;
mod quality;
mod report;
mod run;

pub use crate::geometry::ANGLE_BUCKETS;
pub use checker::{PURE_TOLERANCE, pure_share};
pub use distance::{
    SurfaceDistances, labelled_surface_samples, surface_distances, surface_samples,
};
pub use drift::{Drift, MaterialPoints};
pub use error::EvalError;
pub use intersections::intersecting_pairs;
pub use options::EvalOptions;
pub use plot::{plot, stage_times};
pub use quality::{ASPECT_BUCKETS, TriangleQuality, triangle_quality};
pub use report::{EvalReport, FrameReport, Summary};
pub use run::evaluate;
