//! Typed errors shared by the geometry types.

/// Errors raised when building or checking the shared geometry types.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CoreError {
    /// A face refers to a vertex that does not exist.
    #[error("face {face} uses vertex {index}, but the mesh has {len} vertices")]
    IndexOutOfRange {
        /// Face number.
        face: usize,
        /// The offending vertex index.
        index: u64,
        /// Number of vertices.
        len: usize,
    },
    /// A face uses the same vertex twice.
    #[error("face {face} is degenerate: it uses vertex {index} more than once")]
    DegenerateFace {
        /// Face number.
        face: usize,
        /// The repeated vertex index.
        index: u32,
    },
    /// A polygon has fewer than three corners.
    #[error("face {face} has {corners} corners; a polygon needs at least 3")]
    TooFewCorners {
        /// Face number.
        face: usize,
        /// Its corner count.
        corners: usize,
    },
    /// A coordinate or value is NaN or infinite.
    #[error("{what} {index} is not finite ({value})")]
    NonFinite {
        /// What holds the value ("vertex", "height", …).
        what: &'static str,
        /// Its index.
        index: usize,
        /// The value itself.
        value: f64,
    },
    /// A height field has unmeasured points (NaN heights) where a step needs a
    /// height at every point.
    #[error(
        "{missing} of {total} points were not measured (missing heights); {what} needs a height \
         at every point: fill them first (`asperity convert --fill harmonic`) \
         or keep them in a format that carries them (.npy, .x3p, .gwy, \
         .gsf, .exr)"
    )]
    MissingPoints {
        /// Unmeasured points.
        missing: usize,
        /// All points.
        total: usize,
        /// The step that needs them ("a mesh", "the PSD", …).
        what: String,
    },
    /// A per-vertex (or per-point) array has the wrong length.
    #[error("{what} has {got} entries but there are {expected} vertices")]
    LengthMismatch {
        /// Which array.
        what: String,
        /// Its length.
        got: usize,
        /// The expected length.
        expected: usize,
    },
    /// Grid dimensions are zero or the data length does not match them.
    #[error("grid of {dims:?} needs {expected} values, got {got}")]
    GridSize {
        /// The requested dimensions.
        dims: Vec<usize>,
        /// Values required.
        expected: usize,
        /// Values supplied.
        got: usize,
    },
    /// A spacing is not strictly positive and finite.
    #[error("grid spacing must be positive and finite, got {0:?}")]
    BadSpacing(Vec<f64>),
    /// A mesh or point set with nothing in it where something is required.
    #[error("{0} is empty")]
    Empty(&'static str),
    /// An allocation would exceed the memory budget.
    #[error(
        "{what} would need about {} but the memory limit is {} ({from}; raise it with {})",
        crate::memory::format_bytes(*needed),
        crate::memory::format_bytes(*limit),
        crate::wording::param("max_memory")
    )]
    MemoryLimit {
        /// What was about to be allocated.
        what: String,
        /// Estimated bytes.
        needed: u64,
        /// The budget in bytes.
        limit: u64,
        /// Where the budget came from ([`crate::memory::LimitSource::describe`]).
        from: &'static str,
    },
    /// A run would take longer than the time budget.
    #[error(
        "{what} would take at least {} ({detail}), over the time limit of {} (lower the counts, or raise {} if you mean it)",
        crate::time_budget::format_seconds(*seconds),
        crate::time_budget::format_seconds(*limit_s),
        crate::wording::param("max_time")
    )]
    TimeLimit {
        /// What was about to run.
        what: String,
        /// The units, rate and threads behind the estimate.
        detail: String,
        /// Estimated seconds (a lower bound).
        seconds: f64,
        /// The limit in seconds.
        limit_s: f64,
    },
    /// A parameter is out of its valid range.
    #[error("invalid {name}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// What is wrong.
        reason: String,
    },
}
