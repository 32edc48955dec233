//! When the allocator hands freed memory back to the kernel.
//!
//! mimalloc keeps freed pages for a while (its purge delay, 1 s in v3) so that
//! the next buffer reuses them instead of faulting fresh ones in: the
//! subdivision and rendering commands run faster for it. The level set's
//! stages free large buffers one after the other (the distance's packed
//! closest points, the crossings' wavefront, the flow's masks, the marching
//! cubes' keys) while the next stage allocates its own, and pages held for
//! a second count in the process's peak memory: with the delay the 512³
//! plane-deposit reconstruction peaks at 1.42 GiB, without it at 0.91 GiB
//! (BENCHMARKS.md, 2026-11-27). Commands that reconstruct surfaces purge at
//! once while they run.
//!
//! `analyze` goes the other way: its filters, spectra and segmentation free
//! and allocate field-sized buffers (134 MB at 4096²) for over a second at a
//! time, so with the delay the kernel zeroes the same pages again and again
//! (a quarter of the run's time on a 2-vCPU VM). It keeps freed pages while it
//! runs: 4096² with an S and an L filter, 13.4 s → 11.5 s, peak 2.05 → 2.16 GB
//! (#56, BENCHMARKS.md).

use libmimalloc_sys::{mi_option_get, mi_option_set, mi_option_t};

/// mimalloc's `mi_option_purge_delay` (milliseconds; 0 purges at once). The
/// crate names no constant for it: it comes just before `use_numa_nodes` in
/// `mimalloc.h`'s `mi_option_e` (the test checks its default).
const PURGE_DELAY: mi_option_t = 15;
const _: () = assert!(libmimalloc_sys::mi_option_use_numa_nodes - 1 == PURGE_DELAY);

/// While alive, freed memory goes back to the kernel at once ([`Self::prompt`])
/// or never ([`Self::never`]); the previous delay returns when it is dropped.
pub struct PurgeDelay {
    before: std::ffi::c_long,
}

impl PurgeDelay {
    /// Freed memory goes back at once (delay 0).
    pub fn prompt() -> Self {
        Self::set(0)
    }

    /// Freed memory stays with the process for reuse (delay −1).
    pub fn never() -> Self {
        Self::set(-1)
    }

    fn set(delay: std::ffi::c_long) -> Self {
        // SAFETY: mimalloc's option calls read and write its option table
        // (atomics); any value is valid for the delay.
        #[allow(unsafe_code)]
        let before = unsafe {
            let before = mi_option_get(PURGE_DELAY);
            mi_option_set(PURGE_DELAY, delay);
            before
        };
        Self { before }
    }
}

impl Drop for PurgeDelay {
    fn drop(&mut self) {
        // SAFETY: as in `set`.
        #[allow(unsafe_code)]
        unsafe {
            mi_option_set(PURGE_DELAY, self.before);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_delay_is_set_and_restored() {
        #[allow(unsafe_code)]
        // SAFETY: as in `PurgeDelay::set`.
        let get = || unsafe { mi_option_get(PURGE_DELAY) };
        let before = get();
        // v3's default delay, unless the environment sets one.
        if std::env::var_os("MIMALLOC_PURGE_DELAY").is_none() {
            assert_eq!(before, 1000);
        }
        {
            let _p = PurgeDelay::prompt();
            assert_eq!(get(), 0);
        }
        assert_eq!(get(), before);
        {
            let _p = PurgeDelay::never();
            assert_eq!(get(), -1);
        }
        assert_eq!(get(), before);
    }
}
