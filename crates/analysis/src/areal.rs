//! ISO 25178-2 areal height and hybrid parameters, and ISO 4287 profile parameters.
//!
//! With z the levelled heights (see [`crate::level`]) over the N samples:
//!
//! | Parameter | Formula | Note |
//! | --- | --- | --- |
//! | Sa | mean \|z\| | arithmetic mean height |
//! | Sq | √(mean z²) | root-mean-square height |
//! | Sp | max z | highest peak |
//! | Sv | −min z | deepest pit, reported positive |
//! | Sz | Sp + Sv | maximum height |
//! | Ssk | mean z³ / Sq³ | skewness |
//! | Sku | mean z⁴ / Sq⁴ | ISO kurtosis (3 for a Gaussian), **not** excess kurtosis |
//! | Sdq | √(mean (∂z/∂x)² + (∂z/∂y)²) | rms gradient; central differences (z[i+1] − z[i−1]) / 2dx on interior nodes |
//! | Sdr | (A_surface − A_projected) / A_projected | developed interfacial area ratio; each cell's area is the mean of its two diagonal triangulations |
//!
//! Profile parameters Ra, Rq, Rp, Rv, Rz, Rsk, Rku are the same formulas on each
//! row (x profiles) or column (y profiles), levelled by the profile's own mean,
//! then averaged over the profiles.

use asperity_core::HeightField;
use serde::Serialize;

use crate::AnalysisError;

/// Areal parameters of a levelled height field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Areal {
    /// Arithmetic mean height.
    pub Sa: f64,
    /// Root-mean-square height.
    pub Sq: f64,
    /// Maximum peak height.
    pub Sp: f64,
    /// Maximum pit depth (positive).
    pub Sv: f64,
    /// Maximum height Sp + Sv.
    pub Sz: f64,
    /// Skewness.
    pub Ssk: f64,
    /// Kurtosis (ISO; 3 for a Gaussian).
    pub Sku: f64,
    /// Root-mean-square gradient (central differences).
    pub Sdq: f64,
    /// Developed interfacial area ratio.
    pub Sdr: f64,
}

/// Profile parameters averaged over all rows or columns.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Profile {
    /// Arithmetic mean deviation.
    pub Ra: f64,
    /// Root-mean-square deviation.
    pub Rq: f64,
    /// Maximum peak height.
    pub Rp: f64,
    /// Maximum valley depth.
    pub Rv: f64,
    /// Maximum height.
    pub Rz: f64,
    /// Skewness.
    pub Rsk: f64,
    /// Kurtosis.
    pub Rku: f64,
}

/// Height moments: (Sa, Sq, Sp, Sv, Ssk, Sku) of already-levelled values.
fn moments(z: impl Iterator<Item = f64> + Clone) -> (f64, f64, f64, f64, f64, f64) {
    let n = z.clone().count() as f64;
    let (mut a, mut q2, mut q3, mut q4) = (0.0, 0.0, 0.0, 0.0);
    let (mut hi, mut lo) = (f64::NEG_INFINITY, f64::INFINITY);
    for v in z {
        a += v.abs();
        let v2 = v * v;
        q2 += v2;
        q3 += v2 * v;
        q4 += v2 * v2;
        hi = hi.max(v);
        lo = lo.min(v);
    }
    let sq = (q2 / n).sqrt();
    (a / n, sq, hi, -lo, q3 / n / sq.powi(3), q4 / n / sq.powi(4))
}

fn check(h: &HeightField) -> Result<(), AnalysisError> {
    h.validate()?;
    if h.nx() < 3 || h.ny() < 3 {
        return Err(AnalysisError::BadInput(format!(
            "a {}×{} grid is too small (need at least 3×3)",
            h.nx(),
            h.ny()
        )));
    }
    let (lo, hi) = h.min_max();
    if hi == lo {
        return Err(AnalysisError::BadInput(
            "the height field is constant: roughness parameters are undefined".into(),
        ));
    }
    Ok(())
}

/// Area of the triangle (a, b, c).
pub(crate) fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let cr = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt()
}

/// Areal parameters of `h`, which should already be levelled.
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN, constant or smaller-than-3×3 fields.
pub fn areal(h: &HeightField) -> Result<Areal, AnalysisError> {
    check(h)?;
    let (sa, sq, sp, sv, ssk, sku) = moments(h.data().iter().copied());
    let [nx, ny] = h.dims();
    let [dx, dy] = h.spacing();
    let z = |i: usize, j: usize| *h.get(i, j);
    let mut g2 = 0.0;
    for j in 1..ny - 1 {
        for i in 1..nx - 1 {
            let gx = (z(i + 1, j) - z(i - 1, j)) / (2.0 * dx);
            let gy = (z(i, j + 1) - z(i, j - 1)) / (2.0 * dy);
            g2 += gx * gx + gy * gy;
        }
    }
    let sdq = (g2 / ((nx - 2) * (ny - 2)) as f64).sqrt();
    let mut area = 0.0;
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let (a, b, c, d) = (
                h.point(i, j),
                h.point(i + 1, j),
                h.point(i + 1, j + 1),
                h.point(i, j + 1),
            );
            area += 0.5
                * (triangle_area(a, b, c)
                    + triangle_area(a, c, d)
                    + triangle_area(a, b, d)
                    + triangle_area(b, c, d));
        }
    }
    let projected = (nx - 1) as f64 * dx * (ny - 1) as f64 * dy;
    Ok(Areal {
        Sa: sa,
        Sq: sq,
        Sp: sp,
        Sv: sv,
        Sz: sp + sv,
        Ssk: ssk,
        Sku: sku,
        Sdq: sdq,
        Sdr: area / projected - 1.0,
    })
}

