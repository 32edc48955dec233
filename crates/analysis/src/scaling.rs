//! Growth and cluster scaling: interface-width exponents and cluster fractal
//! dimensions (kim-machiraju-thompson §4; Family–Vicsek scaling; Witten–Sander DLA).
//!
//! - Growth exponent β from W(t) ∝ t^β: a plain log–log fit, and a fit with an
//!   intrinsic width, W² = W_i² + A t^(2β) (W_i² chosen by a scan that maximises
//!   the straightness of log(W² − W_i²) against log t), as BD needs.
//! - Roughness exponent α from the saturated width W_sat ∝ L^α.
//! - Cluster dimension from the radius of gyration of the first n particles,
//!   R_g(n) ∝ n^(1/D), and from the mass within radius r of the particle
//!   nearest the centroid, M(r) ∝ r^D.
//! - For deposits on a plane, the density profile ρ(z) and D from
//!   ρ(z) ∝ z^(D − d).

use serde::Serialize;

use crate::AnalysisError;
use crate::psd::{LogFit, log_fit};

/// β with its fit (and the intrinsic width when fitted).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GrowthFit {
    /// The exponent.
    pub exponent: f64,
    /// Intrinsic width W_i (0 for the plain fit).
    pub intrinsic_width: f64,
    /// The fit.
    pub fit: LogFit,
}

/// Plain log–log fit of W(t) ∝ t^β over `window` (in t).
///
/// # Errors
/// [`AnalysisError::BadInput`] with fewer than 3 points in the window.
pub fn growth_exponent(t: &[f64], w: &[f64], window: [f64; 2]) -> Result<GrowthFit, AnalysisError> {
    let fit = log_fit(t, w, window)?;
    Ok(GrowthFit {
        exponent: fit.slope,
        intrinsic_width: 0.0,
        fit,
    })
}

/// β from W² = W_i² + A t^(2β) by nonlinear least squares on W² itself.
///
/// For each trial β the model is linear in (W_i², A), solved in closed form
/// (with W_i² ≥ 0); β is scanned over [0.005, 1.2] in steps of 0.001 and then
/// refined to 10⁻⁶ by golden-section search around the best step. Fitting W²
/// rather than log(W² − W_i²) keeps the noise of the small late-time
/// differences from pulling W_i² toward zero.
///
/// # Errors
/// As [`growth_exponent`].
pub fn growth_exponent_intrinsic(
    t: &[f64],
    w: &[f64],
    window: [f64; 2],
) -> Result<GrowthFit, AnalysisError> {
    let pts: Vec<(f64, f64)> = t
        .iter()
        .zip(w)
        .filter(|(x, v)| **x >= window[0] && **x <= window[1] && **x > 0.0 && v.is_finite())
        .map(|(x, v)| (*x, v * v))
        .collect();
    if pts.len() < 4 {
        return Err(AnalysisError::BadInput(format!(
            "{} points in the fit window; the intrinsic-width fit needs at least 4",
            pts.len()
        )));
    }
    // Least squares of y = c + A x with x = t^(2β); c clamped at 0.
    let solve = |beta: f64| -> (f64, f64, f64) {
        let n = pts.len() as f64;
        let xs: Vec<f64> = pts.iter().map(|p| p.0.powf(2.0 * beta)).collect();
        let (sx, sy) = (xs.iter().sum::<f64>(), pts.iter().map(|p| p.1).sum::<f64>());
        let sxx: f64 = xs.iter().map(|x| x * x).sum();
        let sxy: f64 = xs.iter().zip(&pts).map(|(x, p)| x * p.1).sum();
        let det = n * sxx - sx * sx;
        let (mut c, mut a) = if det.abs() > 0.0 {
            ((sy * sxx - sx * sxy) / det, (n * sxy - sx * sy) / det)
        } else {
            (0.0, sxy / sxx)
        };
        if c < 0.0 {
            c = 0.0;
            a = sxy / sxx;
        }
        let sse = xs
            .iter()
            .zip(&pts)
            .map(|(x, p)| (p.1 - c - a * x).powi(2))
            .sum::<f64>();
        (sse, c, a)
    };
    let mut best = (f64::INFINITY, 0.005);
    let mut beta = 0.005;
    while beta <= 1.2 {
        let (sse, _, a) = solve(beta);
        if a > 0.0 && sse < best.0 {
            best = (sse, beta);
        }
        beta += 0.001;
    }
    if !best.0.is_finite() {
        return Err(AnalysisError::BadInput(
            "the width does not grow in the fit window".into(),
        ));
    }
    // Golden-section refinement on [β − 0.001, β + 0.001].
    let (mut lo, mut hi) = (best.1 - 0.001, best.1 + 0.001);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    while hi - lo > 1e-6 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if solve(m1).0 < solve(m2).0 {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let beta = 0.5 * (lo + hi);
    let (_, wi2, _) = solve(beta);
    // Report the straightened data as a log–log fit (slope 2β) for plots and r².
    let y: Vec<f64> = w.iter().map(|v| v * v - wi2).collect();
    let fit = log_fit(t, &y, window)?;
    Ok(GrowthFit {
        exponent: beta,
        intrinsic_width: wi2.sqrt(),
        fit,
    })
}

/// α from saturated widths W_sat(L) ∝ L^α.
///
/// # Errors
/// With fewer than 3 sizes.
pub fn roughness_exponent(sizes: &[f64], w_sat: &[f64]) -> Result<LogFit, AnalysisError> {
    log_fit(sizes, w_sat, [0.0, f64::INFINITY])
}

/// A cluster dimension estimate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ClusterDimension {
    /// D.
    pub d: f64,
    /// The fit.
    pub fit: LogFit,
}

