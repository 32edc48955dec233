//! Reference surface with a known spectrum: periodic self-affine height fields by
//! random-phase Fourier synthesis.
//!
//! This is test and demo data, not one of the papers' methods. Its power spectrum
//! is known in closed form, C(q) ∝ q^(−2(1+H)) for wavevectors 0 < |q_x|, |q_y| ≤
//! q_max, so analysis code can check a Hurst estimator against it (a self-affine
//! surface with Hurst exponent H has fractal dimension D = 3 − H).
//!
//! z(x, y) = Σ_(m,n) A(q) cos(q_m x + q_n y + φ_mn),  A(q) = |q|^(−(1+H)),
//! q = 2π(m, n)/L over the half-plane of modes n > 0, or n = 0 and m > 0, with
//! |m|, |n| ≤ `modes`; phases φ are uniform, drawn in that mode order from
//! [`seeded`]`(seed)`; finally the mean is removed and the
//! surface scaled to the requested rms height.
//!
//! # Algorithm
//! Separable evaluation: with S_n(x) = Σ_m A e^{i(q_m x + φ_mn)}, each height is
//! z(x, y) = Re Σ_n e^{i q_n y} S_n(x), so the cost is O(N·M² + N²·M) for an
//! N×N grid and M modes per axis instead of O(N²·M²); every phase factor is an
//! entry of one table of N-th roots of unity. Sequential, so the output
//! is the same bytes on any machine with IEEE-754 arithmetic and any thread count.

use rand::Rng;

use crate::{CoreError, HeightField, MemoryBudget, seeded};

/// Parameters of [`fourier_surface`].
#[derive(Clone, Debug, PartialEq)]
pub struct FourierParams {
    /// Samples per side (the grid is square and periodic with period n·spacing).
    pub n: usize,
    /// Hurst exponent H in (0, 1].
    pub hurst: f64,
    /// Highest mode index per axis, 1 ≤ modes ≤ n/2 (q_max = 2π·modes/L).
    pub modes: usize,
    /// Root-mean-square height of the result.
    pub rms: f64,
    /// Grid spacing.
    pub spacing: f64,
}

impl FourierParams {
    /// Checks every parameter's range.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] naming the parameter.
    pub fn validate(&self) -> crate::Result<()> {
        let p = self;
        if p.n < 2 {
            return Err(invalid(
                "size",
                format!("need at least 2 samples per side, got {}", p.n),
            ));
        }
        if !(p.hurst > 0.0 && p.hurst <= 1.0) {
            return Err(invalid(
                "Hurst exponent",
                format!("must be in (0, 1], got {}", p.hurst),
            ));
        }
        if p.modes < 1 || p.modes > p.n / 2 {
            return Err(invalid(
                "modes",
                format!("must be in 1..={}, got {}", p.n / 2, p.modes),
            ));
        }
        if !(p.rms.is_finite() && p.rms >= 0.0) {
            return Err(invalid(
                "rms",
                format!("must be finite and non-negative, got {}", p.rms),
            ));
        }
        Ok(())
    }

    /// Removes the mean and scales to the requested rms height (a flat field stays 0).
    pub fn normalise(&self, h: &mut HeightField) {
        let mean = h.mean();
        let var = h.data().iter().map(|z| (z - mean).powi(2)).sum::<f64>() / h.len() as f64;
        let scale = if var > 0.0 {
            self.rms / var.sqrt()
        } else {
            0.0
        };
        h.data_mut()
            .iter_mut()
            .for_each(|z| *z = (*z - mean) * scale);
    }

    /// The modes (m, n) of the half-plane n > 0 or (n = 0, m > 0), |m|, |n| ≤ `modes`,
    /// in the order their phases are drawn, with their amplitudes |q|^(−(1+H)).
    pub fn mode_amplitudes(&self) -> impl Iterator<Item = (i64, i64, f64)> + '_ {
        let m = self.modes as i64;
        let l = self.n as f64 * self.spacing;
        (0..=m).flat_map(move |j| {
            (-m..=m)
                .filter(move |&i| !(j == 0 && i <= 0))
                .map(move |i| {
                    let q = std::f64::consts::TAU * ((i * i + j * j) as f64).sqrt() / l;
                    (i, j, q.powf(-(1.0 + self.hurst)))
                })
        })
    }
}

fn invalid(name: &'static str, reason: String) -> CoreError {
    CoreError::InvalidParameter { name, reason }
}

