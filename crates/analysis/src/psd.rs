//! Power spectral density and the Hurst exponent from its slope.
//!
//! # Conventions (those of SurfaceTopography; Jacobs, Junge & Pastewka 2017,
//! *Surf. Topogr.: Metrol. Prop.* 5, 013001)
//! For a field of N = nx·ny samples on area A = nx·dx · ny·dy, with the discrete
//! Fourier transform ĥ(q) = Σ_r h(r) e^(−i q·r) at q = 2π(m/(nx dx), n/(ny dy)):
//!
//! C(q) = A / N² · |ĥ(q)|²,  so that  Σ_q C(q) / A = ⟨h²⟩  (Parseval; = ∫ C d²q/(2π)²).
//!
//! The radially averaged PSD is the mean of C over the wavevectors whose length
//! falls in each of a set of logarithmically spaced bins between q_min = 2π/L
//! (L the longer side) and the Nyquist wavenumber q_N = π/dx.
//!
//! For a self-affine surface C(q) ∝ q^(−2(1+H)), so H = −slope/2 − 1 from a
//! least-squares line through (log q, log C) in the fit window, whose default is
//! [2 q_min, q_N]; the PSD fractal dimension is D = 3 − H.

use asperity_core::HeightField;
use rayon::prelude::*;
use rustfft::{FftPlanner, num_complex::Complex};
use serde::Serialize;

use crate::AnalysisError;

/// In-place 2-D FFT (rows, then columns) of an `nx × ny` grid, x fastest.
/// Rows are transformed in parallel; columns through a blocked transpose, so
/// they too are contiguous rows. Each line is transformed alone: the result is
/// the same bytes at any thread count.
pub(crate) fn fft2(data: &mut [Complex<f64>], nx: usize, ny: usize, inverse: bool) {
    let mut planner = FftPlanner::new();
    let mut plan = |n: usize| {
        if inverse {
            planner.plan_fft_inverse(n)
        } else {
            planner.plan_fft_forward(n)
        }
    };
    let (fx, fy) = (plan(nx), plan(ny));
    let lines =
        |buf: &mut [Complex<f64>], len: usize, f: &std::sync::Arc<dyn rustfft::Fft<f64>>| {
            buf.par_chunks_exact_mut(len).for_each_init(
                || vec![Complex::new(0.0, 0.0); f.get_inplace_scratch_len()],
                |scratch, line| f.process_with_scratch(line, scratch),
            );
        };
    lines(data, nx, &fx);
    let mut t = vec![Complex::new(0.0, 0.0); nx * ny];
    transpose(data, &mut t, nx, ny);
    lines(&mut t, ny, &fy);
    transpose(&t, data, ny, nx);
}

/// `dst[j + ny·i] = src[i + nx·j]` in 32×32 tiles, parallel over tile rows of `dst`.
fn transpose(src: &[Complex<f64>], dst: &mut [Complex<f64>], nx: usize, ny: usize) {
    const B: usize = 32;
    dst.par_chunks_mut(ny * B)
        .enumerate()
        .for_each(|(bi, out)| {
            let i0 = bi * B;
            let rows = out.len() / ny;
            for j0 in (0..ny).step_by(B) {
                for di in 0..rows {
                    let i = i0 + di;
                    for j in j0..(j0 + B).min(ny) {
                        out[j + ny * di] = src[i + nx * j];
                    }
                }
            }
        });
}

/// The 2-D PSD on the FFT grid (x fastest, zero frequency at index 0).
pub fn psd_2d(h: &HeightField) -> Vec<f64> {
    let [nx, ny] = h.dims();
    let [dx, dy] = h.spacing();
    let mut data: Vec<Complex<f64>> = h.data().iter().map(|&v| Complex::new(v, 0.0)).collect();
    fft2(&mut data, nx, ny, false);
    let n = (nx * ny) as f64;
    let area = nx as f64 * dx * ny as f64 * dy;
    data.iter().map(|c| area / (n * n) * c.norm_sqr()).collect()
}

/// A radially averaged, log-binned PSD.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RadialPsd {
    /// Bin wavenumbers (mean |q| of the modes in each non-empty bin).
    pub q: Vec<f64>,
    /// Mean C(q) in each bin.
    pub c: Vec<f64>,
}

/// Radial average of [`psd_2d`] over `bins` log-spaced bins in [2π/L, π/dx].
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN heights, fewer than 4 samples a side, or 0 bins.
pub fn radial_psd(h: &HeightField, bins: usize) -> Result<RadialPsd, AnalysisError> {
    h.validate()?;
    let [nx, ny] = h.dims();
    if nx < 4 || ny < 4 || bins == 0 {
        return Err(AnalysisError::BadInput(format!(
            "need at least 4×4 samples and one bin for a PSD, got {nx}×{ny}"
        )));
    }
    let c2 = psd_2d(h);
    let [dx, dy] = h.spacing();
    let (lx, ly) = (nx as f64 * dx, ny as f64 * dy);
    let q_min = std::f64::consts::TAU / lx.max(ly);
    let q_max = std::f64::consts::PI / dx.max(dy);
    let edges: Vec<f64> = (0..=bins)
        .map(|k| q_min * (q_max / q_min).powf(k as f64 / bins as f64))
        .collect();
    let (mut sq, mut sc, mut cnt) = (vec![0.0; bins], vec![0.0; bins], vec![0usize; bins]);
    let wrap = |k: usize, n: usize| {
        if k <= n / 2 {
            k as f64
        } else {
            k as f64 - n as f64
        }
    };
    for j in 0..ny {
        for i in 0..nx {
            let qx = std::f64::consts::TAU * wrap(i, nx) / lx;
            let qy = std::f64::consts::TAU * wrap(j, ny) / ly;
            let q = (qx * qx + qy * qy).sqrt();
            if q < edges[0] * (1.0 - 1e-12) || q > edges[bins] * (1.0 + 1e-12) {
                continue;
            }
            let b = edges
                .partition_point(|&e| e <= q)
                .saturating_sub(1)
                .min(bins - 1);
            sq[b] += q;
            sc[b] += c2[i + nx * j];
            cnt[b] += 1;
        }
    }
    let (mut q, mut c) = (Vec::new(), Vec::new());
    for b in 0..bins {
        if cnt[b] > 0 {
            q.push(sq[b] / cnt[b] as f64);
            c.push(sc[b] / cnt[b] as f64);
        }
    }
    Ok(RadialPsd { q, c })
}

