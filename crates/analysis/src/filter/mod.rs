//! ISO 16610 filtering: the Gaussian filters that separate a measured surface
//! into the scale-limited surface and what is removed (ISO 25178-2 §3.1.4–3.1.9,
//! ISO 16610-1's S-, L- and F-operators).
//!
//! | Filter | Standard | Here |
//! | --- | --- | --- |
//! | areal Gaussian, S- and L-filter | ISO 16610-61 (weighting function s(x, y) = 1/(α²λc²) · exp(−π(x² + y²)/(αλc)²), α = √(ln 2/π), Eq. 1; amplitude transmission exp(−π(αλc/λ)²), 50 % at λc) | [`gaussian`], degree 0 or 1 |
//! | profile Gaussian | ISO 16610-21 (the same function in one variable) | [`gaussian`] on a profile (one row) |
//! | end effects | ISO 16610-28 (regression near the border) | degree 1 keeps planes to the border |
//! | second-order regression Gaussian | ISO 16610-31 (profiles); its areal form | [`gaussian`], degree 2 |
//! | robust Gaussian regression | ISO 16610-71 (Tukey's biweight, c = 4.4478 · median \|r\|) | [`robust_gaussian`] |
//!
//! All of them are one computation, the Gaussian regression filter of
//! [`regression`]: a local polynomial fitted with the Gaussian weights times a
//! per-point weight, 0 at a missing point (so fields with missing points are
//! filtered by normalised convolution, without filling them first).
//!
//! **The scale-limited surface** ([`scale_limited`], ISO 25178-2 §3.1.9):
//! after the F-operator (form removal: [`crate::level`]), the S-filter at λs
//! keeps the mean surface of the wavelengths above λs (the S-F surface), and
//! the L-filter at λc removes the mean surface of the S-F surface (the
//! waviness), leaving the S-L surface. Nesting indices are chosen from the
//! series of ISO 25178-3 Table 1 (… 1, 2, 2.5, 5, 8, 10 …) by
//! [`default_cutoffs`] when not given: λc the largest value at most a fifth of
//! the shorter side, λs the smallest value at least three sampling intervals.
//!
//! The kernel is truncated at ±λc (where the weighting function has fallen to
//! 6.5·10⁻⁷ of its peak). On periodic data the lines wrap.

mod convolve;
pub mod regression;

use asperity_core::HeightField;
use rayon::prelude::*;
use serde::Serialize;

use crate::AnalysisError;
pub use regression::ALPHA;
use regression::Regression;

/// The Gaussian regression filter's degree when none is named: 1, the
/// ISO 16610-61 Gaussian inside and a plane-keeping end effect at the border.
pub const DEFAULT_ORDER: usize = 1;

/// Tukey's biweight constant of ISO 16610-71: c = 4.4478 · median |r|
/// (4.4478 = 3 / Φ⁻¹(0.75): three standard deviations of a normal residual).
pub const BIWEIGHT_C: f64 = 4.4478;

/// The robust filter stops when the mean surface moves, in rms over the
/// measured points, by less than this fraction of the surface's rms height, or
/// after [`ROBUST_MAX_ITERATIONS`].
pub const ROBUST_TOLERANCE: f64 = 1e-5;

/// At most this many robust iterations.
pub const ROBUST_MAX_ITERATIONS: usize = 50;

/// Eight-byte fields the filter of a `dims` grid holds at once at degree
/// `order`, with per-point weights or not: the memory estimate is this times
/// 8 bytes times the points.
pub fn fields_held(order: usize, weighted: bool) -> usize {
    let axis = order + 1;
    4 + axis + if weighted { 2 * order + 2 } else { 0 }
}

fn check(h: &HeightField, cutoff: f64, order: usize) -> Result<(), AnalysisError> {
    h.validate_measured()?;
    if !(cutoff.is_finite() && cutoff > 0.0) {
        return Err(AnalysisError::BadInput(format!(
            "the filter's cut-off must be a positive length, got {cutoff}"
        )));
    }
    if order > 2 {
        return Err(AnalysisError::BadInput(format!(
            "the Gaussian regression filter's degree is 0, 1 or 2, got {order}"
        )));
    }
    Ok(())
}

fn regression(h: &HeightField, cutoff: f64, order: usize, periodic: bool) -> Regression {
    Regression {
        dims: h.dims(),
        spacing: h.spacing(),
        cutoff,
        order,
        wrap: periodic,
    }
}

