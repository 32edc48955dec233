//! Roughness analysis of height fields and meshes.
//!
//! | Module | What | Reference |
//! | --- | --- | --- |
//! | [`level`] | levelling: mean, least-squares plane, quadratic | ISO 25178-2 (F-operator) |
//! | [`areal`] | Sa, Sq, Sp, Sv, Sz, Ssk, Sku, Sdq, Sdr; profile Ra, Rq, … | ISO 25178-2, ISO 4287 |
//! | [`psd`] | 2-D PSD, radially averaged log-binned 1-D PSD, Hurst exponent | SurfaceTopography conventions |
//! | [`mesh`] | curvature (mean, Gaussian) with the Gauss–Bonnet check | Meyer et al. 2003 |
//!
//! Status: partial (issue "Roughness analysis"). Still to come: Sal/Str and the
//! autocorrelation/height-height correlation functions, triangulation and
//! partitioning fractal dimensions, interface-width fits (α, β), cluster
//! dimensions, smoothed-mesh roughness, box counting, `--plot`.

pub mod areal;
pub mod level;
pub mod mesh;
pub mod psd;

use asperity_core::CoreError;

/// Why an analysis was refused.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// The input cannot be analysed (empty, constant, too small, NaN).
    #[error("{0}")]
    BadInput(String),
    /// Invalid geometry.
    #[error(transparent)]
    Core(#[from] CoreError),
}
