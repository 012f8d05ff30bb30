//! What consumes a tracked sequence's persistent ids: per-vertex velocities for motion blur.

mod velocity;

pub use velocity::{NoIds, Trail, VelocityFrame, VelocityStream, trail, velocities};
