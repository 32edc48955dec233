//! ISO 25178-2 functional parameters (§4.5 and Annex B): the areal material
//! ratio curve and what is read off it. On a profile (one row) the same
//! numbers are ISO 21920-2's (ISO 13565-2's) Rmr, Rmc, Rk, Rpk, Rvk, Rmr1,
//! Rmr2.
//!
//! **The curve.** With the N measured heights sorted from the highest,
//! h₀ ≥ h₁ ≥ … ≥ h_{N−1}, the inverse areal material ratio Smc(mr) is the
//! piecewise-linear curve through (100 · k/(N − 1) %, h_k): the empirical
//! (1 − mr/100) quantile, the same interpolation as numpy's default
//! `quantile`, on which surfalize samples its curve. Smr(c), the areal
//! material ratio at height c (§4.5.1), is its inverse: 0 % above the highest
//! point, 100 % below the lowest. Heights are those of the (levelled,
//! filtered) surface; c is in the same frame.
//!
//! | Parameter | Definition |
//! | --- | --- |
//! | Smr(c), Smc(mr) | the curve and its inverse (§4.5.1, §4.5.2) |
//! | Sxp | Smc(2.5 %) − Smc(50 %): the peak extreme height (ISO 25178-3 defaults p, q) |
//! | Vm(p) | material volume per unit area at p: (1/100 %) ∫₀ᵖ (Smc(q) − Smc(p)) dq (§4.5.3) |
//! | Vv(p) | void volume per unit area at p: (1/100 %) ∫ₚ¹⁰⁰ (Smc(p) − Smc(q)) dq (§4.5.4) |
//! | Vmp, Vmc | Vm(10 %); Vm(80 %) − Vm(10 %) |
//! | Vvv, Vvc | Vv(80 %); Vv(10 %) − Vv(80 %) |
//! | Sk | core height: the equivalent straight line between 0 % and 100 % (Annex B.1) |
//! | Smr1, Smr2 | the material ratios where the line's ends cut the curve (ISO 25178-2:2021's Smrk1, Smrk2) |
//! | Spk, Svk | reduced peak height 2·A₁/Smr1, reduced dale height 2·A₂/(100 % − Smr2), A₁ and A₂ the areas of the curve beyond the core |
//! | Spkx, Svkx | the highest point above the core, the lowest below it |
//!
//! **The equivalent straight line** (ISO 13565-2 §4.3, ISO 25178-2 B.1): the
//! 40 % wide secant of the curve with the least gradient locates the central
//! region (searched at every 0.01 % of its start, the first of equal
//! gradients kept), and the line is the least-squares fit of the curve over
//! that region (sampled every 0.01 %). Volumes are in the height unit (a
//! volume per unit area: µm³/µm² = ml/m² for heights in µm).

use asperity_core::HeightField;
use rayon::prelude::*;
use serde::Serialize;

use crate::AnalysisError;

/// The width of the equivalent straight line's window, in % (ISO 13565-2).
pub const CORE_WINDOW: f64 = 40.0;

/// The step, in %, at which the secant's start and the fit's samples are taken.
const STEP: f64 = 0.01;

/// The inverse areal material ratio curve of a set of heights.
#[derive(Clone, Debug)]
pub struct MaterialRatioCurve {
    /// The heights from the highest.
    descending: Vec<f64>,
    /// ∫₀^{mr_k} Smc(q) dq at the nodes mr_k = 100 k/(N − 1).
    cumulative: Vec<f64>,
}

impl MaterialRatioCurve {
    /// The curve of the measured points of `h`.
    ///
    /// # Errors
    /// [`AnalysisError::BadInput`] with fewer than two measured points or an
    /// infinite height.
    pub fn of(h: &HeightField) -> Result<Self, AnalysisError> {
        h.validate_measured()?;
        Self::from_heights(h.measured_values())
    }

    /// The curve of `heights` (finite values).
    ///
    /// # Errors
    /// [`AnalysisError::BadInput`] with fewer than two heights, or a
    /// height that is not finite.
    pub fn from_heights(mut heights: Vec<f64>) -> Result<Self, AnalysisError> {
        if heights.len() < 2 || heights.iter().any(|z| !z.is_finite()) {
            return Err(AnalysisError::BadInput(
                "the material ratio curve needs at least two finite heights".into(),
            ));
        }
        heights.par_sort_unstable_by(|a, b| b.total_cmp(a));
        let step = 100.0 / (heights.len() - 1) as f64;
        let mut cumulative = Vec::with_capacity(heights.len());
        let mut sum = 0.0;
        cumulative.push(0.0);
        for w in heights.windows(2) {
            sum += 0.5 * (w[0] + w[1]) * step;
            cumulative.push(sum);
        }
        Ok(Self {
            descending: heights,
            cumulative,
        })
    }

