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
//! | Sdq | √(mean (∂z/∂x)² + (∂z/∂y)²) | rms gradient |
//! | Sdr | mean (√(1 + (∂z/∂x)² + (∂z/∂y)²) − 1) | developed interfacial area ratio (ISO 25178-2 §4.3.2, the gradient form) |
//!
//! The gradient is SurfaceTopography's (`derivative(1)`, `rms_gradient`): forward
//! differences `(z[i+1] − z[i]) / dx` and `(z[j+1] − z[j]) / dy`, wrapping around
//! on periodic data and, on non-periodic data, over the (nx − 1) × (ny − 1)
//! nodes that have both forward neighbours — so Sdq and Sdr equal
//! SurfaceTopography's for the same levelling to rounding.
//!
//! Profile parameters Ra, Rq, Rp, Rv, Rz, Rsk, Rku are the same formulas on each
//! row (x profiles) or column (y profiles), levelled by the profile's own mean,
//! then averaged over the profiles.

use asperity_core::HeightField;
use serde::Serialize;

use crate::AnalysisError;
use crate::lines::{LINES_PER_TASK, fold_lines, fold_range};
use crate::profile_elements;

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
    /// Root-mean-square slope (forward differences; wrapped round a periodic
    /// profile, else over its n − 1 steps, as SurfaceTopography's
    /// `rms_slope_from_profile`).
    pub Rdq: f64,
    /// Mean width of the profile elements (ISO 21920-2; see
    /// [`crate::profile_elements`]), over the profiles that have one.
    pub Rsm: Option<f64>,
    /// Mean height of the profile elements, likewise.
    pub Rc: Option<f64>,
}

/// Σ|z|, Σz², Σz³, Σz⁴, max and min of `z`.
fn moment_sums(z: &[f64]) -> [f64; 6] {
    let mut s = [0.0, 0.0, 0.0, 0.0, f64::NEG_INFINITY, f64::INFINITY];
    for &v in z {
        let v2 = v * v;
        s[0] += v.abs();
        s[1] += v2;
        s[2] += v2 * v;
        s[3] += v2 * v2;
        s[4] = s[4].max(v);
        s[5] = s[5].min(v);
    }
    s
}

/// Height moments (Sa, Sq, Sp, Sv, Ssk, Sku) of `n` already-levelled values
/// from their [`moment_sums`].
fn moments([a, q2, q3, q4, hi, lo]: [f64; 6], n: usize) -> (f64, f64, f64, f64, f64, f64) {
    let n = n as f64;
    let sq = (q2 / n).sqrt();
    (a / n, sq, hi, -lo, q3 / n / sq.powi(3), q4 / n / sq.powi(4))
}

/// The height parameters of a field with missing points, over its measured
/// points alone (the amplitude parameters of ISO 25178-2 §4.1 are means over
/// the evaluation area, which here is the measured part; SurfaceTopography's
/// `rms_height_from_area` of a masked topography is the same Sq).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct MeasuredHeights {
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
    /// Kurtosis.
    pub Sku: f64,
    /// Measured points.
    pub points: usize,
}

/// [`MeasuredHeights`] of an already-levelled field, its NaN heights left out.
///
/// # Errors
/// [`AnalysisError::Core`] for an infinite height or no measured point.
pub fn measured_heights(h: &HeightField) -> Result<MeasuredHeights, AnalysisError> {
    h.validate_measured()?;
    let z = h.measured_values();
    let (sa, sq, sp, sv, ssk, sku) = moments(field_moment_sums(&z), z.len());
    Ok(MeasuredHeights {
        Sa: sa,
        Sq: sq,
        Sp: sp,
        Sv: sv,
        Sz: sp + sv,
        Ssk: ssk,
        Sku: sku,
        points: z.len(),
    })
}

/// [`moment_sums`] of a whole field: per task of a fixed size, then in order.
fn field_moment_sums(z: &[f64]) -> [f64; 6] {
    let parts = fold_range(
        z.len(),
        1 << 16,
        || [0.0; 6],
        |s, r| *s = moment_sums(&z[r]),
    );
    parts.iter().fold(
        [0.0, 0.0, 0.0, 0.0, f64::NEG_INFINITY, f64::INFINITY],
        |t, p| {
            [
                t[0] + p[0],
                t[1] + p[1],
                t[2] + p[2],
                t[3] + p[3],
                t[4].max(p[4]),
                t[5].min(p[5]),
            ]
        },
    )
}

