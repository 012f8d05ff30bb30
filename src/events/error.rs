use thiserror::Error;

/// Why an event list could not carry values through a frame transition, or is malformed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EventError {
    #[error("event {event} reads vertex {id}, which has no value at that point of the list")]
    MissingVertex { event: usize, id: u64 },
    #[error("{got} values given where {components} components per vertex are expected")]
    ComponentMismatch { components: usize, got: usize },
    #[error("vertex {id} is given a value twice")]
    DuplicateVertex { id: u64 },
    #[error("event {event}: {what}")]
    Malformed { event: usize, what: String },
}
