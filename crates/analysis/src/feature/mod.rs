//! ISO 25178-2 feature parameters (ISO 25178-2:2021 clause 5; §4.4 of the
//! 2012 edition): the surface segmented into hills and dales by watershed and
//! Wolf pruning ([`watershed`]), and statistics of the significant motifs.
//!
//! | Parameter | Definition (ISO 25178-2:2021 Table 2 defaults: Wolf pruning at 5 % of Sz, incomplete motifs left out) |
//! | --- | --- |
//! | Spd | density of peaks: significant hills per unit area (1/length²) |
//! | Svd | density of pits: significant dales per unit area |
//! | Spc | arithmetic mean peak curvature: the mean over the peaks of −½(∂²z/∂x² + ∂²z/∂y²), central differences (1/length) |
//! | Svc | the same at the pits (negative for pits) |
//! | S5p | five-point peak height: the mean height of the five highest peaks above the mean plane |
//! | S5v | five-point pit depth: the mean depth of the five deepest pits below the mean plane |
//! | S10z | ten-point height: S5p + S5v |
//! | Sha, Sda | mean hill area, mean dale area: the motifs' projected areas (points × dx·dy) |
//! | Shv, Sdv | mean hill volume, mean dale volume: the volume of a hill above the horizontal plane through its lowest saddle, of a dale below it (Σ max(0, z − saddle)·dx·dy; Leach, *Characterisation of Areal Surface Texture*, 2nd ed., ch. 4) |
//!
//! Heights are those of the (levelled, filtered) scale-limited surface, taken
//! from its mean over the measured points. The area of Spd and Svd is the
//! evaluation area: (nx − 1)·dx × (ny − 1)·dy, or nx·dx × ny·dy for a periodic
//! field (one period). With fewer than five significant peaks S5p is the mean
//! of those found, and `peaks`/`pits` say how many. A parameter of no motif is
//! `None`.

pub mod watershed;

use asperity_core::HeightField;
use serde::Serialize;

use crate::AnalysisError;
pub use watershed::{Heights, Motif, NO_MOTIF, Segmentation};

/// ISO 25178-3's default Wolf pruning threshold: 5 % of Sz.
pub const DEFAULT_PRUNING_PERCENT: f64 = 5.0;

/// How the surface is segmented and which motifs count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureOptions {
    /// Wolf pruning threshold in % of Sz (ISO's default 5).
    pub pruning_percent: f64,
    /// Whether motifs touching the edge or a missing point count (ISO's
    /// default: they do not).
    pub incomplete: bool,
    /// Whether the field wraps (a periodic field has no edge).
    pub periodic: bool,
}

impl Default for FeatureOptions {
    fn default() -> Self {
        Self {
            pruning_percent: DEFAULT_PRUNING_PERCENT,
            incomplete: false,
            periodic: false,
        }
    }
}

/// The feature parameters of a surface (see the module's table).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct FeatureParameters {
    /// Density of peaks (1/length²).
    pub Spd: f64,
    /// Density of pits (1/length²).
    pub Svd: f64,
    /// Arithmetic mean peak curvature (1/length).
    pub Spc: Option<f64>,
    /// Arithmetic mean pit curvature (1/length, negative).
    pub Svc: Option<f64>,
    /// Five-point peak height.
    pub S5p: Option<f64>,
    /// Five-point pit depth.
    pub S5v: Option<f64>,
    /// Ten-point height.
    pub S10z: Option<f64>,
    /// Mean hill area.
    pub Sha: Option<f64>,
    /// Mean dale area.
    pub Sda: Option<f64>,
    /// Mean hill volume.
    pub Shv: Option<f64>,
    /// Mean dale volume.
    pub Sdv: Option<f64>,
    /// Significant hills counted (complete ones unless asked otherwise).
    pub peaks: usize,
    /// Significant dales counted.
    pub pits: usize,
    /// The pruning threshold in height units (the % of Sz).
    pub pruning_height: f64,
}

/// Both segmentations and the parameters read off them.
#[derive(Clone, Debug)]
pub struct Features {
    /// The parameters.
    pub parameters: FeatureParameters,
    /// The hills (a segmentation of the negated surface: its `depth_at` and
    /// `saddle` are negated heights).
    pub hills: Segmentation,
    /// The dales.
    pub dales: Segmentation,
}