/// The mask of measured points as weights (1 measured, 0 missing), and the
/// heights with missing points read as 0.
fn measured(h: &HeightField) -> (Vec<f64>, Option<Vec<f64>>) {
    if !h.has_missing() {
        return (h.data().to_vec(), None);
    }
    let w = h
        .data()
        .par_iter()
        .map(|z| f64::from(u8::from(z.is_finite())))
        .collect();
    let z = h
        .data()
        .par_iter()
        .map(|z| if z.is_finite() { *z } else { 0.0 })
        .collect();
    (z, Some(w))
}

/// The Gaussian mean surface of `h` at cut-off `cutoff` (in the field's
/// length unit): the low-pass part, which keeps wavelengths longer than the
/// cut-off (ISO 16610-61; a profile: ISO 16610-21). `order` is the regression
/// degree (0, 1 — [`DEFAULT_ORDER`] — or 2, see [`regression`]). Missing points
/// carry no weight; the mean surface is defined over them too, but NaN where
/// no measured point lies within λc.
///
/// # Errors
/// [`AnalysisError`] for a cut-off that is not a positive length, a degree
/// above 2, or an infinite height.
pub fn gaussian(
    h: &HeightField,
    cutoff: f64,
    order: usize,
    periodic: bool,
) -> Result<HeightField, AnalysisError> {
    check(h, cutoff, order)?;
    let (z, w) = measured(h);
    let mean = regression(h, cutoff, order, periodic).mean_surface(&z, w.as_deref());
    Ok(h.with_data(mean)?)
}

/// [`gaussian`] made robust against outliers (deep valleys, spikes) by
/// ISO 16610-71's iteration: residuals r = z − mean, Tukey's biweight
/// (1 − (r/c)²)² for |r| < c and 0 beyond, c = [`BIWEIGHT_C`] · median |r|,
/// until the mean surface moves by less than [`ROBUST_TOLERANCE`] (see there).
/// Returns the mean surface and the iterations taken.
///
/// # Errors
/// As [`gaussian`].
pub fn robust_gaussian(
    h: &HeightField,
    cutoff: f64,
    order: usize,
    periodic: bool,
) -> Result<(HeightField, usize), AnalysisError> {
    check(h, cutoff, order)?;
    let (z, mask) = measured(h);
    let mask = mask.unwrap_or_else(|| vec![1.0; z.len()]);
    let filter = regression(h, cutoff, order, periodic);
    let mean_z = rms_over(&z, &mask, |z| z).1;
    let tolerance = ROBUST_TOLERANCE * rms_over(&z, &mask, |z| z - mean_z).0;
    let mut mean = filter.mean_surface(&z, Some(&mask));
    let mut iterations = 1;
    while iterations < ROBUST_MAX_ITERATIONS {
        let Some(weights) = biweights(&z, &mean, &mask) else {
            break;
        };
        let next = filter.mean_surface(&z, Some(&weights));
        iterations += 1;
        let change: Vec<f64> = next.iter().zip(&mean).map(|(a, b)| a - b).collect();
        mean = next;
        if rms_over(&change, &mask, |d| d).0 <= tolerance {
            break;
        }
    }
    Ok((h.with_data(mean)?, iterations))
}

/// The rms and the mean of `f(v)` over the points of weight > 0 (NaN values
/// left out).
fn rms_over(v: &[f64], mask: &[f64], f: impl Fn(f64) -> f64) -> (f64, f64) {
    let (mut n, mut sum, mut squares) = (0.0, 0.0, 0.0);
    for (x, w) in v.iter().zip(mask) {
        let y = f(*x);
        if *w > 0.0 && y.is_finite() {
            n += 1.0;
            sum += y;
            squares += y * y;
        }
    }
    let n = f64::max(n, 1.0);
    ((squares / n).sqrt(), sum / n)
}

/// Tukey's biweight of each measured point's residual from `mean` (0 at a
/// missing point), c = [`BIWEIGHT_C`] · median |r|; `None` when the residuals
/// vanish (nothing left to reweight).
fn biweights(z: &[f64], mean: &[f64], mask: &[f64]) -> Option<Vec<f64>> {
    let residual: Vec<f64> = z
        .par_iter()
        .zip(mean)
        .zip(mask)
        .map(|((z, m), w)| if *w > 0.0 { (z - m).abs() } else { f64::NAN })
        .collect();
    let mut measured: Vec<f64> = residual.iter().copied().filter(|r| r.is_finite()).collect();
    if measured.is_empty() {
        return None;
    }
    let mid = measured.len() / 2;
    let c = BIWEIGHT_C * *measured.select_nth_unstable_by(mid, f64::total_cmp).1;
    if c.is_nan() || c <= 0.0 {
        return None;
    }
    Some(
        residual
            .par_iter()
            .map(|r| {
                let t = r / c;
                if t < 1.0 { (1.0 - t * t).powi(2) } else { 0.0 }
            })
            .collect(),
    )
}

