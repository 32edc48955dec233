//! Fractal dimension of height fields by the triangulation and partitioning
//! (variance) methods, each with its fit range and r².
//!
//! - **Triangulation** (Clarke 1986): the surface area A(ε) of the field
//!   triangulated on a grid coarsened to step ε (every s-th sample) scales as
//!   A ∝ ε^(2−D), so D = 2 − slope of log A against log ε. Valid in the regime
//!   where height differences dominate the cell size (rough surfaces).
//! - **Partitioning** (variance method): the field is cut into square boxes of
//!   side s; the mean over boxes of the height standard deviation in a box scales
//!   as σ(s) ∝ s^H, so H = slope and D = 3 − H.
//!
//! Scales run over powers of two from 2 samples to a quarter of the shorter side.

use asperity_core::HeightField;
use serde::Serialize;

use crate::AnalysisError;
use crate::areal::triangle_area;
use crate::psd::{LogFit, log_fit};

/// A dimension estimate with its fit.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Dimension {
    /// The fractal dimension D.
    pub d: f64,
    /// The log–log fit behind it (x in length units).
    pub fit: LogFit,
}

fn scales(h: &HeightField) -> Result<Vec<usize>, AnalysisError> {
    let n = h.nx().min(h.ny());
    let s: Vec<usize> = (1..)
        .map(|k| 1usize << k)
        .take_while(|&s| s <= n / 4)
        .collect();
    if s.len() < 3 {
        return Err(AnalysisError::BadInput(format!(
            "a {}×{} field is too small for a dimension fit (need ≥ 32 samples a side)",
            h.nx(),
            h.ny()
        )));
    }
    Ok(s)
}

/// Triangulation (surface-area) dimension.
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN or too-small fields.
pub fn triangulation(h: &HeightField) -> Result<Dimension, AnalysisError> {
    h.validate()?;
    let [nx, ny] = h.dims();
    let dx = h.spacing()[0];
    let mut eps = Vec::new();
    let mut area = Vec::new();
    for s in std::iter::once(1).chain(scales(h)?) {
        let sub = |i: usize, j: usize| h.point(i * s, j * s);
        let (mx, my) = ((nx - 1) / s, (ny - 1) / s);
        let mut a = 0.0;
        for j in 0..my {
            for i in 0..mx {
                a += triangle_area(sub(i, j), sub(i + 1, j), sub(i + 1, j + 1))
                    + triangle_area(sub(i, j), sub(i + 1, j + 1), sub(i, j + 1));
            }
        }
        // Normalise to the same projected area, so coarse grids that lose an edge strip compare.
        let projected = (mx * s) as f64 * (my * s) as f64;
        eps.push(s as f64 * dx);
        area.push(a / projected * ((nx - 1) * (ny - 1)) as f64);
    }
    let fit = log_fit(&eps, &area, [eps[0], eps[eps.len() - 1]])?;
    Ok(Dimension {
        d: 2.0 - fit.slope,
        fit,
    })
}

/// Partitioning (variance) dimension.
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN or too-small fields.
pub fn partitioning(h: &HeightField) -> Result<Dimension, AnalysisError> {
    h.validate()?;
    let [nx, ny] = h.dims();
    let dx = h.spacing()[0];
    let (mut size, mut sigma) = (Vec::new(), Vec::new());
    for s in scales(h)? {
        let (bx, by) = (nx / s, ny / s);
        let mut total = 0.0;
        for bj in 0..by {
            for bi in 0..bx {
                let (mut m, mut m2) = (0.0, 0.0);
                for j in bj * s..(bj + 1) * s {
                    for &v in &h.row(j)[bi * s..(bi + 1) * s] {
                        m += v;
                        m2 += v * v;
                    }
                }
                let n = (s * s) as f64;
                total += (m2 / n - (m / n).powi(2)).max(0.0).sqrt();
            }
        }
        size.push(s as f64 * dx);
        sigma.push(total / (bx * by) as f64);
    }
    let fit = log_fit(&size, &sigma, [size[0], size[size.len() - 1]])?;
    Ok(Dimension {
        d: 3.0 - fit.slope,
        fit,
    })
}
