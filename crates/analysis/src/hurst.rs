//! The Hurst exponent by several estimators side by side, and the
//! scale-dependent parameters of a surface (Jacobs, Junge & Pastewka 2017;
//! SurfaceTopography).
//!
//! | Estimator | Statistic | Fit |
//! | --- | --- | --- |
//! | `psd_2d` | radially averaged PSD, C ∝ q^−(2+2H) | mode-weighted log bins ([`crate::psd`]) |
//! | `psd_x`, `psd_y` | mean 1-D PSD of rows / columns, ∝ q^−(1+2H) | model GLS ([`crate::model`]) |
//! | `structure_function` | ⟨(z(x+τ) − z(x))²⟩ ∝ τ^2H (the HHCF; rms slope ∝ τ^(H−1)) | model GLS |
//! | `variable_bandwidth` | rms height in boxes of side ℓ after their plane, ∝ ℓ^H | model GLS |
//!
//! `psd_x` and `psd_y` differ on anisotropic surfaces; the estimators together
//! differ when the surface is not self-affine over the fit range. A spread
//! above [`DISAGREEMENT`] is reported as a warning.
//!
//! The fit ranges come from the 2-D PSD's window ([`crate::psd::auto_range`] or
//! the user's): wavenumbers [q_lo, q_hi] become wavelengths λ = 2π/q, and the
//! real-space scales are taken inside [λ_min/2, λ_max/2] (lags) and
//! [λ_min, λ_max] (boxes), within the field.
//!
//! Scale-dependent parameters follow SurfaceTopography: with A(τ) = S(τ)/2 the
//! height-difference autocorrelation, the rms slope at scale τ is √(2A(τ))/τ and
//! the rms curvature 4√(8A(τ/2) − 2A(τ))/τ²; the rms height at scale ℓ is the
//! variable bandwidth. Here S is averaged over the x and y directions rather
//! than over all directions (SurfaceTopography averages radially).

use asperity_core::HeightField;
use serde::Serialize;

use crate::AnalysisError;
use crate::model::{Compressed, ModeGrid, fit};
use crate::psd::{Hurst, RadialPsd};
use crate::statistics::{
    BoxReference, BoxVariance, ProfileSpectrum, StructureFunction, log_scales,
};
use crate::window::Window;

/// Estimates further apart than this are reported as disagreeing.
pub const DISAGREEMENT: f64 = 0.1;

/// One estimate of H.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Estimate {
    /// The estimator's name.
    pub method: &'static str,
    /// The Hurst exponent.
    #[serde(rename = "H")]
    pub hurst: f64,
    /// Its standard error.
    pub stderr: f64,
    /// The fit's r².
    pub r2: f64,
    /// The fitted range, in `range_unit`.
    pub fit_range: [f64; 2],
    /// "rad/length" for wavenumbers, "length" for lags and box sides.
    pub range_unit: &'static str,
    /// Points (bins, lags, boxes) in the fit.
    pub points: usize,
}

/// How the estimators see the data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Periodic data (pairs wrap around; no window).
    pub periodic: bool,
    /// The window of non-periodic data.
    pub window: Window,
}

fn wavelengths(range: [f64; 2]) -> [f64; 2] {
    let t = std::f64::consts::TAU;
    [t / range[1], t / range[0]]
}

/// Samples along the shorter side (the length of a profile).
fn shortest_side(h: &HeightField) -> usize {
    if h.ny() == 1 {
        h.nx()
    } else {
        h.nx().min(h.ny())
    }
}

/// The structure-function estimate over lags in `range` (length units).
fn structure_function(
    h: &HeightField,
    s: Setup,
    range: [f64; 2],
) -> Result<Estimate, AnalysisError> {
    let dx = h.spacing()[0];
    let n = shortest_side(h);
    let lo = ((range[0] / dx).round() as usize).max(1);
    let hi = ((range[1] / dx) as usize).min(n / 4);
    let lags = log_scales(lo, hi, 2);
    let stat = StructureFunction::new(h, lags.clone(), s.periodic);
    model_estimate("structure_function", &stat, &stat.measure(h), h, |k| {
        lags[k] as f64 * dx
    })
}

/// The variable-bandwidth estimate over box sides in `range`.
fn variable_bandwidth(h: &HeightField, range: [f64; 2]) -> Result<Estimate, AnalysisError> {
    let dx = h.spacing()[0];
    let n = shortest_side(h);
    let lo = ((range[0] / dx).round() as usize).max(4);
    let hi = ((range[1] / dx) as usize).min(n / 2);
    // One side per octave: neighbouring sides closer than that are so
    // correlated that the covariance becomes nearly singular.
    let sides = log_scales(lo, hi, 1);
    let stat = BoxVariance::new(h, sides.clone(), BoxReference::Plane);
    model_estimate("variable_bandwidth", &stat, &stat.measure(h), h, |k| {
        sides[k] as f64 * dx
    })
}

