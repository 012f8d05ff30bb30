use std::path::PathBuf;

use crate::compute::Backend;

/// What `eval` compares against, where it measures, and the bars it checks.
#[derive(Debug, Clone)]
pub struct EvalOptions {
    /// The input sequence (directory, pattern or file list); `None` takes the list in `track.json`.
    pub input: Option<PathBuf>,
    pub backend: Backend,
    /// Minimum angle (degrees) a good triangle has; the paper's improvement threshold is 10°.
    pub angle_threshold: f32,
    /// Largest Hausdorff distance, in Δ, a frame may have.
    pub max_hausdorff: f32,
    /// Smallest fraction of good triangles a frame may have.
    pub min_good_triangles: f64,
    /// A folder `propagate --checker` wrote for this run: each frame's checker pure share is
    /// measured on its `frame_NNNN.ply`.
    pub checker: Option<PathBuf>,
}

impl Default for EvalOptions {
    fn default() -> Self {
        Self {
            input: None,
            backend: Backend::Cpu,
            angle_threshold: 10.0,
            max_hausdorff: 1.0,
            min_good_triangles: 0.99,
            checker: None,
        }
    }
}
