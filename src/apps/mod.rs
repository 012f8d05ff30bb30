//! What consumes a tracked sequence's persistent ids and event lists (paper §5): per-vertex
//! velocities for motion blur, and a wave simulation seeded where the topology changes.

mod velocity;
pub mod waves;

pub use velocity::{NoIds, Trail, VelocityFrame, VelocityStream, trail, velocities};