/// The 1-D PSD estimate along x or y over wavenumbers in `range`.
fn profile_psd(
    h: &HeightField,
    s: Setup,
    along_y: bool,
    range: [f64; 2],
) -> Result<Estimate, AnalysisError> {
    let (n, d) = if along_y {
        (h.ny(), h.spacing()[1])
    } else {
        (h.nx(), h.spacing()[0])
    };
    let l = n as f64 * d;
    let k_of = |q: f64| q * l / std::f64::consts::TAU;
    let lo = (k_of(range[0]).ceil() as usize).max(1);
    let hi = (k_of(range[1]).floor() as usize).min(n / 2);
    let indices = log_scales(lo, hi, 6);
    let window = if s.periodic { Window::None } else { s.window };
    let stat = ProfileSpectrum::new(h, along_y, indices.clone(), window);
    let name = if along_y { "psd_y" } else { "psd_x" };
    let mut e = model_estimate(name, &stat, &stat.measure(h), h, |k| {
        std::f64::consts::TAU * indices[k] as f64 / l
    })?;
    e.range_unit = "rad/length";
    Ok(e)
}

/// Fits the model to `measured` and reports it with its range.
fn model_estimate(
    method: &'static str,
    stat: &dyn crate::model::Kernel,
    measured: &[f64],
    h: &HeightField,
    scale: impl Fn(usize) -> f64,
) -> Result<Estimate, AnalysisError> {
    let n = measured.len();
    if n < 3 {
        return Err(AnalysisError::BadInput(format!(
            "{method}: fewer than 3 scales in the fit range; widen it or use a larger field"
        )));
    }
    let model = Compressed::new(stat, &ModeGrid::of(h));
    let f = fit(measured, &model, &vec![true; n])
        .ok_or_else(|| AnalysisError::BadInput(format!("{method}: fewer than 3 usable scales")))?;
    if f.at_bound {
        return Err(AnalysisError::BadInput(format!(
            "{method}: the fit ends at H = {:.2}, outside the self-affine range",
            f.hurst
        )));
    }
    let (a, b) = (scale(0), scale(n - 1));
    Ok(Estimate {
        method,
        hurst: f.hurst,
        stderr: f.stderr,
        r2: f.r2,
        fit_range: [a.min(b), a.max(b)],
        range_unit: "length",
        points: f.points,
    })
}

/// Which Hurst estimators a report runs: every one, or one a user needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Which {
    /// The PSD fit, the profile PSDs, the structure function and the variable
    /// bandwidth method.
    #[default]
    All,
    /// The PSD fit alone (2-D, or the profile's for a profile).
    Psd,
    /// The PSD fit and the profile PSDs along x and y.
    PsdProfiles,
    /// The PSD fit and the structure function.
    StructureFunction,
    /// The PSD fit and the variable bandwidth method.
    VariableBandwidth,
}

/// Every estimator on the levelled field `h` (not windowed; the profile PSDs
/// window themselves), the 2-D PSD fit `psd` and its PSD giving the range.
pub fn estimate_all(
    h: &HeightField,
    s: Setup,
    psd: &RadialPsd,
    psd_fit: &Result<Hurst, AnalysisError>,
) -> Vec<(&'static str, Result<Estimate, AnalysisError>)> {
    estimate(h, s, psd, psd_fit, Which::All)
}

