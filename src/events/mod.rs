//! Event lists (paper §4.4): the ordered record of every vertex created or destroyed during one frame
//! transition, with sparse linear rules that carry per-vertex data forward (`f`) and backward (`g`)
//! through it (§4.6). Events come from the mesh's mutation journal, so no caller can forget to record.

mod error;
mod event;
pub mod file;
mod list;
mod propagate;
mod rule;
mod values;

pub use error::EventError;
pub use event::{Event, EventKind};
pub use list::EventList;
pub use propagate::{backward, forward};
pub use rule::Assignment;
pub use values::VertexValues;
