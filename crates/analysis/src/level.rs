//! Levelling: the reference surface subtracted before computing parameters.
//!
//! ISO 25178-2 computes areal parameters on the scale-limited surface after an
//! F-operator removes form; the most common F-operator is the least-squares
//! mean plane. [`Level::Mean`] subtracts only the mean height (the right choice
//! for periodic synthetic fields, whose exact parameters would be spoilt by a
//! fitted tilt); [`Level::Slope`] subtracts the plane whose slopes are the mean
//! finite-difference gradient (SurfaceTopography's `detrend_mode='slope'`):
//! on a periodic surface with a tilt added it removes exactly the tilt and
//! leaves a periodic field, where a least-squares plane would leave edge steps;
//! [`Level::Plane`] subtracts the least-squares plane z = a + b·x + c·y
//! (SurfaceTopography's `'height'`); [`Level::Quadratic`] adds the x², xy, y²
//! terms (`'curvature'`). On a profile (one row) the y terms are left out.

use asperity_core::HeightField;
use rayon::prelude::*;

use crate::AnalysisError;

/// Which reference surface is removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    /// Nothing removed.
    None,
    /// The mean height (default).
    #[default]
    Mean,
    /// The plane of the mean finite-difference gradient.
    Slope,
    /// The least-squares plane.
    Plane,
    /// The least-squares quadratic surface.
    Quadratic,
}

impl Level {
    /// Parses `none`, `mean`, `slope`, `plane`, `quadratic`.
    pub fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "none" => Level::None,
            "mean" => Level::Mean,
            "slope" => Level::Slope,
            "plane" => Level::Plane,
            "quadratic" | "poly2" => Level::Quadratic,
            _ => return None,
        })
    }
}

/// Solves the small symmetric system `a·x = b` by Gaussian elimination with
/// partial pivoting (n ≤ 6 here; no crate needed for that).
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c].clone();
        for r in c + 1..n {
            let f = a[r][c] / pivot[c];
            for (x, p) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                *x -= f * p;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        x[r] = (b[r] - (r + 1..n).map(|k| a[r][k] * x[k]).sum::<f64>()) / a[r][r];
    }
    Some(x)
}

