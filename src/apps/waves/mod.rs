//! A wave simulation on the tracked surface (paper §5, eq. 1): `∂²h/∂t² = c² Δh − d ∂h/∂t`, `h` the
//! displacement along the normal, `Δ` the cotangent Laplacian, integrated with a symplectic scheme
//! and sub-steps on every frame, its state `(h, ∂h/∂t)` carried to the next frame through the event
//! lists (§4.6). Waves start only where topology changes happen (and at points a user names), which
//! is what the paper credits for the simulation's high signal-to-noise ratio.

mod error;
mod integrate;
mod laplacian;
mod run;
mod seed;

pub use error::WaveError;
pub use integrate::{WaveParameters, WaveState, advance, substeps};
pub use laplacian::Laplacian;
pub use run::{HEIGHT, WAVES_FILE, WaveFrame, WaveOptions, WaveSummary, waves};
pub use seed::{PointSeed, nearest_vertex, patch_vertices};
