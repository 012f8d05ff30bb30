//! Tracked sequences in the forms renderers and DCCs read: one USD `Mesh` prim whose points,
//! topology, persistent `id` primvar, carried channels and `velocities` are sampled per frame, and
//! PLY frames with velocities as `vx vy vz`.
//!
//! Frames are read one at a time ([`crate::apps::VelocityStream`]). PLY frames are written as they
//! come; a USD layer is written whole, as the format's layer model asks, so the export holds the
//! compact sample arrays of every frame (about 40 bytes per vertex and frame, plus carried channels)
//! and never more than two meshes.
//!
//! USD text (`.usda`) is written by the `openusd` crate. Binary `.usdc` is refused: the release of
//! that crate this toolchain builds (0.6) writes crate files whose child lists Pixar's USD rejects
//! (fixed in 0.7, which needs Rust 1.96); `usdcat OUT.usda -o OUT.usdc` converts.

mod error;
mod primvar;
mod run;
mod source;
mod usd;

pub use error::ExportError;
pub use primvar::{Primvar, primvar_of};
pub use run::{ExportOptions, ExportSummary, VELOCITY, export};
pub use source::ExportSource;
pub use usd::{PRIM, UpAxis, UsdLayer, UsdSettings};
