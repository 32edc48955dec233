//! Deliberate faults in the kernels the dense and sparse stages share
//! (feature `fault-injection`, for `tests/faults.rs` only): each one breaks a
//! kernel the way a plausible bug would, so that the test can check that the
//! comparison with [`crate::reference`] catches it — and that sparse-equals-
//! dense, whose two sides share the kernel, cannot.
//!
//! One fault is active at a time, process-wide (the kernels run on rayon's
//! threads); [`inject`] returns a guard that clears it.

use std::sync::atomic::{AtomicU8, Ordering::Relaxed};

/// A fault in a shared kernel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Fault {
    /// The flow's rate upwinds |∇φ| for an outward-moving front (the
    /// Godunov sides swapped: max(D⁻,0)², min(D⁺,0)²).
    UpwindSide = 1,
    /// The ENO correction of D⁻ added with the wrong sign.
    EnoSign = 2,
    /// The redistancing's pseudo-time step doubled (0.6h).
    RedistanceStep = 3,
    /// The wavefront's per-axis squared distances measured a tenth of a cell
    /// too far (`axis_squares`; the seeds' exact distances stay right).
    AxisSquares = 4,
}

static ACTIVE: AtomicU8 = AtomicU8::new(0);

/// Clears the fault when dropped.
#[must_use = "the fault is cleared when the guard is dropped"]
pub struct Injected(());

impl Drop for Injected {
    fn drop(&mut self) {
        ACTIVE.store(0, Relaxed);
    }
}

/// Turns `fault` on until the guard is dropped.
pub fn inject(fault: Fault) -> Injected {
    ACTIVE.store(fault as u8, Relaxed);
    Injected(())
}

/// Whether `fault` is on.
#[inline(always)]
pub(crate) fn on(fault: Fault) -> bool {
    ACTIVE.load(Relaxed) == fault as u8
}