    fn last(&self) -> usize {
        self.descending.len() - 1
    }

    /// The node at or below `mr` and the fraction beyond it.
    fn locate(&self, mr: f64) -> (usize, f64) {
        let t = (mr.clamp(0.0, 100.0) / 100.0) * self.last() as f64;
        let k = (t.floor() as usize).min(self.last() - 1);
        (k, t - k as f64)
    }

    /// Smc(mr): the height at which the material ratio is `mr` %.
    pub fn height_at(&self, mr: f64) -> f64 {
        let (k, f) = self.locate(mr);
        let h = &self.descending;
        h[k] + f * (h[k + 1] - h[k])
    }

    /// Smr(c): the material ratio, in %, at height `c`.
    pub fn ratio_at(&self, c: f64) -> f64 {
        let h = &self.descending;
        if c >= h[0] {
            return 0.0;
        }
        if c <= h[self.last()] {
            return 100.0;
        }
        // the last node at or above c: h[k] ≥ c > h[k + 1]
        let k = h.partition_point(|&z| z >= c) - 1;
        let t = k as f64 + (h[k] - c) / (h[k] - h[k + 1]);
        100.0 * t / self.last() as f64
    }

    /// ∫₀^mr Smc(q) dq.
    fn integral(&self, mr: f64) -> f64 {
        let mr = mr.clamp(0.0, 100.0);
        let (k, _) = self.locate(mr);
        let at = 100.0 * k as f64 / self.last() as f64;
        self.cumulative[k] + (mr - at) * 0.5 * (self.descending[k] + self.height_at(mr))
    }

    /// Vm(p): the material volume per unit area at `p` %.
    pub fn material_volume(&self, p: f64) -> f64 {
        (self.integral(p) - p * self.height_at(p)) / 100.0
    }

    /// Vv(p): the void volume per unit area at `p` %.
    pub fn void_volume(&self, p: f64) -> f64 {
        ((100.0 - p) * self.height_at(p) - (self.integral(100.0) - self.integral(p))) / 100.0
    }

    /// The curve sampled at `n` material ratios from 0 to 100 % (for plots).
    pub fn samples(&self, n: usize) -> Vec<[f64; 2]> {
        let n = n.max(2);
        (0..n)
            .map(|k| {
                let mr = 100.0 * k as f64 / (n - 1) as f64;
                [mr, self.height_at(mr)]
            })
            .collect()
    }

    /// The core of the curve: the equivalent straight line and the Sk family.
    pub fn core(&self) -> Core {
        core_of(
            |mr| self.height_at(mr),
            |c| self.ratio_at(c),
            |mr| self.integral(mr),
            [self.descending[0], self.descending[self.last()]],
        )
    }
}

/// The Sk family (ISO 25178-2 Annex B; ISO 13565-2 on a profile).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Core {
    /// Core height.
    pub Sk: f64,
    /// Reduced peak height.
    pub Spk: f64,
    /// Reduced dale height.
    pub Svk: f64,
    /// Material ratio of the peaks, %.
    pub Smr1: f64,
    /// Material ratio of the dales, %.
    pub Smr2: f64,
    /// Highest point above the core (0 when the core's top is above it).
    pub Spkx: f64,
    /// Lowest point below the core (0 when the core's bottom is below it).
    pub Svkx: f64,
    /// The peak area A₁ (%·height).
    pub Sak1: f64,
    /// The dale area A₂ (%·height).
    pub Sak2: f64,
    /// The equivalent line's height at 0 % (the core's top).
    pub line_top: f64,
    /// The equivalent line's height at 100 % (the core's bottom).
    pub line_bottom: f64,
    /// Where the 40 % window starts, %.
    pub window_start: f64,
}

/// The Sk construction on any inverse material ratio curve `smc`, given its
/// inverse `smr`, its integral from 0 and its extreme heights (the exact
/// curve of a known distribution goes through here as the measured one does).
pub(crate) fn core_of(
    smc: impl Fn(f64) -> f64,
    smr: impl Fn(f64) -> f64,
    integral: impl Fn(f64) -> f64,
    [top, bottom]: [f64; 2],
) -> Core {
    let start = least_gradient_window(&smc);
    let (line_top, line_bottom) = equivalent_line(&smc, start);
    let smr1 = smr(line_top);
    let smr2 = smr(line_bottom);
    let a1 = (integral(smr1) - smr1 * line_top).max(0.0);
    let a2 = ((100.0 - smr2) * line_bottom - (integral(100.0) - integral(smr2))).max(0.0);
    Core {
        Sk: line_top - line_bottom,
        Spk: if a1 > 0.0 { 2.0 * a1 / smr1 } else { 0.0 },
        Svk: if a2 > 0.0 {
            2.0 * a2 / (100.0 - smr2)
        } else {
            0.0
        },
        Smr1: smr1,
        Smr2: smr2,
        Spkx: (top - line_top).max(0.0),
        Svkx: (line_bottom - bottom).max(0.0),
        Sak1: a1,
        Sak2: a2,
        line_top,
        line_bottom,
        window_start: start,
    }
}

