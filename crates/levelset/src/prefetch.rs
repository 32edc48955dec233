//! A software prefetch hint, shared by the passes whose reads jump through
//! memory in a pattern the hardware prefetcher does not follow: the distance
//! stage's point look-ups (module `distance`), tagging's sorted descent (module
//! `tagging`) and the flow's run lists (module `evolve`).
//!
//! It changes no value, only when a cache line arrives, so results are the same
//! with or without it.

/// Asks the CPU to bring the cache line of `s[at]` into L1 (nothing when `at`
/// is past the end).
#[inline(always)]
pub(crate) fn prefetch<T>(s: &[T], at: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(x) = s.get(at) {
        // SAFETY: a prefetch is a hint; it never faults and has no effect on
        // memory, and the pointer comes from a live reference.
        #[allow(unsafe_code)]
        unsafe {
            std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                std::ptr::from_ref(x).cast(),
            );
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (s, at);
}