/// The PSD fit and the estimators `which` names, in [`estimate_all`]'s order;
/// the real-space and profile estimators run at once on every core.
pub fn estimate(
    h: &HeightField,
    s: Setup,
    psd: &RadialPsd,
    psd_fit: &Result<Hurst, AnalysisError>,
    which: Which,
) -> Vec<(&'static str, Result<Estimate, AnalysisError>)> {
    use rayon::prelude::*;
    let mut out = Vec::new();
    let psd_method = if psd.dim == 1 {
        "psd_profile"
    } else {
        "psd_2d"
    };
    out.push((
        psd_method,
        psd_fit.clone().map(|hu| Estimate {
            method: psd_method,
            hurst: hu.hurst,
            stderr: hu.stderr,
            r2: hu.fit.r2,
            fit_range: hu.fit.range,
            range_unit: "rad/length",
            points: hu.fit.points,
        }),
    ));
    let range = match psd_fit {
        Ok(hu) => hu.fit.range,
        Err(_) => {
            let lo = psd.edges.first().map_or(1.0, |e| e[0]);
            [2.0 * lo, psd.edges.last().map_or(1.0, |e| e[1])]
        }
    };
    let [l_min, l_max] = wavelengths(range);
    type Run<'a> = Box<dyn Fn() -> Result<Estimate, AnalysisError> + Sync + 'a>;
    let mut runs: Vec<(&'static str, Which, Run)> = Vec::new();
    if h.ny() > 1 {
        runs.push((
            "psd_x",
            Which::PsdProfiles,
            Box::new(move || profile_psd(h, s, false, range)),
        ));
        runs.push((
            "psd_y",
            Which::PsdProfiles,
            Box::new(move || profile_psd(h, s, true, range)),
        ));
    }
    runs.push((
        "structure_function",
        Which::StructureFunction,
        Box::new(move || structure_function(h, s, [l_min / 2.0, l_max / 2.0])),
    ));
    runs.push((
        "variable_bandwidth",
        Which::VariableBandwidth,
        Box::new(move || variable_bandwidth(h, [l_min, l_max])),
    ));
    let done: Vec<_> = runs
        .par_iter()
        .filter(|(_, kind, _)| which == Which::All || which == *kind)
        .map(|(name, _, run)| (*name, run()))
        .collect();
    out.extend(done);
    out
}

/// The largest difference between two estimates, if there are two.
pub fn spread(estimates: &[(&'static str, Result<Estimate, AnalysisError>)]) -> Option<f64> {
    let hs: Vec<f64> = estimates
        .iter()
        .filter_map(|(_, e)| e.as_ref().ok().map(|e| e.hurst))
        .collect();
    (hs.len() >= 2).then(|| {
        let lo = hs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = hs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        hi - lo
    })
}

/// Roughness parameters as functions of scale (see the module docs).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ScaleDependent {
    /// Distances τ (length units) of the slope and curvature.
    pub distance: Vec<f64>,
    /// rms slope at τ: √(2A(τ))/τ.
    pub rms_slope: Vec<f64>,
    /// rms curvature at τ: 4√(8A(τ/2) − 2A(τ))/τ² (null where the root is negative).
    pub rms_curvature: Vec<Option<f64>>,
    /// Box sides ℓ (length units) of the rms height.
    pub bandwidth: Vec<f64>,
    /// rms height after each box's plane, at side ℓ (variable bandwidth).
    pub rms_height: Vec<f64>,
}

/// The scale-dependent rms slope, curvature and height of the levelled field.
pub fn scale_dependent(h: &HeightField, periodic: bool) -> ScaleDependent {
    let dx = h.spacing()[0];
    let two_d = h.ny() > 1;
    let n = if two_d { h.nx().min(h.ny()) } else { h.nx() };
    // Even lags, so that τ/2 is a lag too.
    let lags: Vec<usize> = log_scales(1, (n / 4).max(1), 3)
        .into_iter()
        .map(|t| 2 * t)
        .filter(|&t| t <= n / 2)
        .collect();
    let half: Vec<usize> = lags.iter().map(|t| t / 2).collect();
    let per_dir = if two_d { 2.0 } else { 1.0 };
    // A(τ) = S(τ)/2 with S per direction.
    let a = |ls: &[usize]| -> Vec<f64> {
        StructureFunction::new(h, ls.to_vec(), periodic)
            .measure(h)
            .iter()
            .map(|s| s / per_dir / 2.0)
            .collect()
    };
    let (a_full, a_half) = (a(&lags), a(&half));
    let distance: Vec<f64> = lags.iter().map(|&t| t as f64 * dx).collect();
    let rms_slope = a_full
        .iter()
        .zip(&distance)
        .map(|(a, d)| (2.0 * a).sqrt() / d)
        .collect();
    let rms_curvature = a_full
        .iter()
        .zip(&a_half)
        .zip(&distance)
        .map(|((af, ah), d)| {
            let b = 8.0 * ah - 2.0 * af;
            (b >= 0.0).then(|| 4.0 * b.sqrt() / (d * d))
        })
        .collect();
    let sides = log_scales(4, (n / 2).max(4), 2);
    let bv = BoxVariance::new(h, sides.clone(), BoxReference::Plane);
    ScaleDependent {
        distance,
        rms_slope,
        rms_curvature,
        bandwidth: sides.iter().map(|&l| l as f64 * dx).collect(),
        rms_height: bv.measure(h).iter().map(|v| v.sqrt()).collect(),
    }
}
