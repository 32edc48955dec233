//! Errors of the growth simulators.

use asperity_core::CoreError;

/// Why a simulation could not run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GrowthError {
    /// A parameter is outside its domain; the message names it and its range.
    #[error("{0}")]
    BadParameter(String),
    /// The lattice cannot hold what was asked of it.
    #[error("{0}")]
    Capacity(String),
    /// An allocation would exceed the memory budget, or a core type rejected its input.
    #[error(transparent)]
    Core(#[from] CoreError),
}

pub(crate) fn bad(msg: impl Into<String>) -> GrowthError {
    GrowthError::BadParameter(msg.into())
}