/// The field minus the chosen reference surface.
///
/// Missing points (NaN heights, see [`crate::fill`]) take no part in the
/// least-squares fit and stay missing: the reference is fitted to the
/// measured points alone.
///
/// # Errors
/// [`AnalysisError::BadInput`] for a grid too small to fit the surface, or
/// slope levelling (which reads the edges) of a field with missing points;
/// [`AnalysisError::Core`] for an infinite height or no measured point.
pub fn level(h: &HeightField, how: Level) -> Result<HeightField, AnalysisError> {
    h.validate_measured()?;
    let [nx, ny] = h.dims();
    let profile = ny == 1;
    let basis: fn(f64, f64) -> Basis = match (how, profile) {
        (Level::None, _) => return Ok(h.clone()),
        (Level::Slope, _) if h.has_missing() => {
            return Err(AnalysisError::BadInput(format!(
                "slope levelling reads the edges, and {} points are missing: use plane levelling",
                h.missing_count()
            )));
        }
        (Level::Slope, _) => return Ok(slope_levelled(h)),
        (Level::Mean, _) => |_, _| [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        (Level::Plane, false) => |x, y| [1.0, x, y, 0.0, 0.0, 0.0],
        (Level::Quadratic, false) => |x, y| [1.0, x, y, x * x, x * y, y * y],
        (Level::Plane, true) => |x, _| [1.0, x, 0.0, 0.0, 0.0, 0.0],
        (Level::Quadratic, true) => |x, _| [1.0, x, x * x, 0.0, 0.0, 0.0],
    };
    let m = match (how, profile) {
        (Level::Mean, _) => 1,
        (Level::Plane, false) | (Level::Quadratic, true) => 3,
        (Level::Plane, true) => 2,
        _ => 6,
    };
    let too_small = if profile {
        nx < m + 1
    } else {
        nx * ny < m + 1 || (m > 1 && (nx < 2 || ny < 2)) || (m > 3 && (nx < 3 || ny < 3))
    };
    if too_small {
        return Err(AnalysisError::BadInput(format!(
            "a {nx}×{ny} grid is too small for {how:?} levelling"
        )));
    }
    // Normal equations in centred, scaled coordinates (well conditioned),
    // summed in blocks of rows of a fixed size, then the blocks in order, so
    // the result is the same at any thread count.
    let (cx, cy) = ((nx - 1) as f64 / 2.0, (ny - 1) as f64 / 2.0);
    let coord = |i: usize, j: usize| ((i as f64 - cx) / cx.max(1.0), (j as f64 - cy) / cy.max(1.0));
    let partial: Vec<([[f64; 6]; 6], [f64; 6])> = (0..ny.div_ceil(ROWS_PER_TASK))
        .into_par_iter()
        .map(|block| {
            let (mut ata, mut atz) = ([[0.0; 6]; 6], [0.0; 6]);
            for j in block * ROWS_PER_TASK..((block + 1) * ROWS_PER_TASK).min(ny) {
                for (i, &z) in h.row(j).iter().enumerate() {
                    if z.is_nan() {
                        continue;
                    }
                    let (x, y) = coord(i, j);
                    let f = basis(x, y);
                    for r in 0..m {
                        atz[r] += f[r] * z;
                        for c in 0..m {
                            ata[r][c] += f[r] * f[c];
                        }
                    }
                }
            }
            (ata, atz)
        })
        .collect();
    let mut ata = vec![vec![0.0; m]; m];
    let mut atz = vec![0.0; m];
    for (a, z) in &partial {
        for r in 0..m {
            atz[r] += z[r];
            for c in 0..m {
                ata[r][c] += a[r][c];
            }
        }
    }
    let coef = solve(ata, atz)
        .ok_or_else(|| AnalysisError::BadInput("levelling system is singular".into()))?;
    let mut out = h.clone();
    out.data_mut()
        .par_chunks_mut(nx)
        .enumerate()
        .for_each(|(j, row)| {
            for (i, z) in row.iter_mut().enumerate() {
                let (x, y) = coord(i, j);
                let f = basis(x, y);
                *z -= (0..m).map(|r| f[r] * coef[r]).sum::<f64>();
            }
        });
    Ok(out)
}

/// The values of a levelling's basis functions at a point (unused ones 0).
type Basis = [f64; 6];

/// Rows a task of [`level`] sums: fixed, so that the sums do not depend on
/// the thread count.
const ROWS_PER_TASK: usize = 32;

/// The mean slopes of `h` by forward differences, each over the region where
/// both directions have a forward neighbour (SurfaceTopography's non-periodic
/// derivative, trimmed to (nx − 1) × (ny − 1); a profile uses its nx − 1
/// differences), in height per sample.
pub fn mean_slopes(h: &HeightField) -> [f64; 2] {
    let [nx, ny] = h.dims();
    if nx < 2 {
        return [0.0, 0.0];
    }
    if ny == 1 {
        return [(h.row(0)[nx - 1] - h.row(0)[0]) / (nx - 1) as f64, 0.0];
    }
    let sx = (0..ny - 1)
        .map(|j| h.row(j)[nx - 1] - h.row(j)[0])
        .sum::<f64>()
        / ((nx - 1) * (ny - 1)) as f64;
    let sy = (0..nx - 1)
        .map(|i| h.row(ny - 1)[i] - h.row(0)[i])
        .sum::<f64>()
        / ((nx - 1) * (ny - 1)) as f64;
    [sx, sy]
}

/// `h` minus the plane of its mean slopes ([`mean_slopes`]) and its mean.
fn slope_levelled(h: &HeightField) -> HeightField {
    let nx = h.nx();
    let [sx, sy] = mean_slopes(h);
    let mut out = h.clone();
    out.data_mut()
        .par_chunks_mut(nx)
        .enumerate()
        .for_each(|(j, row)| {
            for (i, z) in row.iter_mut().enumerate() {
                *z -= sx * i as f64 + sy * j as f64;
            }
        });
    let mean = out.mean();
    out.data_mut().par_iter_mut().for_each(|z| *z -= mean);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removes_exactly_what_it_fits() {
        let (nx, ny) = (9, 7);
        let plane = HeightField::from_vec(
            [nx, ny],
            (0..nx * ny)
                .map(|k| 3.0 + 0.5 * (k % nx) as f64 - 0.25 * (k / nx) as f64)
                .collect(),
        )
        .unwrap();
        let l = level(&plane, Level::Plane).unwrap();
        assert!(l.data().iter().all(|z| z.abs() < 1e-12));
        let quad = plane.map(|z| z + 0.0);
        let bowl = HeightField::from_vec(
            [nx, ny],
            (0..nx * ny)
                .map(|k| ((k % nx) as f64 - 4.0).powi(2) + (k / nx) as f64 * 2.0)
                .collect(),
        )
        .unwrap();
        assert!(
            level(&bowl, Level::Quadratic)
                .unwrap()
                .data()
                .iter()
                .all(|z| z.abs() < 1e-9)
        );
        assert!(
            level(&bowl, Level::Plane)
                .unwrap()
                .data()
                .iter()
                .any(|z| z.abs() > 1.0)
        );
        let m = level(&quad, Level::Mean).unwrap();
        assert!(m.mean().abs() < 1e-12);
        let tiny = HeightField::from_vec([1, 2], vec![1.0, 2.0]).unwrap();
        assert!(level(&tiny, Level::Plane).is_err());
    }
}