/// Where the 40 % secant of least gradient starts: the largest (least
/// negative) slope over starts every [`STEP`], the first of equal ones kept.
fn least_gradient_window(smc: &impl Fn(f64) -> f64) -> f64 {
    let starts = ((100.0 - CORE_WINDOW) / STEP).round() as usize;
    let mut best = (0.0, f64::NEG_INFINITY);
    for k in 0..=starts {
        let s = k as f64 * STEP;
        let slope = (smc(s + CORE_WINDOW) - smc(s)) / CORE_WINDOW;
        if slope > best.1 {
            best = (s, slope);
        }
    }
    best.0
}

/// The least-squares line through the curve over the window from `start`
/// (sampled every [`STEP`]): its heights at 0 % and 100 %.
fn equivalent_line(smc: &impl Fn(f64) -> f64, start: f64) -> (f64, f64) {
    let samples = (CORE_WINDOW / STEP).round() as usize;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for k in 0..=samples {
        let x = start + k as f64 * STEP;
        let y = smc(x);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    let n = (samples + 1) as f64;
    let slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let top = (sy - slope * sx) / n;
    (top, top + slope * 100.0)
}

/// The functional parameters at ISO 25178-3's default ratios.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct Functional {
    /// Peak extreme height Smc(2.5 %) − Smc(50 %).
    pub Sxp: f64,
    /// Peak material volume Vm(10 %).
    pub Vmp: f64,
    /// Core material volume Vm(80 %) − Vm(10 %).
    pub Vmc: f64,
    /// Core void volume Vv(10 %) − Vv(80 %).
    pub Vvc: f64,
    /// Dale void volume Vv(80 %).
    pub Vvv: f64,
    /// The Sk family.
    #[serde(flatten)]
    pub core: Core,
}

impl Functional {
    /// The parameters of a curve.
    pub fn of(curve: &MaterialRatioCurve) -> Self {
        Self {
            Sxp: curve.height_at(2.5) - curve.height_at(50.0),
            Vmp: curve.material_volume(10.0),
            Vmc: curve.material_volume(80.0) - curve.material_volume(10.0),
            Vvc: curve.void_volume(10.0) - curve.void_volume(80.0),
            Vvv: curve.void_volume(80.0),
            core: curve.core(),
        }
    }
}