/// The feature parameters of `h` (missing points as NaN).
///
/// # Errors
/// [`AnalysisError::BadInput`] for a pruning threshold outside [0, 100] %, a
/// profile (one row), fewer than 3 × 3 points, an infinite height or no
/// measured point.
pub fn features(h: &HeightField, o: &FeatureOptions) -> Result<Features, AnalysisError> {
    if !(0.0..=100.0).contains(&o.pruning_percent) {
        return Err(AnalysisError::BadInput(format!(
            "Wolf pruning at {} % of Sz: it lies in 0 … 100 %",
            o.pruning_percent
        )));
    }
    if h.nx() < 3 || h.ny() < 3 {
        return Err(AnalysisError::BadInput(format!(
            "feature parameters need an areal field of at least 3 × 3 points, not {} × {}",
            h.nx(),
            h.ny()
        )));
    }
    if h.len() >= u32::MAX as usize {
        return Err(AnalysisError::BadInput(format!(
            "feature parameters of {} points: at most 2³² − 1",
            h.len()
        )));
    }
    h.validate_measured()?;
    let measured = h.measured_values();
    if measured.is_empty() {
        return Err(AnalysisError::BadInput("no measured point".into()));
    }
    let mean = measured.iter().sum::<f64>() / measured.len() as f64;
    let (lo, hi) = measured
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| {
            (a.min(*z), b.max(*z))
        });
    let threshold = o.pruning_percent / 100.0 * (hi - lo);
    let z = h.data();
    let (hills, dales) = rayon::join(
        || watershed::dales(h, Heights::hills(z), o.periodic, threshold),
        || watershed::dales(h, Heights::dales(z), o.periodic, threshold),
    );
    let parameters = parameters(h, mean, &hills, &dales, o, threshold);
    Ok(Features {
        parameters,
        hills,
        dales,
    })
}

/// The motifs that count.
fn counted<'a>(s: &'a Segmentation, o: &FeatureOptions) -> Vec<&'a Motif> {
    s.motifs
        .iter()
        .filter(|m| o.incomplete || !m.incomplete)
        .collect()
}

fn parameters(
    h: &HeightField,
    mean_plane: f64,
    hills: &Segmentation,
    dales: &Segmentation,
    o: &FeatureOptions,
    threshold: f64,
) -> FeatureParameters {
    let [dx, dy] = h.spacing();
    let area = if o.periodic {
        h.nx() as f64 * dx * h.ny() as f64 * dy
    } else {
        let [lx, ly] = h.extent();
        lx * ly
    };
    let (peaks, pits) = (counted(hills, o), counted(dales, o));
    let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    let five = |mut v: Vec<f64>| {
        v.sort_by(|a, b| b.total_cmp(a));
        v.truncate(5);
        mean(v)
    };
    let z = h.data();
    let curvature = |m: &[&Motif]| {
        mean(
            m.iter()
                .filter_map(|m| mean_curvature(h, z, m.critical, o.periodic))
                .collect(),
        )
    };
    let (five_peaks, five_pits) = (
        five(peaks.iter().map(|m| z[m.critical] - mean_plane).collect()),
        five(pits.iter().map(|m| mean_plane - z[m.critical]).collect()),
    );
    let cell = dx * dy;
    FeatureParameters {
        Spd: peaks.len() as f64 / area,
        Svd: pits.len() as f64 / area,
        Spc: curvature(&peaks),
        Svc: curvature(&pits),
        S5p: five_peaks,
        S5v: five_pits,
        S10z: five_peaks.zip(five_pits).map(|(p, v)| p + v),
        Sha: mean(peaks.iter().map(|m| m.points as f64 * cell).collect()),
        Sda: mean(pits.iter().map(|m| m.points as f64 * cell).collect()),
        Shv: mean(peaks.iter().map(|m| m.volume * cell).collect()),
        Sdv: mean(pits.iter().map(|m| m.volume * cell).collect()),
        peaks: peaks.len(),
        pits: pits.len(),
        pruning_height: threshold,
    }
}