/// The scale-limited surface's specification (ISO 25178-2 §3.1.9).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Specification {
    /// S-filter nesting index λs (removes shorter wavelengths), if any.
    pub lambda_s: Option<f64>,
    /// L-filter nesting index λc (removes longer wavelengths), if any.
    pub lambda_c: Option<f64>,
    /// The L-filter's regression degree (the S-filter's is [`DEFAULT_ORDER`]).
    pub order: usize,
    /// The L-filter robust (ISO 16610-71) rather than linear (ISO 16610-61).
    pub robust: bool,
    /// The data wrap around (a periodic surface).
    pub periodic: bool,
}

impl Specification {
    /// "S-L surface", "S-F surface", "F-L surface" or "primary surface".
    pub fn surface_name(&self) -> &'static str {
        match (self.lambda_s.is_some(), self.lambda_c.is_some()) {
            (true, true) => "S-L surface",
            (true, false) => "S-F surface",
            (false, true) => "F-L surface",
            (false, false) => "primary surface",
        }
    }
}

/// The scale-limited surface and what the filters removed.
#[derive(Clone, Debug)]
pub struct ScaleLimited {
    /// The surface after the S- and L-filters (missing points stay missing).
    pub surface: HeightField,
    /// What the L-filter removed (the waviness), with an L-filter.
    pub waviness: Option<HeightField>,
    /// What the S-filter removed (the short-wavelength noise), with an S-filter.
    pub noise: Option<HeightField>,
    /// Iterations of the robust L-filter (1 for a linear one, 0 without).
    pub iterations: usize,
}

/// Applies the S-filter then the L-filter of `spec` to the (form-removed)
/// surface `h`.
///
/// # Errors
/// [`AnalysisError`] for a nesting index that is not a positive length, λs
/// not below λc, a degree above 2, or an infinite height.
pub fn scale_limited(h: &HeightField, spec: &Specification) -> Result<ScaleLimited, AnalysisError> {
    if let (Some(s), Some(c)) = (spec.lambda_s, spec.lambda_c)
        && s >= c
    {
        return Err(AnalysisError::BadInput(format!(
            "the S-filter's nesting index λs = {s} must be below the L-filter's λc = {c}"
        )));
    }
    let mut surface = h.clone();
    let mut noise = None;
    if let Some(s) = spec.lambda_s {
        let mean = gaussian(&surface, s, DEFAULT_ORDER, spec.periodic)?;
        let mean = h.with_data(keep_missing(h, mean.into_data()))?;
        noise = Some(h.with_data(difference(&surface, &mean))?);
        surface = mean;
    }
    let mut waviness = None;
    let mut iterations = 0;
    if let Some(c) = spec.lambda_c {
        let (mean, n) = if spec.robust {
            robust_gaussian(&surface, c, spec.order, spec.periodic)?
        } else {
            (gaussian(&surface, c, spec.order, spec.periodic)?, 1)
        };
        iterations = n;
        let rough = h.with_data(keep_missing(h, difference(&surface, &mean)))?;
        waviness = Some(mean);
        surface = rough;
    }
    Ok(ScaleLimited {
        surface,
        waviness,
        noise,
        iterations,
    })
}

/// `data` with NaN wherever `from` has a missing point.
fn keep_missing(from: &HeightField, mut data: Vec<f64>) -> Vec<f64> {
    data.par_iter_mut().zip(from.data()).for_each(|(d, z)| {
        if !z.is_finite() {
            *d = f64::NAN
        }
    });
    data
}

/// a − b, point by point (the same grid).
pub fn difference(a: &HeightField, b: &HeightField) -> Vec<f64> {
    a.data()
        .par_iter()
        .zip(b.data())
        .map(|(a, b)| a - b)
        .collect()
}

/// The nesting-index series of ISO 25178-3 Table 1: 1, 2, 2.5, 5, 8 times the
/// powers of ten.
const SERIES: [f64; 5] = [1.0, 2.0, 2.5, 5.0, 8.0];

