//! Roughness analysis of height fields and meshes.
//!
//! | Module | What | Reference |
//! | --- | --- | --- |
//! | [`level`] | levelling: mean, least-squares plane, quadratic | ISO 25178-2 (F-operator) |
//! | [`areal`] | Sa, Sq, Sp, Sv, Sz, Ssk, Sku, Sdq, Sdr; profile Ra, Rq, … | ISO 25178-2, ISO 4287 |
//! | [`spectrum`] | the half spectrum of a real field (real-to-complex 2-D FFT), shared by the PSD and the ACF | Hermitian symmetry |
//! | [`profile_elements`] | Rsm, Rc: mean width and height of profile elements, with ISO's height and width discrimination | ISO 21920-2; ISO 4287 |
//! | [`psd`] | 2-D PSD, radially averaged log-binned 1-D PSD, Hurst exponent | SurfaceTopography conventions |
//! | [`correlation`] | ACF, HHCF, Sal, Str | ISO 25178-2 |
//! | [`feature`] | watershed segmentation with Wolf pruning; Spd, Svd, Spc, Svc, S5p, S5v, S10z, Sha, Sda, Shv, Sdv | ISO 25178-2:2021 clause 5; Scott 2004 |
//! | [`filter`] | Gaussian filters: areal and profile, regression of degree 0–2, robust; the scale-limited (S-L) surface | ISO 16610-21, -28, -31, -61, -71; ISO 25178-2 §3.1 |
//! | [`fill`] | missing points filled (harmonic: the discrete Laplace equation; or the mean) | SurfaceTopography `interpolate_undefined_data` |
//! | [`functional`] | the areal material ratio curve: Smr(c), Smc(mr), Sxp, Vm/Vv family, Sk, Spk, Svk, Smr1, Smr2 | ISO 25178-2 §4.5, Annex B; ISO 13565-2 |
//! | [`fractal`] | triangulation and partitioning dimensions | Clarke 1986; variance method |
//! | [`scaling`] | β (plain, intrinsic width), α, cluster dimensions (R_g, mass–radius) | kim-machiraju-thompson §4 |
//! | [`synthesis`] | self-affine surfaces by FFT Fourier filtering (`asperity generate fbm`) | kim-machiraju-thompson §2 (fractal methods) |
//! | [`texture`] | the texture direction Std from the angular amplitude spectrum | ISO 25178-2 §4.3.4 |
//! | [`jets`] | mean and Gaussian curvature of a mesh at a stated scale (osculating jets) | Cazals & Pouget 2005 |
//! | [`mesh`] | curvature (mean, Gaussian) with the Gauss–Bonnet check, roughness against a Taubin-smoothed copy, box counting | Meyer et al. 2003; Taubin 1995 |
//!
//! Plots of these results (PSD with the Hurst fit, H(τ), histograms, W(t)) are
//! drawn by `asperity_render::plot` as PNG and SVG; `asperity analyze --plot DIR`
//! writes them.

pub mod areal;
pub mod correlation;
pub mod feature;
pub mod fill;
pub mod filter;
pub mod fractal;
pub mod functional;
pub mod hurst;
pub mod jets;
pub mod level;
mod lines;
pub mod mesh;
pub mod model;
pub mod multigrid;
pub mod profile_elements;
pub mod psd;
pub mod scaling;
pub mod spectrum;
pub mod statistics;
pub mod synthesis;
pub mod texture;
pub mod window;

use asperity_core::CoreError;

/// Why an analysis was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// The input cannot be analysed (empty, constant, too small, NaN).
    #[error("{0}")]
    BadInput(String),
    /// Invalid geometry.
    #[error(transparent)]
    Core(#[from] CoreError),
}
