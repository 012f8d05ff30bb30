//! Many caches in one run (`surftrack batch`): the manifest that lists them, the folder and status
//! file of each, which cache a farm task takes, and the report assembled from the statuses. Each
//! cache is tracked by the sequence driver ([`crate::sequence`]) like any other run.

mod error;
mod manifest;
mod report;
mod select;
mod status;

pub use error::BatchError;
pub use manifest::{Cache, Manifest};
pub use report::{BATCH_FILE, BatchReport, Entry, table};
pub use select::{INDEX_VARIABLES, task_index};
pub use status::{CacheStatus, STATUS_FILE, STATUS_VERSION, State};