/// Profile parameters along x (each row) or, with `along_y`, along y (each column).
///
/// # Errors
/// As [`areal`].
pub fn profile(h: &HeightField, along_y: bool) -> Result<Profile, AnalysisError> {
    check(h)?;
    let [nx, ny] = h.dims();
    let profiles: Vec<Vec<f64>> = if along_y {
        (0..nx)
            .map(|i| (0..ny).map(|j| *h.get(i, j)).collect())
            .collect()
    } else {
        (0..ny).map(|j| h.row(j).to_vec()).collect()
    };
    let mut acc = [0.0f64; 7];
    let mut counted = 0.0;
    for p in &profiles {
        let mean = p.iter().sum::<f64>() / p.len() as f64;
        let (ra, rq, rp, rv, rsk, rku) = moments(p.iter().map(|v| v - mean));
        if rq == 0.0 {
            continue; // a flat profile has no shape parameters
        }
        for (a, v) in acc.iter_mut().zip([ra, rq, rp, rv, rp + rv, rsk, rku]) {
            *a += v;
        }
        counted += 1.0;
    }
    if counted == 0.0 {
        return Err(AnalysisError::BadInput("every profile is flat".into()));
    }
    let [ra, rq, rp, rv, rz, rsk, rku] = acc.map(|v| v / counted);
    Ok(Profile {
        Ra: ra,
        Rq: rq,
        Rp: rp,
        Rv: rv,
        Rz: rz,
        Rsk: rsk,
        Rku: rku,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: usize = 256;

    fn field(f: impl Fn(f64, f64) -> f64) -> HeightField {
        HeightField::from_vec(
            [N, N],
            (0..N * N)
                .map(|k| f((k % N) as f64, (k / N) as f64))
                .collect(),
        )
        .unwrap()
    }

    #[test]
    fn exact_fields() {
        let tau = std::f64::consts::TAU;
        let s = areal(&field(|x, _| (tau * x / N as f64).sin())).unwrap();
        assert!((s.Sq - 0.5f64.sqrt()).abs() < 1e-12, "{}", s.Sq);
        assert!((s.Sku - 1.5).abs() < 1e-12, "{}", s.Sku);
        assert!(s.Ssk.abs() < 1e-12);
        assert!(
            (s.Sp - 1.0).abs() < 1e-12 && (s.Sv - 1.0).abs() < 1e-12 && (s.Sz - 2.0).abs() < 1e-12
        );
        // Mean |sin| over whole periods, sampled: (1/N) Σ |sin(2πk/N)| = (2/N) cot(π/N).
        assert!((s.Sa - 2.0 / N as f64 / (std::f64::consts::PI / N as f64).tan()).abs() < 1e-12);
        let s = areal(&field(|x, y| {
            (tau * x / N as f64).sin() * (tau * y / N as f64).sin()
        }))
        .unwrap();
        assert!((s.Sku - 2.25).abs() < 1e-12, "{}", s.Sku);
        assert!((s.Sq - 0.5).abs() < 1e-12);
        let c = areal(&field(|x, y| {
            if (x as usize + y as usize).is_multiple_of(2) {
                1.0
            } else {
                -1.0
            }
        }))
        .unwrap();
        assert!(
            (c.Sq - 1.0).abs() < 1e-12 && (c.Sa - 1.0).abs() < 1e-12 && (c.Sku - 1.0).abs() < 1e-12
        );
        assert_eq!(
            c.Sdq, 0.0,
            "central differences skip the neighbours of a checkerboard"
        );
    }

    #[test]
    fn slopes_and_areas_of_a_plane() {
        // z = 0.75·x on unit spacing: gradient 0.75 everywhere, area ratio √(1 + 0.75²) − 1 = 0.25.
        let p = field(|x, _| 0.75 * x);
        let s = areal(&p).unwrap();
        assert!((s.Sdq - 0.75).abs() < 1e-12);
        assert!((s.Sdr - 0.25).abs() < 1e-12, "{}", s.Sdr);
        let r = profile(&p, false).unwrap();
        assert!((r.Rz - 0.75 * 255.0).abs() < 1e-9);
        assert!(profile(&p, true).is_err(), "columns of z = x are flat");
    }

    #[test]
    fn refusals() {
        assert!(
            areal(&HeightField::filled([8, 8], 2.0))
                .unwrap_err()
                .to_string()
                .contains("constant")
        );
        assert!(
            areal(&HeightField::from_vec([2, 2], vec![0.0, 1.0, 2.0, 3.0]).unwrap())
                .unwrap_err()
                .to_string()
                .contains("too small")
        );
        let mut h = field(|x, _| x);
        *h.get_mut(3, 3) = f64::NAN;
        assert!(areal(&h).is_err());
    }
}
