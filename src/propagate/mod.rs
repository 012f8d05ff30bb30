//! Carrying per-vertex data through a tracked sequence (paper §4.6): values given on the first frame
//! are walked forward through each transition's event list, or values given on the last frame
//! backward, so that colours, texture coordinates or displacements stay on the material while the
//! surface deforms, merges and splits.
//!
//! The start frame's values come from a [`Source`]: a procedural 3-D [`Checker`], a PNG
//! [`Texture`] or texture coordinates through a [`Projection`] of the start frame, or an attribute
//! of any mesh file. [`propagate`] writes the carried channels as PLY vertex properties and as OBJ
//! texture coordinates and vertex colours, optionally displacing vertices along their normals by a
//! carried scalar; [`carry`] is the loop itself, for callers that want the frames in memory; [`blend`]
//! mixes a forward and a backward pass frame by frame, the paper's morph colouring (§5).

mod blend;
mod carry;
mod checker;
mod displace;
mod error;
mod projection;
mod run;
mod source;
mod texture;
mod tracked;
mod transfer;

pub use crate::sequence::{EVENTS_DIR, FRAMES_DIR, TRACK_FILE, frame_name};
pub use blend::{BACKWARD_DIR, BlendOptions, BlendSummary, FORWARD_DIR, blend};
pub use carry::{Direction, carry};
pub use checker::{Checker, DARK, LIGHT};
pub use displace::{Displace, displace};
pub use error::PropagateError;
pub use projection::{Axis, Bounds, Projection};
pub use run::{PropagateOptions, PropagateSummary, SUMMARY_FILE, propagate};
pub use source::{Channel, Source, StartFrame, start_values};
pub use texture::Texture;
pub use tracked::TrackedSequence;
pub use transfer::transfer;
