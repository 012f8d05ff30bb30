//! Tracked sequences in the forms renderers and DCCs read: one USD `Mesh` prim whose points,
//! topology, persistent `id` primvar, carried channels and `velocities` are sampled per frame, and
//! PLY frames with velocities as `vx vy vz`.
//!
//! Frames are read one at a time ([`crate::apps::VelocityStream`]) and written as they come: PLY
//! frames one file each, a USD file streamed (binary `.usdc`/`.usd` writes each frame's arrays into
//! the file at once, text `.usda` spools each attribute's samples to a temporary file), so memory
//! holds two meshes and one frame's samples whatever the length of the sequence. Both USD forms
//! are written here from USD's file format sources: no Rust USD crate this toolchain builds writes
//! crate files USD reads, nor streams.

mod error;
mod primvar;
mod run;
mod source;
mod usd;
mod usd_file;
mod usda;
mod usdc;

pub use error::ExportError;
pub use primvar::{Primvar, primvar_of};
pub use run::{ExportOptions, ExportSummary, VELOCITY, export};
pub use source::ExportSource;
pub use usd::{PRIM, UpAxis, UsdSettings};
