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
/// # Errors
/// [`AnalysisError::BadInput`] for NaN heights or a grid too small to fit the surface.
pub fn level(h: &HeightField, how: Level) -> Result<HeightField, AnalysisError> {
    h.validate()?;
    let [nx, ny] = h.dims();
    let profile = ny == 1;
    let basis: fn(f64, f64) -> Vec<f64> = match (how, profile) {
        (Level::None, _) => return Ok(h.clone()),
        (Level::Slope, _) => return Ok(slope_levelled(h)),
        (Level::Mean, _) => |_, _| vec![1.0],
        (Level::Plane, false) => |x, y| vec![1.0, x, y],
        (Level::Quadratic, false) => |x, y| vec![1.0, x, y, x * x, x * y, y * y],
        (Level::Plane, true) => |x, _| vec![1.0, x],
        (Level::Quadratic, true) => |x, _| vec![1.0, x, x * x],
    };
    let m = basis(0.0, 0.0).len();
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
    // Normal equations in centred, scaled coordinates (well conditioned).
    let (cx, cy) = ((nx - 1) as f64 / 2.0, (ny - 1) as f64 / 2.0);
    let coord = |i: usize, j: usize| ((i as f64 - cx) / cx.max(1.0), (j as f64 - cy) / cy.max(1.0));
    let mut ata = vec![vec![0.0; m]; m];
    let mut atz = vec![0.0; m];
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = coord(i, j);
            let f = basis(x, y);
            let z = *h.get(i, j);
            for r in 0..m {
                atz[r] += f[r] * z;
                for c in 0..m {
                    ata[r][c] += f[r] * f[c];
                }
            }
        }
    }
    let coef = solve(ata, atz)
        .ok_or_else(|| AnalysisError::BadInput("levelling system is singular".into()))?;
    let mut out = h.clone();
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = coord(i, j);
            let fit: f64 = basis(x, y).iter().zip(&coef).map(|(f, c)| f * c).sum();
            *out.get_mut(i, j) -= fit;
        }
    }
    Ok(out)
}

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
    let ny = h.ny();
    let [sx, sy] = mean_slopes(h);
    let mut out = h.clone();
    for j in 0..ny {
        for (i, z) in out.row_mut(j).iter_mut().enumerate() {
            *z -= sx * i as f64 + sy * j as f64;
        }
    }
    let mean = out.mean();
    out.map(|z| z - mean)
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