/// −½(∂²z/∂x² + ∂²z/∂y²) at point `p` by central differences; `None` on the
/// edge of a field that does not wrap or beside a missing point.
fn mean_curvature(h: &HeightField, z: &[f64], p: usize, periodic: bool) -> Option<f64> {
    let (nx, ny) = (h.nx(), h.ny());
    let (i, j) = (p % nx, p / nx);
    let inside = |v: usize, n: usize| periodic || (v > 0 && v + 1 < n);
    if !inside(i, nx) || !inside(j, ny) {
        return None;
    }
    let at = |a: usize, b: usize| z[b * nx + a];
    let (left, right) = ((i + nx - 1) % nx, (i + 1) % nx);
    let (below, above) = ((j + ny - 1) % ny, (j + 1) % ny);
    let [dx, dy] = h.spacing();
    let d2x = (at(left, j) - 2.0 * z[p] + at(right, j)) / (dx * dx);
    let d2y = (at(i, below) - 2.0 * z[p] + at(i, above)) / (dy * dy);
    let c = -0.5 * (d2x + d2y);
    c.is_finite().then_some(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// z = A cos(2πx/λ) cos(2πy/λ) on n × n points of spacing `dx`.
    fn egg_crate(n: usize, period: usize, dx: f64, amplitude: f64) -> HeightField {
        let k = 2.0 * PI / period as f64;
        let data = (0..n * n)
            .map(|p| amplitude * (k * (p % n) as f64).cos() * (k * (p / n) as f64).cos())
            .collect();
        HeightField::from_vec([n, n], data)
            .unwrap()
            .with_spacing([dx, dx])
            .unwrap()
    }

    fn periodic() -> FeatureOptions {
        FeatureOptions {
            periodic: true,
            ..FeatureOptions::default()
        }
    }

    /// The egg crate has two peaks and two pits per period cell, peaks of
    /// height A and curvature A k², each hill holding A λ²/π² above its
    /// saddles at z = 0 over half a cell.
    #[test]
    fn an_egg_crate_gives_its_closed_form_features() {
        let (n, period, dx, a) = (256, 64, 0.5, 2.0);
        let h = egg_crate(n, period, dx, a);
        let f = features(&h, &periodic()).unwrap().parameters;
        let lambda = period as f64 * dx;
        let cells = (n / period).pow(2) as f64;
        assert_eq!((f.peaks, f.pits), (2 * 16, 2 * 16));
        assert!((f.Spd - 2.0 * cells / (n as f64 * dx).powi(2)).abs() < 1e-15);
        assert!((f.Spd - 2.0 / lambda.powi(2)).abs() < 1e-15);
        let k = 2.0 * PI / lambda;
        // the central difference gives A (2 − 2 cos k dx)/dx² per direction
        let discrete = a * (2.0 - 2.0 * (k * dx).cos()) / (dx * dx);
        assert!(
            (f.Spc.unwrap() - discrete).abs() < 1e-9 * discrete,
            "{:?}",
            f.Spc
        );
        assert!((f.Spc.unwrap() - a * k * k).abs() < 2e-3 * a * k * k);
        assert!((f.Svc.unwrap() + discrete).abs() < 1e-9 * discrete);
        assert!((f.S5p.unwrap() - a).abs() < 1e-12 && (f.S5v.unwrap() - a).abs() < 1e-12);
        assert!((f.S10z.unwrap() - 2.0 * a).abs() < 1e-12);
        let volume = a * lambda * lambda / (PI * PI);
        for v in [f.Shv.unwrap(), f.Sdv.unwrap()] {
            assert!((v - volume).abs() < 2e-3 * volume, "volume {v} vs {volume}");
        }
        for area in [f.Sha.unwrap(), f.Sda.unwrap()] {
            assert!((area - lambda * lambda / 2.0).abs() < 1e-12, "area {area}");
        }
        assert!((f.pruning_height - 0.05 * 2.0 * a).abs() < 1e-12);
    }

    /// N separated Gaussian bumps at random places on a periodic field: Spd
    /// is N over the area exactly, and the five highest bumps give S5p.
    #[test]
    fn separated_bumps_give_their_count_per_area() {
        let (n, sigma, amplitude) = (256usize, 3.0, 1.0);
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(0xb0b5);
        let mut centres: Vec<[f64; 2]> = Vec::new();
        let wrap = |d: f64| d - n as f64 * (d / n as f64).round();
        while centres.len() < 40 {
            let c = [
                rng.random::<f64>() * n as f64,
                rng.random::<f64>() * n as f64,
            ];
            if centres
                .iter()
                .all(|o| wrap(o[0] - c[0]).hypot(wrap(o[1] - c[1])) > 8.0 * sigma)
            {
                centres.push(c);
            }
        }
        let heights: Vec<f64> = (0..centres.len())
            .map(|k| amplitude * (1.0 + 0.01 * k as f64))
            .collect();
        let data = (0..n * n)
            .map(|p| {
                let (x, y) = ((p % n) as f64, (p / n) as f64);
                centres
                    .iter()
                    .zip(&heights)
                    .map(|(c, a)| {
                        a * (-(wrap(x - c[0]).powi(2) + wrap(y - c[1]).powi(2))
                            / (2.0 * sigma * sigma))
                            .exp()
                    })
                    .sum()
            })
            .collect();
        let h = HeightField::from_vec([n, n], data)
            .unwrap()
            .with_spacing([0.1, 0.1])
            .unwrap();
        let f = features(&h, &periodic()).unwrap();
        assert_eq!(f.parameters.peaks, centres.len());
        assert_eq!(f.parameters.Spd, centres.len() as f64 / (25.6 * 25.6));
        // each peak lies on the grid point nearest its centre
        for m in &f.hills.motifs {
            let (i, j) = ((m.critical % n) as f64, (m.critical / n) as f64);
            assert!(
                centres
                    .iter()
                    .any(|c| wrap(i - c[0]).hypot(wrap(j - c[1])) < 1.0)
            );
        }
    }

    /// Motifs touching the edge are left out unless asked for; a field with
    /// holes segments around them, and the result does not depend on the
    /// thread count.
    #[test]
    fn edges_holes_and_threads() {
        // the egg crate sampled from x = y = 8 (between a peak and a pit): its
        // peaks lie at 8 + 16 m, those at m = 1 … 6 in both directions (with
        // m + m' even) have diamonds of half-width 16 clear of the edges
        let (n, k) = (130usize, 2.0 * PI / 32.0);
        let data = (0..n * n)
            .map(|p| (k * ((p % n) + 8) as f64).cos() * (k * ((p / n) + 8) as f64).cos())
            .collect();
        let h = HeightField::from_vec([n, n], data).unwrap();
        let open = features(&h, &FeatureOptions::default()).unwrap().parameters;
        assert_eq!(open.peaks, 18, "{open:?}");
        let all = FeatureOptions {
            incomplete: true,
            ..FeatureOptions::default()
        };
        assert!(features(&h, &all).unwrap().parameters.peaks >= 32);
        let peak = 40 * n + 40;
        let mut holed = h.data().to_vec();
        for p in [peak, peak + 1, peak + n] {
            holed[p] = f64::NAN;
        }
        let hole = h.with_data(holed).unwrap();
        let with_hole = features(&hole, &FeatureOptions::default()).unwrap();
        // the peak at (40, 40) now borders missing points
        assert_eq!(with_hole.parameters.peaks, 17);
        assert_eq!(with_hole.hills.labels[peak], NO_MOTIF);
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let single = one.install(|| features(&hole, &FeatureOptions::default()).unwrap());
        assert_eq!(single.hills.labels, with_hole.hills.labels);
        assert_eq!(single.parameters, with_hole.parameters);
    }

    /// Pruning merges the shallower of two dales into the deeper: a bowl
    /// (pit 0, Sz ≈ 2.05) with a dimple (pit −0.05) beside a saddle at 0.091,
    /// so the bowl's local depth is 4.4 % of Sz and the dimple's 6.9 %.
    #[test]
    fn wolf_pruning_merges_shallow_dales() {
        let n = 41;
        let data = (0..n * n)
            .map(|p| {
                let (x, y) = ((p % n) as f64 - 20.0, (p / n) as f64 - 20.0);
                let bowl = (x * x + y * y) / 400.0;
                bowl - 0.3 * (-((x - 10.0).powi(2) + y * y) / 4.0).exp()
            })
            .collect();
        let h = HeightField::from_vec([n, n], data).unwrap();
        let pits = |pruning_percent| {
            let o = FeatureOptions {
                pruning_percent,
                incomplete: true,
                periodic: false,
            };
            let d = features(&h, &o).unwrap().dales;
            d.motifs.iter().map(|m| m.critical).collect::<Vec<_>>()
        };
        let (centre, dimple) = (20 * n + 20, 20 * n + 30);
        assert_eq!(pits(0.0), [centre, dimple]);
        assert_eq!(pits(4.0), [centre, dimple]);
        assert_eq!(pits(5.0), [dimple]);
        assert_eq!(pits(7.0), [dimple]);
        assert!(
            features(
                &h,
                &FeatureOptions {
                    pruning_percent: 101.0,
                    ..FeatureOptions::default()
                }
            )
            .is_err()
        );
    }
}
