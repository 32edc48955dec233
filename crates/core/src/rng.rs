//! Reproducible randomness: one `u64` seed, portable generators, derived sub-streams.
//!
//! # The rule
//! Library code never draws from the OS or from a thread-local generator. Every
//! stochastic function takes `&mut impl rand::Rng` (sequential code) or a `u64`
//! seed (parallel code), and the CLI prints and accepts `--seed`.
//!
//! # Generator
//! [`SimRng`] is ChaCha with 8 rounds from `rand_chacha`, whose output is specified
//! by the algorithm, unlike `rand::rngs::StdRng`, which rand documents as not
//! portable across versions. [`seeded`]`(seed)` expands the `u64` into the 256-bit
//! key with `SeedableRng::seed_from_u64` (PCG32 expansion, fixed by `rand_core`).
//!
//! # Sub-streams for parallel code
//! ChaCha has a 64-bit *stream* number beside its key: the same key with a different
//! stream gives an independent sequence of 2⁶⁸ bytes. Parallel code splits its
//! work into **tasks whose boundaries do not depend on the thread count** (rows,
//! tiles, walkers, particles numbered 0..n) and gives task `t` the generator
//! [`substream`]`(seed, t)`: key from `seed` as above, stream = `t`. Results are then
//! combined in task order. Whatever the number of threads, each task sees the same
//! numbers, so the output is byte-identical. Nested derivations (task `t` of phase
//! `p`) use [`mix_stream`] to combine identifiers into one stream number.
//!
//! ```
//! use asperity_core::{seeded, substream};
//! use rand::Rng;
//! let a: u64 = substream(7, 3).random();
//! let b: u64 = substream(7, 3).random();
//! assert_eq!(a, b);
//! assert_ne!(a, substream(7, 4).random::<u64>());
//! assert_eq!(seeded(7).random::<u64>(), substream(7, 0).random::<u64>());
//! ```

use rand::SeedableRng;

/// The simulation random-number generator (ChaCha8, portable and seekable).
pub type SimRng = rand_chacha::ChaCha8Rng;

/// The generator for `seed` (stream 0).
pub fn seeded(seed: u64) -> SimRng {
    SimRng::seed_from_u64(seed)
}

/// Generator for independent task `stream` under `seed` (see the module docs).
pub fn substream(seed: u64, stream: u64) -> SimRng {
    let mut rng = seeded(seed);
    rng.set_stream(stream);
    rng
}

/// Combines two identifiers (e.g. phase and task) into one stream number.
///
/// Uses the SplitMix64 finaliser, a bijection on `u64`, on `a`, then mixes in `b`.
pub fn mix_stream(a: u64, b: u64) -> u64 {
    splitmix64(splitmix64(a) ^ b)
}

fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    const PINNED_SEED42_FIRST_U64: u64 = 12_578_764_544_318_200_737;

    #[test]
    fn generator_is_pinned() {
        // Regression pin, not a truth check: if a dependency update changed the
        // ChaCha8 stream or the seed expansion, every seeded output in asperity would
        // silently change. Value recorded with rand_chacha 0.9 when this was written.
        let v: u64 = seeded(42).random();
        assert_eq!(v, PINNED_SEED42_FIRST_U64);
        let w: u64 = substream(42, 5).random();
        assert_ne!(v, w);
    }

    #[test]
    fn streams_differ_and_mix_is_stable() {
        let a: u64 = substream(1, 0).random();
        let b: u64 = substream(1, 1).random();
        assert_ne!(a, b);
        assert_eq!(mix_stream(3, 4), mix_stream(3, 4));
        assert_ne!(mix_stream(3, 4), mix_stream(4, 3));
    }
}