/// The largest series value ≤ `x` (`up` false) or the smallest ≥ `x` (`up` true).
pub fn series_value(x: f64, up: bool) -> f64 {
    let decade = 10f64.powf(x.log10().floor());
    let candidates = (-1..=1).flat_map(|k| SERIES.map(|m| m * decade * 10f64.powi(k)));
    let pick = candidates.filter(|v| {
        if up {
            *v >= x * (1.0 - 1e-12)
        } else {
            *v <= x * (1.0 + 1e-12)
        }
    });
    if up {
        pick.fold(f64::INFINITY, f64::min)
    } else {
        pick.fold(0.0, f64::max)
    }
}

/// Default nesting indices (λs, λc) for a field: λc the largest series value
/// at most a fifth of the shorter side, λs the smallest at least three
/// sampling intervals (ISO 25178-3's sampling rule), in the field's length unit.
pub fn default_cutoffs(h: &HeightField) -> (f64, f64) {
    let [lx, ly] = h.extent();
    let side = if h.ny() > 1 { lx.min(ly) } else { lx };
    let [dx, dy] = h.spacing();
    let step = if h.ny() > 1 { dx.max(dy) } else { dx };
    (
        series_value(3.0 * step, true),
        series_value(side / 5.0, false),
    )
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    fn field(
        nx: usize,
        ny: usize,
        spacing: [f64; 2],
        mut f: impl FnMut(f64, f64) -> f64,
    ) -> HeightField {
        let mut data = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                data.push(f(i as f64 * spacing[0], j as f64 * spacing[1]));
            }
        }
        HeightField::from_vec([nx, ny], data)
            .unwrap()
            .with_spacing(spacing)
            .unwrap()
    }

    /// Amplitude of the sinusoid of wave vector `k` in `h` over the points whose
    /// distance from every border is at least `margin` (least squares on sin, cos).
    fn amplitude(h: &HeightField, k: [f64; 2], margin: [usize; 2]) -> f64 {
        let [nx, ny] = h.dims();
        let [dx, dy] = h.spacing();
        let (mut ss, mut cc, mut sc, mut zs, mut zc) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for j in margin[1]..ny - margin[1] {
            for i in margin[0]..nx - margin[0] {
                let ph = k[0] * i as f64 * dx + k[1] * j as f64 * dy;
                let (s, c) = ph.sin_cos();
                let z = *h.get(i, j);
                ss += s * s;
                cc += c * c;
                sc += s * c;
                zs += z * s;
                zc += z * c;
            }
        }
        let det = ss * cc - sc * sc;
        let a = (zs * cc - zc * sc) / det;
        let b = (zc * ss - zs * sc) / det;
        a.hypot(b)
    }

    fn iso_transmission(cutoff: f64, wavelength: f64) -> f64 {
        (-PI * (ALPHA * cutoff / wavelength).powi(2)).exp()
    }

    #[test]
    fn profile_transmission_is_the_standards_periodic_and_open() {
        let cutoff = 64.0;
        // periodic: whole periods on 1024 samples
        for ratio in [0.25, 0.5, 1.0, 2.0, 4.0] {
            let lambda = cutoff * ratio;
            let k = 2.0 * PI / lambda;
            let h = field(1024, 1, [1.0, 1.0], |x, _| (k * x + 0.3).sin());
            let mean = gaussian(&h, cutoff, DEFAULT_ORDER, true).unwrap();
            let t = amplitude(&mean, [k, 0.0], [0, 0]);
            let want = iso_transmission(cutoff, lambda);
            assert!(
                (t - want).abs() <= 0.005,
                "periodic λ/λc {ratio}: {t} vs {want}"
            );
        }
        // open: any wavelength, measured a cut-off away from the ends
        let cutoff = 50.0;
        for ratio in [0.25, 0.4, 0.7, 1.0, 1.5, 2.5, 4.0] {
            for order in [0, 1] {
                let lambda = cutoff * ratio;
                let k = 2.0 * PI / lambda;
                let h = field(2000, 1, [1.0, 1.0], |x, _| (k * x + 1.1).sin());
                let mean = gaussian(&h, cutoff, order, false).unwrap();
                let t = amplitude(&mean, [k, 0.0], [50, 0]);
                let want = iso_transmission(cutoff, lambda);
                assert!(
                    (t - want).abs() <= 0.005,
                    "open λ/λc {ratio}, degree {order}: {t} vs {want}"
                );
            }
        }
    }

    #[test]
    fn areal_transmission_is_isotropic() {
        // wave vector (3, 4) periods over a 256² periodic grid of spacing 0.5: λ = 128 / 5
        let (n, dx) = (256, 0.5);
        let side = n as f64 * dx;
        let k = [2.0 * PI * 3.0 / side, 2.0 * PI * 4.0 / side];
        let lambda = side / 5.0;
        for (cutoff, periodic, margin) in [
            (lambda, true, 0),
            (lambda / 2.0, true, 0),
            (lambda, false, 52),
        ] {
            let h = field(n, n, [dx, dx], |x, y| (k[0] * x + k[1] * y).cos());
            let mean = gaussian(&h, cutoff, DEFAULT_ORDER, periodic).unwrap();
            let t = amplitude(&mean, k, [margin, margin]);
            let want = iso_transmission(cutoff, lambda);
            assert!(
                (t - want).abs() <= 0.005,
                "λc {cutoff} periodic {periodic}: {t} vs {want}"
            );
        }
    }

    fn max_error(a: &HeightField, f: impl Fn(f64, f64) -> f64) -> f64 {
        let [nx, ny] = a.dims();
        let mut worst = 0.0f64;
        for j in 0..ny {
            for i in 0..nx {
                let [x, y] = a.position(i, j);
                worst = worst.max((a.get(i, j) - f(x, y)).abs());
            }
        }
        worst
    }

    #[test]
    fn planes_and_quadratics_are_kept_to_the_border() {
        let mut rng = StdRng::seed_from_u64(rand::random());
        let c: [f64; 6] = std::array::from_fn(|_| rng.random_range(-2.0..2.0));
        let plane = move |x: f64, y: f64| 40.0 + c[0] * x + c[1] * y;
        let quad =
            move |x: f64, y: f64| plane(x, y) + 0.05 * (c[2] * x * x + c[3] * x * y + c[4] * y * y);
        // small kernels (direct) and long ones (FFT), square and unequal spacing
        for (nx, ny, spacing, cutoff) in [
            (90, 70, [1.0, 1.0], 12.0),
            (120, 64, [0.5, 0.8], 40.0),
            (300, 1, [1.0, 1.0], 80.0),
        ] {
            let h = field(nx, ny, spacing, plane);
            let mean = gaussian(&h, cutoff, 1, false).unwrap();
            let range = {
                let (lo, hi) = h.min_max();
                hi - lo
            };
            assert!(
                max_error(&mean, plane) <= 1e-9 * range,
                "plane {nx}×{ny} λc {cutoff}"
            );
            let h = field(nx, ny, spacing, quad);
            let mean = gaussian(&h, cutoff, 2, false).unwrap();
            let range = {
                let (lo, hi) = h.min_max();
                hi - lo
            };
            let err = max_error(&mean, quad);
            assert!(
                err <= 1e-9 * range,
                "quadratic {nx}×{ny} λc {cutoff}: {err}"
            );
        }
        // with holes: the measured points alone carry the fit
        let mut h = field(80, 60, [1.0, 1.0], plane);
        for _ in 0..400 {
            let (i, j) = (rng.random_range(0..80), rng.random_range(0..60));
            *h.get_mut(i, j) = f64::NAN;
        }
        let mean = gaussian(&h, 15.0, 1, false).unwrap();
        assert!(max_error(&mean, plane) <= 1e-9 * 200.0);
    }

    #[test]
    fn degree_zero_leaves_the_plane_at_the_border_as_the_plain_kernel_does() {
        let h = field(200, 1, [1.0, 1.0], |x, _| x);
        let mean = gaussian(&h, 40.0, 0, false).unwrap();
        // inside, the symmetric kernel keeps the line; at the end it leans inwards
        assert!((mean.get(100, 0) - 100.0).abs() < 1e-9);
        assert!(*mean.get(0, 0) > 5.0, "{}", mean.get(0, 0));
    }

    /// Largest |a − b| over the points at least `margin` from every border.
    fn max_difference(a: &HeightField, b: &HeightField, margin: usize) -> f64 {
        let [nx, ny] = a.dims();
        let mut worst = 0.0f64;
        for j in margin..ny - margin {
            for i in margin..nx - margin {
                worst = worst.max((a.get(i, j) - b.get(i, j)).abs());
            }
        }
        worst
    }

    #[test]
    fn the_robust_filter_ignores_deep_valleys() {
        let (n, cutoff) = (256, 32.0);
        let k = 2.0 * PI / (4.0 * cutoff);
        let clean = field(n, n, [1.0, 1.0], |x, y| (k * x).sin() + 0.5 * (k * y).cos());
        let sq = (clean.data().iter().map(|z| z * z).sum::<f64>() / clean.len() as f64).sqrt();
        let mut dirty = clean.clone();
        let mut rng = StdRng::seed_from_u64(rand::random());
        for _ in 0..clean.len() / 100 {
            let (i, j) = (rng.random_range(0..n), rng.random_range(0..n));
            *dirty.get_mut(i, j) = -10.0 * sq;
        }
        // degree 1 everywhere; degree 2 a cut-off from the border, where its
        // quadratic extrapolates from a quarter of the kernel and moves by up to ~4 % Sq
        for (order, margin) in [(1, 0), (2, 32)] {
            let (reference, _) = robust_gaussian(&clean, cutoff, order, false).unwrap();
            let (robust, iterations) = robust_gaussian(&dirty, cutoff, order, false).unwrap();
            let worst = max_difference(&reference, &robust, margin);
            assert!(
                worst <= 0.02 * sq,
                "degree {order}: robust mean line off by {worst} (Sq {sq}), {iterations} iterations"
            );
            // the linear filter is pulled down by the valleys: the test can fail
            let linear = gaussian(&dirty, cutoff, order, false).unwrap();
            let pulled = max_difference(&reference, &linear, margin);
            assert!(
                pulled > 0.1 * sq,
                "degree {order}: linear filter moved by only {pulled}"
            );
        }
    }

    #[test]
    fn the_parts_add_up_and_missing_points_stay_missing() {
        let mut rng = StdRng::seed_from_u64(rand::random());
        let mut h = field(96, 80, [1.0, 1.0], |_, _| rng.random_range(-1.0..1.0));
        *h.get_mut(10, 10) = f64::NAN;
        let spec = Specification {
            lambda_s: Some(2.5),
            lambda_c: Some(25.0),
            order: 1,
            robust: false,
            periodic: false,
        };
        let parts = scale_limited(&h, &spec).unwrap();
        assert!(parts.surface.get(10, 10).is_nan());
        let (w, s) = (parts.waviness.unwrap(), parts.noise.unwrap());
        for k in 0..h.len() {
            let z = h.data()[k];
            if z.is_finite() {
                let sum = parts.surface.data()[k] + w.data()[k] + s.data()[k];
                assert!((sum - z).abs() < 1e-12, "{sum} vs {z}");
            }
        }
        assert_eq!(spec.surface_name(), "S-L surface");
        let bad = Specification {
            lambda_s: Some(30.0),
            ..spec
        };
        assert!(scale_limited(&h, &bad).is_err());
    }

    #[test]
    fn the_same_at_any_thread_count() {
        let mut rng = StdRng::seed_from_u64(rand::random());
        let h = field(200, 150, [1.0, 1.0], |_, _| rng.random_range(-1.0..1.0));
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| robust_gaussian(&h, 60.0, 2, false).unwrap().0)
        };
        let (a, b) = (run(1), run(3));
        assert!(
            a.data()
                .iter()
                .zip(b.data())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        );
    }

    #[test]
    fn nesting_indices_come_from_the_series() {
        assert_eq!(series_value(0.9, false), 0.8);
        assert_eq!(series_value(0.8, false), 0.8);
        assert_eq!(series_value(3.1, true), 5.0);
        assert_eq!(series_value(0.0024, true), 0.0025);
        // 1 mm × 1 mm at 1 µm (in mm): λc 0.2 mm, λs 0.005 mm
        let h = field(1001, 1001, [1e-3, 1e-3], |x, _| x);
        let (s, c) = default_cutoffs(&h);
        assert!(
            (c - 0.2).abs() < 1e-12 && (s - 0.005).abs() < 1e-15,
            "{s} {c}"
        );
    }

    #[test]
    fn bad_settings_are_refused() {
        let h = field(20, 20, [1.0, 1.0], |x, y| x + y);
        assert!(gaussian(&h, 0.0, 1, false).is_err());
        assert!(gaussian(&h, f64::NAN, 1, false).is_err());
        assert!(gaussian(&h, 5.0, 3, false).is_err());
    }
}
