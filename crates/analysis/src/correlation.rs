//! Autocorrelation, height–height correlation, and the ISO 25178 spatial
//! parameters Sal and Str.
//!
//! - ACF R(τ) = ⟨z(r) z(r + τ)⟩ of the levelled field, computed circularly with
//!   FFTs (Wiener–Khinchin: R = IFFT(|FFT z|²)/N) and normalised by R(0).
//! - Sal (ISO 25178-2 autocorrelation length): the shortest horizontal distance,
//!   over all directions, at which the normalised ACF decays to s = 0.2.
//! - Str (texture aspect ratio): shortest ÷ longest such distance over the
//!   directions (1 isotropic, → 0 strongly directional). Directions whose ACF does
//!   not fall to 0.2 within half the field count as half the field's extent, and
//!   the result says so.
//! - HHCF H(τ) = ⟨(z(x + τ) − z(x))²⟩ along x (rows), directly, for τ = 1…nx/2
//!   samples; for a self-affine surface H(τ) ∝ τ^(2H).

use asperity_core::HeightField;
use rayon::prelude::*;
use rustfft::num_complex::Complex;

use crate::spectrum::{self, PowerSpectrum};
use serde::Serialize;

use crate::AnalysisError;

/// Normalised circular autocorrelation (R(0) = 1), on the grid of lags (x fastest,
/// lag 0 at index 0, negative lags wrapped).
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN or constant fields.
pub fn acf(h: &HeightField) -> Result<Vec<f64>, AnalysisError> {
    h.validate()?;
    acf_from_spectrum(&PowerSpectrum::of(h, None))
}

/// [`acf`] of the field whose spectrum is `s` (its mean, the zero mode, left out).
///
/// # Errors
/// [`AnalysisError::BadInput`] for a constant field.
pub fn acf_from_spectrum(s: &PowerSpectrum) -> Result<Vec<f64>, AnalysisError> {
    let [nx, ny] = s.dims;
    let power = s.power.par_iter().map(|&p| Complex::new(p, 0.0)).collect();
    let (mut r, r0) = wiener_khinchin(power, nx, ny)?;
    r.par_iter_mut().for_each(|c| *c /= r0);
    Ok(r)
}

/// The autocorrelation sums of an `nx × ny` grid from its power `|Z|²` (as
/// complex numbers, the half spectrum), the zero mode left out, by the
/// Wiener–Khinchin theorem: the inverse transform and its value at lag 0.
///
/// # Errors
/// [`AnalysisError::BadInput`] for a constant field (no power off the mean).
fn wiener_khinchin(
    mut power: Vec<Complex<f64>>,
    nx: usize,
    ny: usize,
) -> Result<(Vec<f64>, f64), AnalysisError> {
    power[0] = Complex::new(0.0, 0.0);
    let r = spectrum::inverse(power, nx, ny);
    let r0 = r[0];
    if r0.abs() < 1e-300 {
        return Err(AnalysisError::BadInput(
            "the height field is constant: its autocorrelation is undefined".into(),
        ));
    }
    Ok((r, r0))
}

/// Sal and Str.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Spatial {
    /// Autocorrelation length (s = 0.2).
    pub Sal: f64,
    /// Texture aspect ratio.
    pub Str: f64,
    /// Whether some direction never decayed to 0.2 within half the field.
    pub capped: bool,
}

/// Sal and Str from the ACF, scanning 360 directions over 180°.
///
/// # Errors
/// As [`acf`].
pub fn spatial(h: &HeightField) -> Result<Spatial, AnalysisError> {
    h.validate()?;
    spatial_from_spectrum(&PowerSpectrum::of(h, None))
}

/// [`spatial`] of the field whose (unwindowed) spectrum is `s`.
///
/// # Errors
/// As [`acf_from_spectrum`].
pub fn spatial_from_spectrum(s: &PowerSpectrum) -> Result<Spatial, AnalysisError> {
    let r = acf_from_spectrum(s)?;
    let [nx, ny] = s.dims;
    let [dx, dy] = s.spacing;
    let half = 0.5 * (nx as f64 * dx).min(ny as f64 * dy);
    Ok(decay_lengths(&r, s.dims, s.spacing, half))
}

