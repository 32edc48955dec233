//! The fast generator of the simulation loops.
//!
//! Growth models draw one to three random numbers per lattice step and run
//! 10⁸–10⁹ steps, so they use Xoshiro256++ (`rand_xoshiro`), about four times
//! faster than the ChaCha8 [`asperity_core::SimRng`]. Each run's generator is
//! seeded from the core sub-stream `substream(seed, run)`, which keeps the
//! determinism contract of [`asperity_core::rng`]: run `r` sees the same numbers
//! whatever the thread count.

use rand::{RngCore, SeedableRng};

/// The generator used inside simulation loops.
pub type FastRng = rand_xoshiro::Xoshiro256PlusPlus;

/// The generator of run `run` under `seed`.
pub fn fast_rng(seed: u64, run: u64) -> FastRng {
    FastRng::from_rng(&mut asperity_core::substream(seed, run))
}

/// Uniform integer in `0..n` by Lemire's multiply-shift on 64 bits (bias below
/// n / 2⁶⁴, far under any statistical resolution here).
#[inline(always)]
pub fn below(rng: &mut FastRng, n: u64) -> u64 {
    ((rng.next_u64() as u128 * n as u128) >> 64) as u64
}

/// Uniform `f64` in [0, 1) with 53 random bits.
#[inline(always)]
pub fn unit(rng: &mut FastRng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Uniform direction on the unit sphere (Marsaglia 1972).
#[inline]
pub fn unit_vector3(rng: &mut FastRng) -> [f64; 3] {
    loop {
        let a = 2.0 * unit(rng) - 1.0;
        let b = 2.0 * unit(rng) - 1.0;
        let s = a * a + b * b;
        if s < 1.0 {
            let f = 2.0 * (1.0 - s).sqrt();
            return [a * f, b * f, 1.0 - 2.0 * s];
        }
    }
}

/// Uniform direction on the unit circle (in the xy plane, z = 0).
#[inline]
pub fn unit_vector2(rng: &mut FastRng) -> [f64; 3] {
    let t = std::f64::consts::TAU * unit(rng);
    [t.cos(), t.sin(), 0.0]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproducible_and_uniform() {
        let mut a = fast_rng(7, 2);
        let mut b = fast_rng(7, 2);
        assert_eq!(a.next_u64(), b.next_u64());
        assert_ne!(fast_rng(7, 3).next_u64(), fast_rng(7, 2).next_u64());
        let mut counts = [0u32; 6];
        for _ in 0..60_000 {
            counts[below(&mut a, 6) as usize] += 1;
        }
        // Each count is Binomial(60000, 1/6): σ ≈ 91; allow 5σ.
        assert!(
            counts.iter().all(|&c| (c as i64 - 10_000).abs() < 460),
            "{counts:?}"
        );
        let mut mean = [0.0; 3];
        for _ in 0..30_000 {
            let v = unit_vector3(&mut a);
            assert!((v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - 1.0).abs() < 1e-12);
            for k in 0..3 {
                mean[k] += v[k] / 30_000.0;
            }
        }
        // Mean of a uniform direction is 0 with σ = 1/√(3·30000) ≈ 0.0033.
        assert!(mean.iter().all(|m| m.abs() < 0.017), "{mean:?}");
    }
}