/// A straight-line fit in log–log coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LogFit {
    /// Slope of log y against log x.
    pub slope: f64,
    /// Intercept (natural logarithms).
    pub intercept: f64,
    /// Coefficient of determination.
    pub r2: f64,
    /// The x range used.
    pub range: [f64; 2],
    /// Points used.
    pub points: usize,
}

/// Least-squares line through (ln x, ln y) for x in `range` (positive values only).
///
/// # Errors
/// [`AnalysisError::BadInput`] when fewer than 3 points fall in the range.
pub fn log_fit(x: &[f64], y: &[f64], range: [f64; 2]) -> Result<LogFit, AnalysisError> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| {
            **a >= range[0] * (1.0 - 1e-12)
                && **a <= range[1] * (1.0 + 1e-12)
                && **a > 0.0
                && **b > 0.0
        })
        .map(|(a, b)| (a.ln(), b.ln()))
        .collect();
    if pts.len() < 3 {
        return Err(AnalysisError::BadInput(format!(
            "only {} points in the fit window [{}, {}]; widen it or use a larger field",
            pts.len(),
            range[0],
            range[1]
        )));
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
    let slope = sxy / sxx;
    let r2 = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    Ok(LogFit {
        slope,
        intercept: my - slope * mx,
        r2,
        range,
        points: pts.len(),
    })
}

/// Hurst exponent from the radially averaged PSD.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Hurst {
    /// H = −slope/2 − 1.
    pub hurst: f64,
    /// D = 3 − H.
    pub fractal_dimension: f64,
    /// The fit behind it.
    pub fit: LogFit,
}

/// H from the PSD slope in `window` (default [2·q_min, q_N]).
///
/// # Errors
/// As [`radial_psd`] and [`log_fit`].
pub fn hurst(
    psd: &RadialPsd,
    h: &HeightField,
    window: Option<[f64; 2]>,
) -> Result<Hurst, AnalysisError> {
    let [nx, ny] = h.dims();
    let [dx, dy] = h.spacing();
    let q_min = std::f64::consts::TAU / (nx as f64 * dx).max(ny as f64 * dy);
    let q_n = std::f64::consts::PI / dx.max(dy);
    let fit = log_fit(&psd.q, &psd.c, window.unwrap_or([2.0 * q_min, q_n]))?;
    let hurst = -fit.slope / 2.0 - 1.0;
    Ok(Hurst {
        hurst,
        fractal_dimension: 3.0 - hurst,
        fit,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parseval_and_a_single_mode() {
        let (nx, ny) = (32, 16);
        let h = HeightField::from_vec(
            [nx, ny],
            (0..nx * ny)
                .map(|k| ((k * 7919) % 13) as f64 - 6.0)
                .collect(),
        )
        .unwrap()
        .with_spacing([0.5, 0.25])
        .unwrap();
        let c = psd_2d(&h);
        let area = nx as f64 * 0.5 * ny as f64 * 0.25;
        let ms = h.data().iter().map(|v| v * v).sum::<f64>() / (nx * ny) as f64;
        assert!((c.iter().sum::<f64>() / area - ms).abs() < 1e-9 * ms);
        // cos(2π·3x/nx): all power at m = ±3, n = 0, each half of ⟨h²⟩ = 1/2.
        let w = HeightField::from_vec(
            [nx, ny],
            (0..nx * ny)
                .map(|k| (std::f64::consts::TAU * 3.0 * (k % nx) as f64 / nx as f64).cos())
                .collect(),
        )
        .unwrap();
        let c = psd_2d(&w);
        let a = (nx * ny) as f64;
        assert!((c[3] / a - 0.25).abs() < 1e-12 && (c[nx - 3] / a - 0.25).abs() < 1e-12);
        assert!(
            c.iter()
                .enumerate()
                .filter(|(k, _)| *k != 3 && *k != nx - 3)
                .all(|(_, v)| *v < 1e-20)
        );
    }

    #[test]
    fn fit_recovers_a_power_law() {
        let q: Vec<f64> = (1..50).map(|k| k as f64 * 0.1).collect();
        let c: Vec<f64> = q.iter().map(|v| 3.0 * v.powf(-3.6)).collect();
        let f = log_fit(&q, &c, [0.0, 10.0]).unwrap();
        assert!(
            (f.slope + 3.6).abs() < 1e-12
                && (f.r2 - 1.0).abs() < 1e-12
                && (f.intercept - 3f64.ln()).abs() < 1e-12
        );
        assert!(
            log_fit(&q, &c, [100.0, 200.0])
                .unwrap_err()
                .to_string()
                .contains("only 0 points")
        );
    }
}