/// The functional parameters of the measured points of `h`.
///
/// # Errors
/// As [`MaterialRatioCurve::of`].
pub fn functional(h: &HeightField) -> Result<Functional, AnalysisError> {
    Ok(Functional::of(&MaterialRatioCurve::of(h)?))
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    /// A two-component normal mixture: a plateau (weight w) over deep valleys.
    struct Mixture {
        w: f64,
        plateau: (f64, f64),
        valleys: (f64, f64),
    }

    fn phi(x: f64) -> f64 {
        (-0.5 * x * x).exp() / (2.0 * PI).sqrt()
    }

    /// P(Z > x) for a standard normal.
    fn upper_tail(x: f64) -> f64 {
        0.5 * libm::erfc(x / std::f64::consts::SQRT_2)
    }

    impl Mixture {
        fn parts(&self) -> [(f64, f64, f64); 2] {
            [
                (self.w, self.plateau.0, self.plateau.1),
                (1.0 - self.w, self.valleys.0, self.valleys.1),
            ]
        }

        /// P(z ≥ c), in %.
        fn ratio(&self, c: f64) -> f64 {
            100.0
                * self
                    .parts()
                    .iter()
                    .map(|(w, m, s)| w * upper_tail((c - m) / s))
                    .sum::<f64>()
        }

        /// The height where the ratio is `mr` % (bisection).
        fn height(&self, mr: f64) -> f64 {
            if mr <= 0.0 {
                return f64::INFINITY;
            }
            if mr >= 100.0 {
                return f64::NEG_INFINITY;
            }
            let (mut lo, mut hi) = (-50.0, 50.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if self.ratio(mid) > mr {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            0.5 * (lo + hi)
        }

        /// ∫₀^mr Smc(q) dq = 100 ∫_{Smc(mr)}^∞ z f(z) dz, in closed form.
        fn integral(&self, mr: f64) -> f64 {
            let a = self.height(mr);
            100.0
                * self
                    .parts()
                    .iter()
                    .map(|(w, m, s)| {
                        if a == f64::NEG_INFINITY {
                            return w * m;
                        }
                        let t = (a - m) / s;
                        w * (m * upper_tail(t) + s * phi(t))
                    })
                    .sum::<f64>()
        }

        fn sample(&self, rng: &mut StdRng) -> f64 {
            let (m, s) = if rng.random::<f64>() < self.w {
                self.plateau
            } else {
                self.valleys
            };
            // Box–Muller
            let (u, v): (f64, f64) = (1.0 - rng.random::<f64>(), rng.random());
            m + s * (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
        }
    }

    #[test]
    fn the_sk_family_of_a_plateau_honed_surface_is_its_distributions() {
        let mix = Mixture {
            w: 0.85,
            plateau: (0.0, 0.3),
            valleys: (-2.0, 0.8),
        };
        let exact = core_of(
            |mr| mix.height(mr),
            |c| mix.ratio(c),
            |mr| mix.integral(mr),
            [f64::INFINITY, f64::NEG_INFINITY],
        );
        let mut rng = StdRng::seed_from_u64(rand::random());
        let heights: Vec<f64> = (0..1024 * 1024).map(|_| mix.sample(&mut rng)).collect();
        let measured = MaterialRatioCurve::from_heights(heights).unwrap().core();
        for (name, a, b) in [
            ("Sk", measured.Sk, exact.Sk),
            ("Spk", measured.Spk, exact.Spk),
            ("Svk", measured.Svk, exact.Svk),
        ] {
            assert!(
                (a - b).abs() <= 0.01 * b.abs(),
                "{name}: {a} measured, {b} exact"
            );
        }
        assert!(
            (measured.Smr1 - exact.Smr1).abs() < 0.5 && (measured.Smr2 - exact.Smr2).abs() < 0.5
        );
        // a plateau-honed surface: deep valleys, few peaks
        assert!(exact.Svk > 3.0 * exact.Spk, "{exact:?}");
    }

    #[test]
    fn a_sinusoids_material_ratio_is_the_arc_cosine() {
        // Rmr(c) = acos(c / A) / π for z = A sin(2πx/λ), sampled at the
        // midpoints of 4·10⁶ equal steps over one period: each of the two
        // crossings of c is placed to within a step, so the ratio is exact to
        // 2/N = 5·10⁻⁷ (in % below, to 10⁻⁴ %, i.e. 10⁻⁶ as a fraction)
        let (a, n, periods) = (1.5, 4_000_000usize, 1.0);
        let heights: Vec<f64> = (0..n)
            .map(|k| a * (2.0 * PI * periods * (k as f64 + 0.5) / n as f64).sin())
            .collect();
        let curve = MaterialRatioCurve::from_heights(heights).unwrap();
        for c in [-1.4, -0.9, -0.3, 0.0, 0.25, 0.8, 1.2, 1.45] {
            let want = 100.0 * (c / a).acos() / PI;
            let got = curve.ratio_at(c);
            assert!(
                (got - want).abs() <= 1e-4,
                "Rmr({c}) = {got} %, analytic {want} %"
            );
        }
    }

    #[test]
    fn the_curve_and_volumes_meet_their_identities() {
        let mut rng = StdRng::seed_from_u64(rand::random());
        let heights: Vec<f64> = (0..5000)
            .map(|_| rng.random_range(-1.0..1.0f64).powi(3))
            .collect();
        let mean = heights.iter().sum::<f64>() / heights.len() as f64;
        let (lo, hi) = heights
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), z| {
                (l.min(*z), h.max(*z))
            });
        let curve = MaterialRatioCurve::from_heights(heights).unwrap();
        assert_eq!(curve.height_at(0.0), hi);
        assert_eq!(curve.height_at(100.0), lo);
        assert_eq!(
            (curve.ratio_at(hi + 1.0), curve.ratio_at(lo - 1.0)),
            (0.0, 100.0)
        );
        for mr in [0.7, 10.0, 33.3, 50.0, 91.0] {
            assert!(
                (curve.ratio_at(curve.height_at(mr)) - mr).abs() < 1e-9,
                "round trip at {mr}"
            );
        }
        // Vm(100 %) is the mean above the lowest point, Vv(0 %) the mean below
        // the highest, to the trapezoid rule's end correction (1/N of the range)
        let slack = 2.0 * (hi - lo) / 5000.0;
        assert!((curve.material_volume(100.0) - (mean - lo)).abs() < slack);
        assert!((curve.void_volume(0.0) - (hi - mean)).abs() < slack);
        assert_eq!(curve.material_volume(0.0), 0.0);
        assert!(curve.void_volume(100.0).abs() < 1e-12);
    }

    #[test]
    fn too_few_heights_are_refused() {
        assert!(MaterialRatioCurve::from_heights(vec![1.0]).is_err());
        assert!(MaterialRatioCurve::from_heights(vec![1.0, f64::NAN]).is_err());
    }
}