/// Sal and Str of a field that does not wrap around (measured data, crops):
/// the ACF is the linear (non-circular) one, each lag's sum divided by the
/// number of overlapping pairs, (nx − |τx|)(ny − |τy|) — the unbiased
/// estimator of ISO 25178-2's integral over the overlap of the field with its
/// shifted copy (surfalize's). It is computed by FFT of the field padded with
/// zeros by half its size and a little more (to a fast FFT length), so no lag
/// the search reads (at most half the field) wraps. A circular ACF on such
/// data would join opposite edges and shorten Sal.
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN or constant fields.
pub fn spatial_open(h: &HeightField) -> Result<Spatial, AnalysisError> {
    let (r, padded) = linear_acf(h)?;
    let [nx, ny] = h.dims();
    let [dx, dy] = h.spacing();
    let half = 0.5 * (nx as f64 * dx).min(ny as f64 * dy);
    Ok(decay_lengths(&r, padded, h.spacing(), half))
}

/// The normalised unbiased linear ACF of `h` (see [`spatial_open`]) on the
/// padded grid of lags it returns (lags up to half the field in each
/// direction are exact; negative lags wrap).
fn linear_acf(h: &HeightField) -> Result<(Vec<f64>, [usize; 2]), AnalysisError> {
    h.validate()?;
    let [nx, ny] = h.dims();
    let pad = |n: usize| crate::spectrum::smooth_len(n + n / 2 + 2);
    let [px, py] = [pad(nx), pad(ny)];
    let mean = h.mean();
    let mut padded = vec![0.0; px * py];
    padded
        .par_chunks_mut(px)
        .take(ny)
        .enumerate()
        .for_each(|(j, line)| {
            for (p, z) in line.iter_mut().zip(h.row(j)) {
                *p = z - mean;
            }
        });
    // |Z|² in place of Z (no power-spectrum struct and no second copy)
    let mut power = spectrum::forward(&padded, None, px, py);
    drop(padded);
    power
        .par_iter_mut()
        .for_each(|c| *c = Complex::new(c.norm_sqr(), 0.0));
    let (mut r, r0) = wiener_khinchin(power, px, py)?;
    // each lag's sum over its overlapping pairs; lags past the field have none
    let pairs = |lag: usize, p: usize, n: usize| {
        let lag = lag.min(p - lag);
        n.saturating_sub(lag) as f64
    };
    r.par_iter_mut().enumerate().for_each(|(k, v)| {
        let (i, j) = (k % px, k / px);
        let overlap = pairs(i, px, nx) * pairs(j, py, ny);
        *v = if overlap > 0.0 {
            *v / r0 * (nx * ny) as f64 / overlap
        } else {
            0.0
        };
    });
    Ok((r, [px, py]))
}

/// The shortest and longest distances, over 360 directions, at which the
/// normalised ACF `r` (lags on a `dims` grid, negative lags wrapped) first
/// falls to s = 0.2, searched out to `half`.
fn decay_lengths(r: &[f64], [nx, ny]: [usize; 2], [dx, dy]: [f64; 2], half: f64) -> Spatial {
    let at = |x: f64, y: f64| {
        // Bilinear lookup of the periodic ACF at lag (x, y) in samples.
        let (fx, fy) = (x.floor(), y.floor());
        let (tx, ty) = (x - fx, y - fy);
        let g = |i: f64, j: f64| {
            r[(i.rem_euclid(nx as f64) as usize) + nx * (j.rem_euclid(ny as f64) as usize)]
        };
        (g(fx, fy) * (1.0 - tx) + g(fx + 1.0, fy) * tx) * (1.0 - ty)
            + (g(fx, fy + 1.0) * (1.0 - tx) + g(fx + 1.0, fy + 1.0) * tx) * ty
    };
    let step = 0.25 * dx.min(dy);
    let mut capped = false;
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for k in 0..360 {
        let th = std::f64::consts::PI * k as f64 / 360.0;
        let (c, s) = (th.cos(), th.sin());
        let mut d = 0.0;
        let mut prev = (0.0, 1.0);
        let found = loop {
            d += step;
            if d > half {
                break None;
            }
            let v = at(d * c / dx, d * s / dy);
            if v <= 0.2 {
                // Linear interpolation between the last two steps.
                let t = (prev.1 - 0.2) / (prev.1 - v);
                break Some(prev.0 + t * (d - prev.0));
            }
            prev = (d, v);
        };
        let d = found.unwrap_or_else(|| {
            capped = true;
            half
        });
        lo = lo.min(d);
        hi = hi.max(d);
    }
    Spatial {
        Sal: lo,
        Str: lo / hi,
        capped,
    }
}

