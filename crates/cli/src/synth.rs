//! Built-in sample surface for the demo and tests: a periodic self-affine height
//! field by random-phase Fourier synthesis.
//!
//! This is test data, not one of the papers' methods: a surface whose power
//! spectrum is known in closed form, C(q) ∝ q^(−2(1+H)) for wavevectors
//! 0 < |q| ≤ q_max, so the analysis issue can check its Hurst estimator against
//! it (a self-affine surface with Hurst exponent H has fractal dimension 3 − H).
//!
//! z(x, y) = Σ_(m,n) A(q) cos(q_m x + q_n y + φ_mn), A(q) = q^(−(1+H)),
//! q = 2π(m, n)/L, phases φ uniform from the seeded generator, then scaled to the
//! requested rms height. Evaluated separably (a sum over n of row sums over m),
//! rows in parallel; each output value is summed in a fixed order, so the result
//! does not depend on the thread count.

use asperity_core::{HeightField, MemoryBudget, seeded};
use rand::Rng;
use rayon::prelude::*;

/// Parameters of [`fourier_surface`].
#[derive(Clone, Debug)]
pub struct FourierParams {
    /// Samples per side (square, periodic).
    pub n: usize,
    /// Hurst exponent H in (0, 1].
    pub hurst: f64,
    /// Highest mode index along each axis (q_max = 2π·modes/L).
    pub modes: usize,
    /// Target rms height.
    pub rms: f64,
    /// Grid spacing.
    pub spacing: f64,
}

/// A periodic self-affine height field (see the module docs).
pub fn fourier_surface(
    p: &FourierParams,
    seed: u64,
    budget: &MemoryBudget,
) -> anyhow::Result<HeightField> {
    anyhow::ensure!(p.n >= 2, "size must be at least 2");
    anyhow::ensure!(
        p.hurst > 0.0 && p.hurst <= 1.0,
        "Hurst exponent must be in (0, 1], got {}",
        p.hurst
    );
    anyhow::ensure!(
        p.modes >= 1 && p.modes <= p.n / 2,
        "modes must be in 1..={}",
        p.n / 2
    );
    let mut h = HeightField::try_filled([p.n, p.n], 0.0, budget)?.with_spacing([p.spacing; 2])?;
    let m = p.modes as i64;
    let l = p.n as f64 * p.spacing;
    let tau = std::f64::consts::TAU;
    // Half-plane of modes (the other half is the complex conjugate).
    let mut rng = seeded(seed);
    let mut modes = Vec::new();
    for j in 0..=m {
        for i in -m..=m {
            if j == 0 && i <= 0 {
                continue;
            }
            let q = tau * ((i * i + j * j) as f64).sqrt() / l;
            let phase: f64 = rng.random::<f64>() * tau;
            modes.push((i, j, q.powf(-(1.0 + p.hurst)), phase));
        }
    }
    let n = p.n;
    h.data_mut()
        .par_chunks_mut(n)
        .enumerate()
        .for_each(|(row, out)| {
            let y = row as f64 * p.spacing;
            for (col, z) in out.iter_mut().enumerate() {
                let x = col as f64 * p.spacing;
                *z = modes
                    .iter()
                    .map(|&(i, j, a, ph)| a * (tau * (i as f64 * x + j as f64 * y) / l + ph).cos())
                    .sum();
            }
        });
    let mean = h.mean();
    let rms = (h.data().iter().map(|z| (z - mean).powi(2)).sum::<f64>() / (n * n) as f64).sqrt();
    let scale = if rms > 0.0 { p.rms / rms } else { 0.0 };
    h.data_mut()
        .iter_mut()
        .for_each(|z| *z = (*z - mean) * scale);
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rms_periodicity_and_determinism() {
        let p = FourierParams {
            n: 32,
            hurst: 0.7,
            modes: 8,
            rms: 2.0,
            spacing: 0.5,
        };
        let a = fourier_surface(&p, 3, &MemoryBudget::unlimited()).unwrap();
        let mean = a.mean();
        let rms =
            (a.data().iter().map(|z| (z - mean).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
        assert!(mean.abs() < 1e-12 && (rms - 2.0).abs() < 1e-12);
        // Spectrum: the DFT at mode (i, j) is N²/2 · A(q) · e^{iφ} up to the rms
        // scale, so amplitude ratios must follow q^-(1+H) exactly.
        let dft = |i: f64, j: f64| {
            let (mut re, mut im) = (0.0, 0.0);
            for y in 0..32 {
                for x in 0..32 {
                    let t = -std::f64::consts::TAU * (i * x as f64 + j * y as f64) / 32.0;
                    re += a.get(x, y) * t.cos();
                    im += a.get(x, y) * t.sin();
                }
            }
            (re * re + im * im).sqrt()
        };
        let base = dft(1.0, 0.0);
        for (i, j) in [(2.0, 0.0), (3.0, 4.0), (0.0, 7.0)] {
            let q: f64 = i * i + j * j;
            let want = q.sqrt().powf(-(1.0 + 0.7));
            assert!(
                (dft(i, j) / base - want).abs() < 1e-9 * want.max(1.0),
                "mode ({i}, {j})"
            );
        }
        assert!(dft(9.0, 0.0) < 1e-9 * base, "no modes above q_max");
        let b = fourier_surface(&p, 3, &MemoryBudget::unlimited()).unwrap();
        assert_eq!(a, b);
        assert_ne!(
            a,
            fourier_surface(&p, 4, &MemoryBudget::unlimited()).unwrap()
        );
        assert!(
            fourier_surface(
                &FourierParams {
                    hurst: 1.5,
                    ..p.clone()
                },
                1,
                &MemoryBudget::unlimited()
            )
            .is_err()
        );
    }
}