/// Refuses NaN, constant fields and grids under `min` samples a side.
fn check(h: &HeightField, [min_x, min_y]: [usize; 2]) -> Result<(), AnalysisError> {
    h.validate()?;
    if h.nx() < min_x || h.ny() < min_y {
        return Err(AnalysisError::BadInput(format!(
            "a {}×{} grid is too small (need at least {min_x}×{min_y})",
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

/// Areal parameters of `h`, which should already be levelled; `periodic`
/// chooses the gradient's differences (see the module docs).
///
/// # Errors
/// [`AnalysisError::BadInput`] for NaN, constant or smaller-than-3×3 fields.
pub fn areal(h: &HeightField, periodic: bool) -> Result<Areal, AnalysisError> {
    check(h, [3, 3])?;
    let (sa, sq, sp, sv, ssk, sku) = moments(field_moment_sums(h.data()), h.data().len());
    let [nx, ny] = h.dims();
    let [dx, dy] = h.spacing();
    let (mx, my) = if periodic { (nx, ny) } else { (nx - 1, ny - 1) };
    // Σ|∇z|² and Σ(√(1 + |∇z|²) − 1), per task of rows, then in order.
    let parts = fold_range(
        my,
        LINES_PER_TASK,
        || [0.0; 2],
        |s, rows| {
            for j in rows {
                let (row, next) = (h.row(j), h.row((j + 1) % ny));
                let mut add = |i: usize, right: f64| {
                    let gx = (right - row[i]) / dx;
                    let gy = (next[i] - row[i]) / dy;
                    let g = gx * gx + gy * gy;
                    s[0] += g;
                    // √(1 + g) − 1 without cancellation for small slopes.
                    s[1] += g / ((1.0 + g).sqrt() + 1.0);
                };
                (0..nx - 1).for_each(|i| add(i, row[i + 1]));
                if mx == nx {
                    add(nx - 1, row[0]);
                }
            }
        },
    );
    let [g2, area] = parts
        .iter()
        .fold([0.0, 0.0], |t, p| [t[0] + p[0], t[1] + p[1]]);
    let nodes = (mx * my) as f64;
    Ok(Areal {
        Sa: sa,
        Sq: sq,
        Sp: sp,
        Sv: sv,
        Sz: sp + sv,
        Ssk: ssk,
        Sku: sku,
        Sdq: (g2 / nodes).sqrt(),
        Sdr: area / nodes,
    })
}

/// Profile parameters (ISO 4287) along x (each row) or, with `along_y`, along y
/// (each column), averaged over the profiles; `periodic` wraps the slope's
/// differences round each profile.
///
/// # Errors
/// As [`areal`].
pub fn profile(h: &HeightField, along_y: bool, periodic: bool) -> Result<Profile, AnalysisError> {
    check(h, if along_y { [1, 3] } else { [3, 1] })?;
    let step = h.spacing()[usize::from(along_y)];
    // Per task of profiles: the sums of (Ra, Rq, Rp, Rv, Rz, Rsk, Rku, Rdq)
    // and how many profiles were not flat; then the tasks in order.
    let parts = fold_lines(
        h,
        along_y,
        || ([0.0f64; 8], 0.0, [0.0f64; 3]),
        |(acc, counted, elements), p| {
            if let Some((rsm, rc)) = profile_elements::mean_width_and_height(p, step) {
                *elements = [elements[0] + rsm, elements[1] + rc, elements[2] + 1.0];
            }
            let mean = p.iter().sum::<f64>() / p.len() as f64;
            let centred: Vec<f64> = p.iter().map(|v| v - mean).collect();
            let (ra, rq, rp, rv, rsk, rku) = moments(moment_sums(&centred), centred.len());
            if rq == 0.0 {
                return; // a flat profile has no shape parameters
            }
            let wrap = if periodic { p[0] - p[p.len() - 1] } else { 0.0 };
            let steps = p.len() - 1 + usize::from(periodic);
            let squares = p.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>() + wrap * wrap;
            let rdq = (squares / steps.max(1) as f64).sqrt() / step;
            for (a, v) in acc.iter_mut().zip([ra, rq, rp, rv, rp + rv, rsk, rku, rdq]) {
                *a += v;
            }
            *counted += 1.0;
        },
    );
    let (acc, counted, elements) = parts.iter().fold(
        ([0.0f64; 8], 0.0, [0.0f64; 3]),
        |(mut t, c, mut e), (p, n, pe)| {
            t.iter_mut().zip(p).for_each(|(t, p)| *t += p);
            e.iter_mut().zip(pe).for_each(|(e, p)| *e += p);
            (t, c + n, e)
        },
    );
    let with_elements = (elements[2] > 0.0).then_some(elements[2]);
    if counted == 0.0 {
        return Err(AnalysisError::BadInput("every profile is flat".into()));
    }
    let [ra, rq, rp, rv, rz, rsk, rku, rdq] = acc.map(|v| v / counted);
    Ok(Profile {
        Ra: ra,
        Rq: rq,
        Rp: rp,
        Rv: rv,
        Rz: rz,
        Rsk: rsk,
        Rku: rku,
        Rdq: rdq,
        Rsm: with_elements.map(|n| elements[0] / n),
        Rc: with_elements.map(|n| elements[1] / n),
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
        let s = areal(&field(|x, _| (tau * x / N as f64).sin()), true).unwrap();
        assert!((s.Sq - 0.5f64.sqrt()).abs() < 1e-12, "{}", s.Sq);
        // Forward differences of sin θi: 2 sin(θ/2) cos(θ(i + ½)), rms √2 sin(π/N).
        let d = 2.0 * (std::f64::consts::PI / N as f64).sin();
        assert!((s.Sdq - d * 0.5f64.sqrt()).abs() < 1e-12, "{}", s.Sdq);
        assert!((s.Sku - 1.5).abs() < 1e-12, "{}", s.Sku);
        assert!(s.Ssk.abs() < 1e-12);
        assert!(
            (s.Sp - 1.0).abs() < 1e-12 && (s.Sv - 1.0).abs() < 1e-12 && (s.Sz - 2.0).abs() < 1e-12
        );
        // Mean |sin| over whole periods, sampled: (1/N) Σ |sin(2πk/N)| = (2/N) cot(π/N).
        assert!((s.Sa - 2.0 / N as f64 / (std::f64::consts::PI / N as f64).tan()).abs() < 1e-12);
        let s = areal(
            &field(|x, y| (tau * x / N as f64).sin() * (tau * y / N as f64).sin()),
            true,
        )
        .unwrap();
        assert!((s.Sku - 2.25).abs() < 1e-12, "{}", s.Sku);
        assert!((s.Sq - 0.5).abs() < 1e-12);
        let c = areal(
            &field(|x, y| {
                if (x as usize + y as usize).is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                }
            }),
            true,
        )
        .unwrap();
        assert!(
            (c.Sq - 1.0).abs() < 1e-12 && (c.Sa - 1.0).abs() < 1e-12 && (c.Sku - 1.0).abs() < 1e-12
        );
        // Every forward difference of a ±1 checkerboard is ±2: |∇z|² = 8.
        assert!((c.Sdq - 8f64.sqrt()).abs() < 1e-12, "{}", c.Sdq);
        assert!((c.Sdr - 2.0).abs() < 1e-12, "√9 − 1 = 2: {}", c.Sdr);
    }

    #[test]
    fn slopes_and_areas_of_a_plane() {
        // z = 0.75·x on unit spacing: gradient 0.75 everywhere, area ratio √(1 + 0.75²) − 1 = 0.25.
        let p = field(|x, _| 0.75 * x);
        let s = areal(&p, false).unwrap();
        assert!((s.Sdq - 0.75).abs() < 1e-12);
        assert!((s.Sdr - 0.25).abs() < 1e-12, "{}", s.Sdr);
        let r = profile(&p, false, false).unwrap();
        assert!((r.Rz - 0.75 * 255.0).abs() < 1e-9);
        assert!((r.Rdq - 0.75).abs() < 1e-12, "{}", r.Rdq);
        // Wrapped, the ramp's one jump back of 0.75·255 joins the 255 steps of 0.75.
        let wrapped = profile(&p, false, true).unwrap();
        let expected = (0.75f64.powi(2) * (255.0 + 255.0f64.powi(2)) / 256.0).sqrt();
        assert!((wrapped.Rdq - expected).abs() < 1e-9, "{}", wrapped.Rdq);
        assert!(
            profile(&p, true, false).is_err(),
            "columns of z = x are flat"
        );
        // A single row is a profile (a line scan).
        let line = HeightField::from_vec([5, 1], vec![0.0, 1.0, 0.0, -1.0, 0.0]).unwrap();
        assert!((profile(&line, false, false).unwrap().Rdq - 1.0).abs() < 1e-12);
    }

    #[test]
    fn refusals() {
        assert!(
            areal(&HeightField::filled([8, 8], 2.0), false)
                .unwrap_err()
                .to_string()
                .contains("constant")
        );
        assert!(
            areal(
                &HeightField::from_vec([2, 2], vec![0.0, 1.0, 2.0, 3.0]).unwrap(),
                false
            )
            .unwrap_err()
            .to_string()
            .contains("too small")
        );
        let mut h = field(|x, _| x);
        *h.get_mut(3, 3) = f64::NAN;
        assert!(areal(&h, false).is_err());
    }
}
