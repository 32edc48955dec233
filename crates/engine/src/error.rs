//! The engine's error: every method crate's error, plus refusals of the
//! engine's own (a parameter out of range, a file that does not say what it
//! should), each with a kind a front end maps to its own convention (the CLI's
//! exit code, Python's `ValueError`/`OSError`/`MemoryError`).

use asperity_analysis::AnalysisError;
use asperity_ca::CaError;
use asperity_core::CoreError;
use asperity_growth::GrowthError;
use asperity_ifs::IfsError;
use asperity_io::IoError;
use asperity_render::RenderError;

/// Why a job was refused or failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EngineError {
    /// A parameter or an input the job cannot use; the message says which and why.
    #[error("{0}")]
    Invalid(String),
    /// A parameter the job does not have, or a value of the wrong type (a
    /// front end's `TypeError`); the message names it.
    #[error("{0}")]
    Type(String),
    /// A shared-type error: invalid geometry, a size, the memory budget.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// Reading or writing a file.
    #[error(transparent)]
    File(#[from] IoError),
    /// A growth simulation refused its parameters.
    #[error(transparent)]
    Growth(#[from] GrowthError),
    /// A cellular-automaton run refused its rule or grid.
    #[error(transparent)]
    Ca(#[from] CaError),
    /// A projected-IFS model is invalid.
    #[error(transparent)]
    Ifs(#[from] IfsError),
    /// An analysis could not be made.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// A picture could not be drawn.
    #[error(transparent)]
    Render(#[from] RenderError),
}

/// What kind of failure an [`EngineError`] is, for front ends that map kinds to
/// their own conventions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// Bad parameters or input data: the caller can fix the request.
    Invalid,
    /// A parameter the job does not have, or a value of the wrong type.
    Type,
    /// The operating system refused a file operation.
    Os,
    /// The job would exceed the memory budget.
    Memory,
    /// The job would run longer than the time budget.
    Time,
}

impl EngineError {
    /// The kind of failure.
    pub fn kind(&self) -> ErrorKind {
        match self {
            EngineError::File(IoError::Os { .. }) => return ErrorKind::Os,
            EngineError::Type(_) => return ErrorKind::Type,
            _ => {}
        }
        match self.core() {
            Some(CoreError::MemoryLimit { .. }) => ErrorKind::Memory,
            Some(CoreError::TimeLimit { .. }) => ErrorKind::Time,
            _ => ErrorKind::Invalid,
        }
    }

    /// The shared-type error behind this one, if any (a memory refusal's
    /// estimate, for a front end that reports it as numbers).
    pub fn core(&self) -> Option<&CoreError> {
        match self {
            EngineError::Core(e)
            | EngineError::Growth(GrowthError::Core(e))
            | EngineError::Ca(CaError::Core(e))
            | EngineError::Ifs(IfsError::Core(e))
            | EngineError::Analysis(AnalysisError::Core(e))
            | EngineError::Render(RenderError::Core(e)) => Some(e),
            _ => None,
        }
    }
}

/// Shorthand for the engine's results.
pub type Result<T, E = EngineError> = std::result::Result<T, E>;

/// An [`EngineError::Invalid`] with this message.
pub fn invalid(msg: impl Into<String>) -> EngineError {
    EngineError::Invalid(msg.into())
}

/// `Err(invalid(msg))` unless `ok`.
///
/// # Errors
/// [`EngineError::Invalid`] with `msg` when `ok` is false.
pub fn ensure(ok: bool, msg: impl FnOnce() -> String) -> Result<()> {
    if ok { Ok(()) } else { Err(invalid(msg())) }
}

impl From<String> for EngineError {
    fn from(msg: String) -> Self {
        EngineError::Invalid(msg)
    }
}