fn centroid(p: &[[f64; 3]]) -> [f64; 3] {
    let n = p.len() as f64;
    [0, 1, 2].map(|a| p.iter().map(|q| q[a]).sum::<f64>() / n)
}

/// Radius of gyration of `points`.
pub fn radius_of_gyration(points: &[[f64; 3]]) -> f64 {
    let c = centroid(points);
    (points
        .iter()
        .map(|q| (0..3).map(|a| (q[a] - c[a]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / points.len() as f64)
        .sqrt()
}

/// D from R_g of the first n particles (in deposition order), n over powers of two
/// from 64 to all.
///
/// # Errors
/// [`AnalysisError::BadInput`] for fewer than 256 points.
pub fn gyration_dimension(points: &[[f64; 3]]) -> Result<ClusterDimension, AnalysisError> {
    if points.len() < 256 {
        return Err(AnalysisError::BadInput(format!(
            "{} points are too few for a dimension fit (need ≥ 256)",
            points.len()
        )));
    }
    let ns: Vec<usize> = (6..)
        .map(|k| 1usize << k)
        .take_while(|&n| n <= points.len())
        .collect();
    let rg: Vec<f64> = ns
        .iter()
        .map(|&n| radius_of_gyration(&points[..n]))
        .collect();
    let fit = log_fit(
        &ns.iter().map(|&n| n as f64).collect::<Vec<_>>(),
        &rg,
        [0.0, f64::INFINITY],
    )?;
    Ok(ClusterDimension {
        d: 1.0 / fit.slope,
        fit,
    })
}

/// D from the mass within radius r of the particle nearest the centroid, for r
/// from `r_min` to half the radius of gyration.
///
/// # Errors
/// [`AnalysisError::BadInput`] for fewer than 256 points.
pub fn mass_radius_dimension(
    points: &[[f64; 3]],
    r_min: f64,
) -> Result<ClusterDimension, AnalysisError> {
    if points.len() < 256 {
        return Err(AnalysisError::BadInput(format!(
            "{} points are too few for a dimension fit (need ≥ 256)",
            points.len()
        )));
    }
    // Centre: the particle nearest the centroid (the centroid itself may lie off
    // the cluster, e.g. above a rough sheet).
    let g = centroid(points);
    let dist =
        |q: &[f64; 3], c: &[f64; 3]| (0..3).map(|a| (q[a] - c[a]).powi(2)).sum::<f64>().sqrt();
    let c = *points
        .iter()
        .min_by(|p, q| dist(p, &g).total_cmp(&dist(q, &g)))
        .expect("non-empty");
    let mut d: Vec<f64> = points.iter().map(|q| dist(q, &c)).collect();
    d.sort_by(f64::total_cmp);
    let r_max = 0.5 * radius_of_gyration(points);
    if r_max <= r_min {
        return Err(AnalysisError::BadInput(
            "the cluster is too small for the requested minimum radius".into(),
        ));
    }
    let radii: Vec<f64> = (0..16)
        .map(|k| r_min * (r_max / r_min).powf(k as f64 / 15.0))
        .collect();
    let mass: Vec<f64> = radii
        .iter()
        .map(|&r| d.partition_point(|&x| x <= r) as f64)
        .collect();
    let fit = log_fit(&radii, &mass, [r_min, r_max])?;
    Ok(ClusterDimension { d: fit.slope, fit })
}

/// Density profile of a deposit on a plane: ρ(z) = (cells at height z) / `area`
/// for z = 0 ..= the highest cell (z rounded to integers).
pub fn density_profile(points: &[[f64; 3]], area: f64) -> Vec<f64> {
    let top = points.iter().map(|p| p[2].round()).fold(0.0, f64::max) as usize;
    let mut rho = vec![0.0; top + 1];
    for p in points {
        let z = p[2].round();
        if z >= 0.0 {
            rho[z as usize] += 1.0 / area;
        }
    }
    rho
}

/// D of a deposit grown on a plane from its density profile,
/// ρ(z) ∝ z^(D − d) in the growth zone (Meakin 1983), with d the embedding
/// dimension (3 for a deposit on a plane, 2 on a line). The fit runs from
/// z = 4 to a third of the deposit height, away from the substrate and the
/// sparse active zone.
///
/// # Errors
/// [`AnalysisError::BadInput`] when the deposit is lower than 16 cells.
pub fn density_dimension(rho: &[f64], d: usize) -> Result<ClusterDimension, AnalysisError> {
    let top = rho.len().saturating_sub(1);
    if top < 16 {
        return Err(AnalysisError::BadInput(format!(
            "the deposit is {top} cells high; the density fit needs at least 16"
        )));
    }
    let z: Vec<f64> = (0..rho.len()).map(|k| k as f64).collect();
    let fit = log_fit(&z, rho, [4.0, top as f64 / 3.0])?;
    Ok(ClusterDimension {
        d: d as f64 + fit.slope,
        fit,
    })
}

/// D of a deposit from its pair correlation: the mean number of particles
/// within s of a particle grows as N(s) ∝ s^D (Meakin 1983 measured DLA on
/// fibres and surfaces this way), fitted over every radius given. Unlike the
/// shell density it does not depend on the substrate's shape: it counts the
/// deposit about its own particles, not about the seed.
///
/// # Errors
/// [`AnalysisError::BadInput`] when fewer than 3 radii have a count.
pub fn pair_dimension(
    radius: &[f64],
    neighbours: &[f64],
) -> Result<ClusterDimension, AnalysisError> {
    let (Some(&first), Some(&last)) = (radius.first(), radius.last()) else {
        return Err(AnalysisError::BadInput("no pair radii to fit".into()));
    };
    let fit = log_fit(radius, neighbours, [first, last])?;
    Ok(ClusterDimension { d: fit.slope, fit })
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::seeded;
    use rand::Rng;

    #[test]
    fn exponents_from_synthetic_widths() {
        let t: Vec<f64> = (0..30).map(|k| 2f64.powf(k as f64 * 0.5)).collect();
        let w: Vec<f64> = t.iter().map(|x| 0.7 * x.powf(0.25)).collect();
        assert!((growth_exponent(&t, &w, [1.0, 1e9]).unwrap().exponent - 0.25).abs() < 1e-12);
        // With an intrinsic width the plain fit is biased low; the intrinsic fit is not.
        let w: Vec<f64> = t
            .iter()
            .map(|x| (0.5f64.powi(2) + 0.7 * x.powf(2.0 / 3.0)).sqrt())
            .collect();
        let plain = growth_exponent(&t, &w, [1.0, 1e9]).unwrap().exponent;
        let fit = growth_exponent_intrinsic(&t, &w, [1.0, 1e9]).unwrap();
        assert!((plain - 1.0 / 3.0).abs() > 0.008, "{plain}");
        assert!((fit.exponent - 1.0 / 3.0).abs() < 0.002, "{}", fit.exponent);
        assert!(
            (fit.intrinsic_width - 0.5).abs() < 0.05,
            "{}",
            fit.intrinsic_width
        );
        let a = roughness_exponent(
            &[64.0, 128.0, 256.0, 512.0],
            &[2.0, 2.0 * 2f64.sqrt(), 4.0, 4.0 * 2f64.sqrt()],
        )
        .unwrap();
        assert!((a.slope - 0.5).abs() < 1e-12);
    }

    #[test]
    fn dimensions_of_uniform_clusters() {
        let mut rng = seeded(9);
        let ball: Vec<[f64; 3]> = std::iter::repeat_with(|| {
            [
                rng.random::<f64>() * 2.0 - 1.0,
                rng.random::<f64>() * 2.0 - 1.0,
                rng.random::<f64>() * 2.0 - 1.0,
            ]
        })
        .filter(|p| p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0)
        .take(20_000)
        .collect();
        let disc: Vec<[f64; 3]> = ball.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let m3 = mass_radius_dimension(&ball, 0.15).unwrap().d;
        let m2 = mass_radius_dimension(&disc, 0.15).unwrap().d;
        assert!((m3 - 3.0).abs() < 0.1, "{m3}");
        assert!((m2 - 2.0).abs() < 0.1, "{m2}");
        // A cluster that grows outward: particles sorted by radius (as DLA deposits them).
        let mut grown = ball.clone();
        grown.sort_by(|a, b| {
            (a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
                .total_cmp(&(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]))
        });
        let g = gyration_dimension(&grown).unwrap().d;
        assert!((g - 3.0).abs() < 0.1, "{g}");
        assert!(gyration_dimension(&ball[..10]).is_err());
        // A slab of uniform density: ρ(z) constant, D = d.
        let slab: Vec<[f64; 3]> = (0..40)
            .flat_map(|z| (0..100).map(move |k| [k as f64, 0.0, z as f64]))
            .collect();
        let rho = density_profile(&slab, 100.0);
        assert_eq!(rho.len(), 40);
        assert!(rho.iter().all(|r| (r - 1.0).abs() < 1e-12));
        let d = density_dimension(&rho, 3).unwrap().d;
        assert!((d - 3.0).abs() < 1e-9, "{d}");
        // ρ ∝ z^(−1/2) gives D = 2.5.
        let rho: Vec<f64> = (0..64)
            .map(|z| if z == 0 { 1.0 } else { (z as f64).powf(-0.5) })
            .collect();
        assert!((density_dimension(&rho, 3).unwrap().d - 2.5).abs() < 1e-9);
        assert!(density_dimension(&rho[..10], 3).is_err());
    }
}
