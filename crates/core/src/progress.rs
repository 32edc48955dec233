//! Progress reporting that does not tie libraries to a terminal UI.
//!
//! Long-running library functions take `&dyn Progress`; the CLI passes an
//! indicatif bar (drawn on stderr only when it is a terminal), tests pass
//! [`NoProgress`]. Implementations must be cheap to call from several threads.

/// Receives progress from long-running work.
pub trait Progress: Sync {
    /// A new phase of `total` units begins, described by `message`.
    fn start(&self, total: u64, message: &str);
    /// `n` more units are done.
    fn advance(&self, n: u64);
    /// The current phase is over.
    fn finish(&self);
}

/// Ignores all progress.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {
    fn start(&self, _total: u64, _message: &str) {}
    fn advance(&self, _n: u64) {}
    fn finish(&self) {}
}
