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
//!   solved by conjugate gradients preconditioned by an aggregation multigrid
//!   V-cycle ([`crate::multigrid`]), matrix-free: a few tens of iterations whatever
//!   the holes' size (a Jacobi preconditioner needed 2,570 on
//!   SurfaceTopography's `sur-3.sur`, 89 % of 512² missing: 4.5 s, now a
//!   fraction of a second).
//! - [`Fill::Mean`]: every missing height is the mean of the measured ones.

use asperity_core::HeightField;

use crate::multigrid::{Hierarchy, Level};

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

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Conjugate gradients on the Laplace system over the grid (a vector holds
/// every node, 0 at the measured ones), started from the measured mean and
/// preconditioned by a multigrid V-cycle ([`crate::multigrid`]).
fn harmonic(out: &mut HeightField, missing: &[usize]) -> Result<Filled, AnalysisError> {
    let [nx, ny] = out.dims();
    let [dx, dy] = out.spacing();
    let (wx, wy) = (1.0 / (dx * dx), 1.0 / (dy * dy));
    let mut unknown = vec![false; nx * ny];
    missing.iter().for_each(|&k| unknown[k] = true);
    let heights = out.data();
    // The measured neighbours' heights, on the right-hand side.
    let rhs: Vec<f64> = (0..nx * ny)
        .map(|k| {
            if !unknown[k] {
                return 0.0;
            }
            let (i, j) = (k % nx, k / nx);
            [
                (i > 0).then(|| (k - 1, wx)),
                (i + 1 < nx).then(|| (k + 1, wx)),
                (j > 0).then(|| (k - nx, wy)),
                (j + 1 < ny).then(|| (k + nx, wy)),
            ]
            .into_iter()
            .flatten()
            .filter(|&(m, _)| !unknown[m])
            .map(|(m, w)| w * heights[m])
            .sum()
        })
        .collect();
    let hierarchy = Hierarchy::new(Level::grid(nx, ny, &unknown, (wx, wy)));
    let level = hierarchy.finest();
    let precondition = |r: &[f64]| hierarchy.precondition(r);
    let values = out.measured_values();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let mut x: Vec<f64> = unknown
        .iter()
        .map(|&u| if u { mean } else { 0.0 })
        .collect();
    let mut ax = vec![0.0; nx * ny];
    level.apply(&x, &mut ax);
    let mut r: Vec<f64> = rhs.iter().zip(&ax).map(|(b, a)| b - a).collect();
    let norm_b = dot(&rhs, &rhs).sqrt().max(f64::MIN_POSITIVE);
    let mut z = precondition(&r);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut iterations = 0;
    let mut residual = dot(&r, &r).sqrt() / norm_b;
    // CG reaches the exact solution in at most n steps in exact arithmetic;
    // rounding can ask for a few more.
    let limit = 2 * missing.len() + 100;
    while residual > TOLERANCE && iterations < limit {
        level.apply(&p, &mut ax);
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
    let n = missing.len();
    if residual.is_nan() || residual > TOLERANCE * 1e3 {
        return Err(AnalysisError::BadInput(format!(
            "filling {n} missing points did not converge (relative residual {residual:.1e} \
             after {iterations} iterations)"
        )));
    }
    for &k in missing {
        out.data_mut()[k] = x[k];
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

    fn punch(h: &HeightField, mut hole: impl FnMut(usize, usize) -> bool) -> HeightField {
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

    /// Any fraction missing inside the field, scattered or in one block, on
    /// fields of odd and even sides and of one row or column: the harmonic
    /// surface comes back (a plane on a single row or column, harmonic in
    /// one dimension; holes off the edge, where the fill's no-flux condition
    /// is not the surface's), in a few tens of multigrid-preconditioned
    /// iterations (the Jacobi preconditioner took thousands on large holes).
    #[test]
    fn any_fraction_missing_is_filled_in_few_iterations() {
        use rand::{Rng, SeedableRng};
        let seed: u64 = rand::random();
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        for (nx, ny) in [(257, 190), (64, 64), (300, 1), (1, 120)] {
            for fraction in [0.01f64, 0.3, 0.9, 0.995] {
                let truth = if nx > 1 && ny > 1 {
                    harmonic_surface(nx, ny, 0.5, 0.7)
                } else {
                    let plane = (0..nx * ny).map(|k| 3.0 + 0.25 * k as f64).collect();
                    HeightField::from_vec([nx, ny], plane).unwrap()
                };
                let block = rng.random::<bool>();
                let (ci, cj) = (nx as f64 / 2.0, ny as f64 / 2.0);
                let holed = punch(&truth, |i, j| {
                    let inside =
                        (nx == 1 || i > 0 && i + 1 < nx) && (ny == 1 || j > 0 && j + 1 < ny);
                    let (di, dj) = ((i as f64 - ci).abs(), (j as f64 - cj).abs());
                    inside
                        && if block {
                            di < fraction * ci && dj < fraction * cj
                        } else {
                            rng.random::<f64>() < fraction
                        }
                });
                if holed.missing_count() == 0 {
                    continue;
                }
                let (filled, report) = fill_missing(&holed, Fill::Harmonic).unwrap();
                assert!(
                    report.iterations <= 80,
                    "seed {seed}, {nx}×{ny}, {fraction}: {report:?}"
                );
                let scale = truth.data().iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (a, b) in filled.data().iter().zip(truth.data()) {
                    assert!(
                        (a - b).abs() <= 1e-8 * scale,
                        "seed {seed}, {nx}×{ny}, {fraction}: {a} against {b}"
                    );
                }
            }
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
