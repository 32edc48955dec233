//! Filling unmeasured points.
//!
//! Measured topographies have holes: points an optical profilometer could
//! not see, dropouts of a stylus, the outside of a circular aperture. They
//! arrive as NaN heights (see `asperity_core::HeightField::validate_measured`).
//! The amplitude parameters are computed over the measured points alone
//! ([`crate::areal::measured_heights`]); spectra, correlation functions and the
//! fractal estimators need a value at every point of the grid, so their
//! holes are filled first, as SurfaceTopography's `interpolate_undefined_data`
//! and Gwyddion's "Remove data under mask" (Laplace) do:
//!
//! - [`Fill::Harmonic`]: each missing height is the weighted mean of its four
//!   neighbours, `Σ_n w_n (z − z_n) = 0` with `w = 1/Δx²` along x and `1/Δy²`
//!   along y (the five-point discrete Laplace equation, Δz = 0), with the
//!   measured heights as boundary values and no flux through the grid's
//!   edge. The filled surface is the smoothest one through the measured
//!   points (the minimiser of the discrete Dirichlet energy), so a hole adds
//!   no roughness of its own. The system is symmetric positive definite
//!   (every hole touches a measured point, the grid being connected) and is
//!   solved by conjugate gradients with a Jacobi preconditioner, matrix-free.
//!   Written here: the solve is forty lines and a sparse-matrix crate would
//!   bring assembly and a factorisation the holes do not need.
//! - [`Fill::Mean`]: every missing height is the mean of the measured ones.

use asperity_core::HeightField;

use crate::AnalysisError;

/// How missing points are filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Fill {
    /// The discrete Laplace equation through the measured points.
    #[default]
    Harmonic,
    /// The mean of the measured heights.
    Mean,
}

impl Fill {
    /// Its name in reports and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Fill::Harmonic => "harmonic",
            Fill::Mean => "mean",
        }
    }
}

/// What [`fill_missing`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filled {
    /// Points filled.
    pub missing: usize,
    /// Conjugate-gradient iterations (0 for [`Fill::Mean`] or no hole).
    pub iterations: usize,
    /// The final residual relative to the right-hand side's norm.
    pub residual: f64,
}

/// Relative residual at which the harmonic solve stops.
const TOLERANCE: f64 = 1e-12;

/// `h` with every missing (NaN) height filled as `how` says.
///
/// # Errors
/// [`AnalysisError::Core`] for an infinite height or a field with no
/// measured point; [`AnalysisError::BadInput`] if the harmonic solve does not
/// converge (it always does in exact arithmetic within the number of holes'
/// points).
pub fn fill_missing(h: &HeightField, how: Fill) -> Result<(HeightField, Filled), AnalysisError> {
    h.validate_measured()?;
    let missing: Vec<usize> = (0..h.len()).filter(|&k| h.data()[k].is_nan()).collect();
    let mut out = h.clone();
    if missing.is_empty() {
        let none = Filled {
            missing: 0,
            iterations: 0,
            residual: 0.0,
        };
        return Ok((out, none));
    }
    let report = match how {
        Fill::Mean => {
            let values = h.measured_values();
            let mean = values.iter().sum::<f64>() / values.len() as f64;
            missing.iter().for_each(|&k| out.data_mut()[k] = mean);
            Filled {
                missing: missing.len(),
                iterations: 0,
                residual: 0.0,
            }
        }
        Fill::Harmonic => harmonic(&mut out, &missing)?,
    };
    Ok((out, report))
}

/// The Laplace system over the missing points: for each, its neighbours that
/// are missing too (index into the unknowns, weight), its diagonal and the
/// right-hand side from its measured neighbours.
struct Laplace {
    links: Vec<[(u32, f64); 4]>,
    diagonal: Vec<f64>,
    rhs: Vec<f64>,
}

impl Laplace {
    fn new(h: &HeightField, missing: &[usize]) -> Self {
        let [nx, ny] = h.dims();
        let [dx, dy] = h.spacing();
        let (wx, wy) = (1.0 / (dx * dx), 1.0 / (dy * dy));
        let mut unknown = vec![u32::MAX; h.len()];
        for (n, &k) in missing.iter().enumerate() {
            unknown[k] = n as u32;
        }
        let mut links = vec![[(u32::MAX, 0.0); 4]; missing.len()];
        let mut diagonal = vec![0.0; missing.len()];
        let mut rhs = vec![0.0; missing.len()];
        for (n, &k) in missing.iter().enumerate() {
            let (i, j) = (k % nx, k / nx);
            let neighbours = [
                (i > 0).then(|| (k - 1, wx)),
                (i + 1 < nx).then(|| (k + 1, wx)),
                (j > 0).then(|| (k - nx, wy)),
                (j + 1 < ny).then(|| (k + nx, wy)),
            ];
            for (slot, (m, w)) in neighbours.into_iter().flatten().enumerate() {
                diagonal[n] += w;
                match unknown[m] {
                    u32::MAX => rhs[n] += w * h.data()[m],
                    u => links[n][slot] = (u, w),
                }
            }
        }
        Self {
            links,
            diagonal,
            rhs,
        }
    }