/// Height–height correlation along x: (lag in length units, H(τ)) at every lag
/// τ = 1…nx/2 samples when nx/2 ≤ 64, otherwise at 64 log-spaced integer lags in
/// that range (each lag costs a pass over the field, so all nx/2 lags would be
/// O(nx²·ny)). Lags are evaluated in parallel; each sum is sequential, so the
/// result is the same at any thread count.
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN heights or fewer than 4 columns.
pub fn hhcf_x(h: &HeightField) -> Result<Vec<(f64, f64)>, AnalysisError> {
    use rayon::prelude::*;
    h.validate()?;
    let [nx, ny] = h.dims();
    if nx < 4 {
        return Err(AnalysisError::BadInput(format!(
            "need at least 4 columns for a height-height correlation, got {nx}"
        )));
    }
    let dx = h.spacing()[0];
    let max = nx / 2;
    const LAGS: usize = 64;
    let mut lags: Vec<usize> = if max <= LAGS {
        (1..=max).collect()
    } else {
        (0..LAGS)
            .map(|k| (max as f64).powf(k as f64 / (LAGS - 1) as f64).round() as usize)
            .collect()
    };
    lags.dedup();
    Ok(lags
        .into_par_iter()
        .map(|t| {
            let mut s = 0.0;
            for j in 0..ny {
                let row = h.row(j);
                s += row
                    .windows(t + 1)
                    .map(|w| (w[t] - w[0]).powi(2))
                    .sum::<f64>();
            }
            (t as f64 * dx, s / ((nx - t) * ny) as f64)
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn acf_of_a_cosine_is_a_cosine() {
        let n = 64;
        let tau = std::f64::consts::TAU;
        let h = HeightField::from_vec(
            [n, n],
            (0..n * n)
                .map(|k| (tau * 3.0 * (k % n) as f64 / n as f64).cos())
                .collect(),
        )
        .unwrap();
        let r = acf(&h).unwrap();
        for lag in 0..n {
            assert!((r[lag] - (tau * 3.0 * lag as f64 / n as f64).cos()).abs() < 1e-12);
            assert!((r[lag * n] - 1.0).abs() < 1e-12, "constant along y");
        }
    }

    #[test]
    fn sal_and_str_of_two_crossed_sines() {
        // ACF(τ, θ) = (cos(kτ cos θ) + cos(kτ sin θ)) / 2; find its 0.2 crossing per
        // direction by brute force and compare.
        let n = 128;
        let k = std::f64::consts::TAU * 4.0 / n as f64;
        let h = HeightField::from_vec(
            [n, n],
            (0..n * n)
                .map(|q| (k * (q % n) as f64).sin() + (k * (q / n) as f64).sin())
                .collect(),
        )
        .unwrap();
        let s = spatial(&h).unwrap();
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for a in 0..360 {
            let th = std::f64::consts::PI * a as f64 / 360.0;
            let mut t = 0.0;
            while ((k * t * th.cos()).cos() + (k * t * th.sin()).cos()) / 2.0 > 0.2 {
                t += 1e-4;
            }
            lo = lo.min(t);
            hi = hi.max(t);
        }
        assert!(!s.capped);
        assert!((s.Sal - lo).abs() < 0.02 * lo, "Sal {} vs {lo}", s.Sal);
        assert!(
            (s.Str - lo / hi).abs() < 0.02,
            "Str {} vs {}",
            s.Str,
            lo / hi
        );
    }

    #[test]
    fn hhcf_of_a_ramp_is_the_squared_lag() {
        let h = HeightField::from_vec([16, 3], (0..48).map(|k| 0.5 * (k % 16) as f64).collect())
            .unwrap();
        for (tau, v) in hhcf_x(&h).unwrap() {
            assert!((v - 0.25 * tau * tau).abs() < 1e-12);
        }
    }
}
