//! Errors of the P-IFS model and its differential analysis.

use asperity_core::CoreError;

/// Which constraint of the P-IFS model (poull-gentil §2.1–2.2) an input violates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Constraint {
    /// Matrix sizes, operator count, control-point count.
    Shape,
    /// Every entry and coordinate must be finite.
    Finite,
    /// Columns of a barycentric operator sum to 1 (§2.2).
    Barycentric,
    /// Every operator contracts the barycentric vector space (§2.1).
    Contractivity,
    /// The C⁰ adjacency constraint T0·c1 = T1·c0 (§2.1).
    Adjacency,
}

impl std::fmt::Display for Constraint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Constraint::Shape => "shape",
            Constraint::Finite => "finiteness",
            Constraint::Barycentric => "barycentric",
            Constraint::Contractivity => "contractivity",
            Constraint::Adjacency => "C0 adjacency",
        })
    }
}

/// Errors raised by this crate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum IfsError {
    /// The model violates a named constraint.
    #[error("the {constraint} constraint is violated: {detail}")]
    Violated {
        /// The constraint.
        constraint: Constraint,
        /// What exactly is wrong, naming the operator, column or point.
        detail: String,
    },
    /// A parameter is out of its range.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// The parameter (as the CLI spells it).
        name: String,
        /// Why it is refused.
        reason: String,
    },
    /// The DCF is not defined for this operator (non-diagonalisable, complex
    /// or negative dominant eigenvalue).
    #[error("the DCF of {operator} is not defined: {reason}")]
    NoDcf {
        /// The operator, e.g. `T0` or `T0⊗T'1`.
        operator: String,
        /// Why.
        reason: String,
    },
    /// A model file could not be understood.
    #[error("model file: {0}")]
    File(String),
    /// A shared-type error (mesh construction, memory budget).
    #[error(transparent)]
    Core(#[from] CoreError),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, IfsError>;

pub(crate) fn violated(constraint: Constraint, detail: impl Into<String>) -> IfsError {
    IfsError::Violated {
        constraint,
        detail: detail.into(),
    }
}

pub(crate) fn invalid(name: &str, reason: impl Into<String>) -> IfsError {
    IfsError::InvalidParameter {
        name: name.into(),
        reason: reason.into(),
    }
}