/// A periodic self-affine height field (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for parameters out of range,
/// [`CoreError::MemoryLimit`] if the grid exceeds `budget`.
pub fn fourier_surface(
    p: &FourierParams,
    seed: u64,
    budget: &MemoryBudget,
) -> crate::Result<HeightField> {
    p.validate()?;
    let mut h = HeightField::try_filled([p.n, p.n], 0.0, budget)?.with_spacing([p.spacing; 2])?;
    let (n, m) = (p.n, p.modes as i64);
    let tau = std::f64::consts::TAU;
    let l = n as f64 * p.spacing;
    let mut rng = seeded(seed);
    // amp[(row n)][(col m + M)] with its phase; rows n = 0..=M, cols m = −M..=M.
    let width = (2 * m + 1) as usize;
    let mut coeff = vec![(0.0f64, 0.0f64); width * (m as usize + 1)];
    for j in 0..=m {
        for i in -m..=m {
            if j == 0 && i <= 0 {
                continue;
            }
            let q = tau * ((i * i + j * j) as f64).sqrt() / l;
            let amp = q.powf(-(1.0 + p.hurst));
            let phase = rng.random::<f64>() * tau;
            coeff[j as usize * width + (i + m) as usize] = (amp * phase.cos(), amp * phase.sin());
        }
    }
    // e^{2πi·k/n} for k = 0..n: every phase factor below is an exact table entry,
    // since e^{i q_m x} = e^{2πi·(m·x mod n)/n} on the grid.
    let roots: Vec<(f64, f64)> = (0..n)
        .map(|k| {
            let (sn, cs) = (tau * k as f64 / n as f64).sin_cos();
            (cs, sn)
        })
        .collect();
    let root = |k: i64| roots[k.rem_euclid(n as i64) as usize];
    // S_n(x) for every column x: complex row sums over m.
    let rows = m as usize + 1;
    let mut s = vec![(0.0f64, 0.0f64); rows * n];
    for x in 0..n as i64 {
        for (jn, row) in coeff.chunks_exact(width).enumerate() {
            let (mut re, mut im) = (0.0, 0.0);
            for (k, &(cr, ci)) in row.iter().enumerate() {
                let (cs, sn) = root((k as i64 - m) * x);
                re += cr * cs - ci * sn;
                im += cr * sn + ci * cs;
            }
            s[jn * n + x as usize] = (re, im);
        }
    }
    for y in 0..n {
        for x in 0..n {
            let z: f64 = (0..rows)
                .map(|j| {
                    let (cs, sn) = root((j * y) as i64);
                    let (sr, si) = s[j * n + x];
                    cs * sr - sn * si
                })
                .sum();
            *h.get_mut(x, y) = z;
        }
    }
    p.normalise(&mut h);
    Ok(h)
}

/// The reference surface every benchmark measures: `n × n` samples of H = 0.8,
/// `n/8` modes per axis, rms 0.05, spacing 1/n, seed 7.
///
/// # Errors
/// As [`fourier_surface`].
pub fn benchmark_surface(n: usize, budget: &MemoryBudget) -> crate::Result<HeightField> {
    let p = FourierParams {
        n,
        hurst: 0.8,
        modes: (n / 8).max(1),
        rms: 0.05,
        spacing: 1.0 / n as f64,
    };
    fourier_surface(&p, 7, budget)
}

/// [`benchmark_surface`] triangulated with alternating diagonals, with normals:
/// 2(n − 1)² triangles.
///
/// # Errors
/// As [`fourier_surface`].
pub fn benchmark_mesh(n: usize, budget: &MemoryBudget) -> crate::Result<crate::TriMesh> {
    let h = benchmark_surface(n, budget)?;
    Ok(h.to_trimesh(crate::Diagonal::Alternating)?
        .with_computed_normals())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> FourierParams {
        FourierParams {
            n: 32,
            hurst: 0.7,
            modes: 8,
            rms: 2.0,
            spacing: 0.5,
        }
    }

    /// |DFT| of the surface at integer mode (i, j), computed directly.
    fn dft(h: &HeightField, i: f64, j: f64) -> f64 {
        let n = h.nx();
        let (mut re, mut im) = (0.0, 0.0);
        for y in 0..n {
            for x in 0..n {
                let t = -std::f64::consts::TAU * (i * x as f64 + j * y as f64) / n as f64;
                re += h.get(x, y) * t.cos();
                im += h.get(x, y) * t.sin();
            }
        }
        (re * re + im * im).sqrt()
    }

    #[test]
    fn spectrum_follows_the_power_law_exactly() {
        // The DFT at mode (i, j) is N²/2 · A(q) · scale, so amplitude ratios must be
        // (|q|/|q₀|)^−(1+H) to rounding error, and zero above q_max.
        let h = fourier_surface(&params(), 3, &MemoryBudget::unlimited()).unwrap();
        let base = dft(&h, 1.0, 0.0);
        for (i, j) in [(2.0, 0.0), (3.0, 4.0), (0.0, 7.0), (-5.0, 2.0), (8.0, 8.0)] {
            let q: f64 = i * i + j * j;
            let want = q.sqrt().powf(-1.7);
            assert!(
                (dft(&h, i, j) / base - want).abs() < 1e-9,
                "mode ({i}, {j})"
            );
        }
        assert!(dft(&h, 9.0, 0.0) < 1e-9 * base, "no modes above q_max");
        assert!(dft(&h, 0.0, 0.0) < 1e-9 * base, "zero mean");
    }

    #[test]
    fn rms_determinism_and_validation() {
        let p = params();
        let a = fourier_surface(&p, 3, &MemoryBudget::unlimited()).unwrap();
        let mean = a.mean();
        let rms =
            (a.data().iter().map(|z| (z - mean).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
        assert!(mean.abs() < 1e-12 && (rms - 2.0).abs() < 1e-12);
        assert_eq!(
            a,
            fourier_surface(&p, 3, &MemoryBudget::unlimited()).unwrap()
        );
        assert_ne!(
            a,
            fourier_surface(&p, 4, &MemoryBudget::unlimited()).unwrap()
        );
        for bad in [
            FourierParams {
                hurst: 1.5,
                ..p.clone()
            },
            FourierParams {
                hurst: f64::NAN,
                ..p.clone()
            },
            FourierParams {
                modes: 17,
                ..p.clone()
            },
            FourierParams { n: 1, ..p.clone() },
            FourierParams {
                rms: -1.0,
                ..p.clone()
            },
            FourierParams {
                spacing: 0.0,
                ..p.clone()
            },
        ] {
            assert!(
                fourier_surface(&bad, 1, &MemoryBudget::unlimited()).is_err(),
                "{bad:?}"
            );
        }
    }
}