    /// `A x` into `out`.
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        for (n, o) in out.iter_mut().enumerate() {
            let off: f64 = self.links[n]
                .iter()
                .filter(|(u, _)| *u != u32::MAX)
                .map(|&(u, w)| w * x[u as usize])
                .sum();
            *o = self.diagonal[n] * x[n] - off;
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Preconditioned conjugate gradients (Jacobi), started from the measured
/// mean.
fn harmonic(out: &mut HeightField, missing: &[usize]) -> Result<Filled, AnalysisError> {
    let system = Laplace::new(out, missing);
    let values = out.measured_values();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let n = missing.len();
    let mut x = vec![mean; n];
    let mut ax = vec![0.0; n];
    system.apply(&x, &mut ax);
    let mut r: Vec<f64> = system.rhs.iter().zip(&ax).map(|(b, a)| b - a).collect();
    let norm_b = dot(&system.rhs, &system.rhs).sqrt().max(f64::MIN_POSITIVE);
    let precondition =
        |r: &[f64]| -> Vec<f64> { r.iter().zip(&system.diagonal).map(|(r, d)| r / d).collect() };
    let mut z = precondition(&r);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut iterations = 0;
    let mut residual = dot(&r, &r).sqrt() / norm_b;
    // CG reaches the exact solution in at most n steps in exact arithmetic;
    // rounding can ask for a few more.
    let limit = 2 * n + 100;
    while residual > TOLERANCE && iterations < limit {
        system.apply(&p, &mut ax);
        let alpha = rz / dot(&p, &ax);
        x.iter_mut().zip(&p).for_each(|(x, p)| *x += alpha * p);
        r.iter_mut().zip(&ax).for_each(|(r, a)| *r -= alpha * a);
        z = precondition(&r);
        let rz_next = dot(&r, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        p.iter_mut().zip(&z).for_each(|(p, z)| *p = z + beta * *p);
        iterations += 1;
        residual = dot(&r, &r).sqrt() / norm_b;
    }
    if residual.is_nan() || residual > TOLERANCE * 1e3 {
        return Err(AnalysisError::BadInput(format!(
            "filling {n} missing points did not converge (relative residual {residual:.1e} \
             after {iterations} iterations)"
        )));
    }
    for (&k, v) in missing.iter().zip(x) {
        out.data_mut()[k] = v;
    }
    Ok(Filled {
        missing: n,
        iterations,
        residual,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x² − y² + 3xy + 2x − y + 5 is harmonic, and its five-point Laplacian
    /// with the weights `1/Δ²` vanishes exactly at any spacings.
    fn harmonic_surface(nx: usize, ny: usize, dx: f64, dy: f64) -> HeightField {
        let f = |x: f64, y: f64| x * x - y * y + 3.0 * x * y + 2.0 * x - y + 5.0;
        let data = (0..nx * ny)
            .map(|k| f((k % nx) as f64 * dx, (k / nx) as f64 * dy))
            .collect();
        HeightField::from_vec([nx, ny], data)
            .unwrap()
            .with_spacing([dx, dy])
            .unwrap()
    }

    fn punch(h: &HeightField, hole: impl Fn(usize, usize) -> bool) -> HeightField {
        let mut out = h.clone();
        let nx = h.nx();
        for k in 0..h.len() {
            if hole(k % nx, k / nx) {
                out.data_mut()[k] = f64::NAN;
            }
        }
        out
    }

    #[test]
    fn a_harmonic_surface_is_restored_in_its_holes() {
        // Anisotropic spacing: the weights 1/Δx², 1/Δy² matter.
        let truth = harmonic_surface(40, 30, 0.5, 0.25);
        let holed = punch(&truth, |i, j| {
            let (a, b) = (i as f64 - 15.0, j as f64 - 12.0);
            a * a + b * b < 60.0 || (i == 30 && (5..25).contains(&j))
        });
        assert!(holed.missing_count() > 150);
        let (filled, report) = fill_missing(&holed, Fill::Harmonic).unwrap();
        assert_eq!(report.missing, holed.missing_count());
        assert!(report.residual <= 1e-12, "{report:?}");
        let scale = truth.data().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (k, (a, b)) in filled.data().iter().zip(truth.data()).enumerate() {
            assert!((a - b).abs() <= 1e-9 * scale, "point {k}: {a} against {b}");
        }
    }

    #[test]
    fn a_hole_on_the_edge_has_no_flux_through_it() {
        // A field constant along x with a hole across the right edge: the
        // harmonic fill continues each row (zero normal derivative).
        let mut data = Vec::new();
        for j in 0..10 {
            data.extend(std::iter::repeat_n(j as f64, 12));
        }
        let truth = HeightField::from_vec([12, 10], data).unwrap();
        let holed = punch(&truth, |i, j| i >= 8 && (2..7).contains(&j));
        let (filled, _) = fill_missing(&holed, Fill::Harmonic).unwrap();
        for (a, b) in filled.data().iter().zip(truth.data()) {
            assert!((a - b).abs() < 1e-10, "{a} against {b}");
        }
    }

    #[test]
    fn the_mean_fill_uses_the_measured_mean() {
        let truth = HeightField::from_vec([2, 2], vec![1.0, 2.0, 6.0, 0.0]).unwrap();
        let holed = punch(&truth, |i, j| i == 1 && j == 1);
        let (filled, report) = fill_missing(&holed, Fill::Mean).unwrap();
        assert_eq!(filled.data(), &[1.0, 2.0, 6.0, 3.0]);
        assert_eq!(report.missing, 1);
    }

    #[test]
    fn a_field_without_measured_points_is_refused() {
        let empty = HeightField::from_vec([3, 1], vec![f64::NAN; 3]).unwrap();
        assert!(fill_missing(&empty, Fill::Harmonic).is_err());
        let complete = harmonic_surface(4, 4, 1.0, 1.0);
        let (same, report) = fill_missing(&complete, Fill::Harmonic).unwrap();
        assert_eq!(same, complete);
        assert_eq!(report.missing, 0);
    }
}
