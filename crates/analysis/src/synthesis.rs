//! Self-affine surfaces by Fourier filtering with random phases, in O(N² log N).
//!
//! The same surface as [`asperity_core::fourier_surface`] — the same modes,
//! amplitudes |q|^(−(1+H)) and phases, drawn in the same order from the same
//! seed — but summed by one inverse 2-D FFT instead of separable direct sums
//! (O(N·M² + N²·M)): z(x, y) = Re Σ c_mn e^{2πi(m x + n y)/N}, each mode's
//! coefficient c_mn = A e^{iφ} added to FFT bin (m mod N, n mod N). Modes that
//! alias onto one bin on the grid (m = ±N/2) are added together, exactly as the
//! direct sum evaluates them. The two agree to rounding (tested), so the direct
//! synthesis is this generator's independent reference. This is the classic
//! "Fourier filtering" method kim-machiraju-thompson list among fractal
//! generators, and the reference input of this crate's tests.
//!
//! Parallel over rows and columns of the FFT, each line transformed alone, so
//! the output is the same bytes at any thread count.

use asperity_core::fourier_surface::FourierParams;
use asperity_core::{HeightField, MemoryBudget, seeded};
use rand::Rng;
use rustfft::num_complex::Complex;

use crate::AnalysisError;
use crate::psd::fft2;

/// A periodic self-affine height field (see the module docs).
///
/// # Errors
/// [`AnalysisError::Core`] for parameters out of range or a grid above `budget`
/// (the estimate counts the complex FFT buffer and its transpose).
pub fn fbm(
    p: &FourierParams,
    seed: u64,
    budget: &MemoryBudget,
) -> Result<HeightField, AnalysisError> {
    p.validate()?;
    let n = p.n;
    budget.check_elements(
        n as u128 * n as u128,
        16 * 2 + 8,
        "the Fourier synthesis buffers",
    )?;
    let mut data = vec![Complex::new(0.0f64, 0.0); n * n];
    let mut rng = seeded(seed);
    let tau = std::f64::consts::TAU;
    for (m, k, amp) in p.mode_amplitudes() {
        let phase = rng.random::<f64>() * tau;
        let (s, c) = phase.sin_cos();
        let x = m.rem_euclid(n as i64) as usize;
        let y = k.rem_euclid(n as i64) as usize;
        data[x + n * y] += Complex::new(amp * c, amp * s);
    }
    fft2(&mut data, n, n, true);
    let mut h = HeightField::try_filled([n, n], 0.0, budget)?.with_spacing([p.spacing; 2])?;
    for (z, c) in h.data_mut().iter_mut().zip(&data) {
        *z = c.re;
    }
    drop(data);
    p.normalise(&mut h);
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::fourier_surface::fourier_surface;

    #[test]
    fn equals_the_direct_synthesis() {
        for (n, modes, hurst) in [(64, 32, 0.8), (48, 10, 0.3), (33, 16, 0.5), (128, 64, 1.0)] {
            let p = FourierParams {
                n,
                hurst,
                modes,
                rms: 1.5,
                spacing: 0.25,
            };
            let budget = MemoryBudget::unlimited();
            let a = fbm(&p, 11, &budget).unwrap();
            let b = fourier_surface(&p, 11, &budget).unwrap();
            let err = a
                .data()
                .iter()
                .zip(b.data())
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-10, "n={n} modes={modes}: max difference {err}");
            assert_eq!(a.spacing(), b.spacing());
        }
    }

    #[test]
    fn validates_like_the_reference() {
        let budget = MemoryBudget::unlimited();
        let bad = FourierParams {
            n: 64,
            hurst: 1.5,
            modes: 32,
            rms: 1.0,
            spacing: 1.0,
        };
        assert!(fbm(&bad, 1, &budget).is_err());
        let big = FourierParams {
            n: 1 << 15,
            hurst: 0.5,
            modes: 8,
            rms: 1.0,
            spacing: 1.0,
        };
        let e = fbm(&big, 1, &MemoryBudget::new(1 << 30))
            .unwrap_err()
            .to_string();
        assert!(e.contains("Fourier synthesis"), "{e}");
    }
}
