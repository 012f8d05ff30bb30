use thiserror::Error;

/// Why mesh improvement could not start.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ImproveError {
    #[error("improvement parameter {name} must be {expected}, got {value}")]
    Parameter {
        name: &'static str,
        expected: &'static str,
        value: f32,
    },
}
