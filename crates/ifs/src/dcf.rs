//! Differential characteristic functions (poull-gentil §2.3, after Janbein et al.).
//!
//! For an operator T with eigenpairs (λᵢ, vᵢ) (λ₀ = 1, v₀ its fixed point, then by
//! decreasing modulus) and a starting point q = Σ xᵢvᵢ,
//!
//! > DCF(T, q, t) = Σᵢ xᵢ vᵢ t^{αᵢ},  αᵢ = log|λᵢ| / log|λ₁|.
//!
//! It passes through the orbit Tⁿq (at t = λ₁ⁿ for positive eigenvalues) and
//! through q itself at t = 1, and DCF(T, Tq, t) = DCF(T, q, λ₁t): the DCFs of the
//! points of T(𝒜) repeat those of 𝒜 ∖ T(𝒜). The **family** is therefore sampled
//! over that fundamental domain — the other operator's half of the attractor —
//! at every dyadic parameter of a chosen depth *and* every periodic point of
//! period up to a chosen length (fixed points of words; the Takagi curve's
//! extreme member sits at the periodic point 2/3 = 0.(10)₂, not at a dyadic one).
//!
//! After the reparametrisation u = x₁t, DCF = v₀ + v₁u + Σ_{k≥2} cₖvₖu^{αₖ} with
//! the invariants cₖ = xₖ/x₁^{αₖ}; near the fixed point the second-order term is
//! w₂ = Σ_{αₖ=2} cₖvₖ, so D′(0) = v₁, D″(0) = 2w₂ in the u parameter, and
//! the three cases of §2.3 follow from α₂:
//!
//! | α₂ | class | pseudo-curvature |
//! |---|---|---|
//! | < 2 | `infinite` | D″ ~ u^{α₂−2} → ∞ |
//! | = 2 | `finite` | κ = 2 (Pv₁ × Pw₂)/‖Pv₁‖³, a **range** over the family |
//! | > 2 | `zero` | D″ → 0 |
//!
//! The "lower and upper bound DCFs" are the members with the smallest and largest
//! c₂. v₁ is oriented so that x₁ > 0 on the family, i.e. the DCF leaves the fixed
//! point into the attractor; members with x₁ ≈ 0 (or, for an attractor that
//! reaches its end from both sides, x₁ < 0) are counted in `dropped`.
//!
//! Operators whose spectrum does not allow a DCF are classified, never turned
//! into NaN: `non-diagonalisable` (a Jordan block: the classical Takagi curve
//! w = ½ has y ~ x log x at its ends), `complex` (a complex pair — stricter than
//! the paper needs, which only excludes a complex dominant pair) and
//! `negative-dominant` (λ₁ < 0: the orbit alternates sides and t^{α} cannot follow it).

use asperity_core::vec3::{cross, norm};
use nalgebra::{DMatrix, DVector};

use crate::pifs::Pifs;
use crate::spectrum::{Spectrum, Structure};

/// How a fixed point's pseudo-curvature behaves (curves: §2.3; one direction of a surface: §4.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveClass {
    /// α₂ < 2: infinite pseudo-curvature.
    Infinite,
    /// α₂ = 2: finite, a range over the family of DCFs.
    Finite,
    /// α₂ > 2 (or no second eigen-direction): zero.
    Zero,
    /// A Jordan block: no DCF.
    NonDiagonalisable,
    /// A complex eigenvalue pair: no DCF.
    Complex,
    /// λ₁ < 0: no DCF.
    NegativeDominant,
    /// The tangent Pv₁ vanishes in the modelling space (a pinched end).
    Degenerate,
}

impl CurveClass {
    /// The name used in JSON and tables.
    pub fn name(self) -> &'static str {
        match self {
            CurveClass::Infinite => "infinite",
            CurveClass::Finite => "finite",
            CurveClass::Zero => "zero",
            CurveClass::NonDiagonalisable => "non-diagonalisable",
            CurveClass::Complex => "complex",
            CurveClass::NegativeDominant => "negative-dominant",
            CurveClass::Degenerate => "degenerate",
        }
    }

    /// Whether the DCF exists (finite, zero or infinite curvature).
    pub fn has_dcf(self) -> bool {
        matches!(
            self,
            CurveClass::Infinite | CurveClass::Finite | CurveClass::Zero
        )
    }
}

/// How densely the family of DCFs is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FamilyOptions {
    /// Dyadic starting points k/2^depth in the fundamental domain.
    pub dyadic_depth: u32,
    /// Periodic starting points 0.(w)^∞ for every word w up to this length.
    pub period: u32,
}

impl Default for FamilyOptions {
    fn default() -> Self {
        Self {
            dyadic_depth: 10,
            period: 12,
        }
    }
}

/// One member of the family: a starting point and its invariants.
#[derive(Clone, Debug, PartialEq)]
pub struct Member {
    /// Attractor parameter of the starting point.
    pub start: f64,
    /// Barycentric starting point q.
    pub point: DVector<f64>,
    /// Eigen-coordinates x = V⁻¹q (x₁ > 0).
    pub x: DVector<f64>,
    /// c₂ = x₂ / x₁^{α₂} (0 when N = 2).
    pub c2: f64,
}

/// The DCF of one operator with its sampled family.
#[derive(Clone, Debug)]
pub struct Dcf {
    /// Real eigenvalues in DCF order.
    pub eigenvalues: Vec<f64>,
    /// α exponents (α₀ = 0, α₁ = 1).
    pub alpha: Vec<f64>,
    vectors: DMatrix<f64>,
    inverse: DMatrix<f64>,
    /// Family members, sorted by c₂.
    pub members: Vec<Member>,
    /// Starting points left out (x₁ ≈ 0, or on the far side of the fixed point).
    pub dropped: usize,
}

/// Everything known about one operator of a [`Pifs`].
#[derive(Clone, Debug)]
pub struct OperatorAnalysis {
    /// 0 or 1.
    pub operator: usize,
    /// Its eigen-decomposition.
    pub spectrum: Spectrum,
    /// Classification of its fixed point.
    pub class: CurveClass,
    /// Why there is no DCF, when there is none.
    pub reason: Option<String>,
    /// The DCF and its family, when the spectrum allows one.
    pub dcf: Option<Dcf>,
}

/// The transported first- and second-order data of a DCF at one fixed point (or
/// at its image under a word W: every vector multiplied by W).
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// +1 when the DCF leaves its fixed point towards increasing parameter (T0),
    /// −1 when towards decreasing parameter (T1).
    pub sigma: f64,
    /// W·v₀: the point.
    pub point: DVector<f64>,
    /// W·v₁: the tangent (into the attractor).
    pub tangent: DVector<f64>,
    /// W·w₂ for the family members that bound every linear functional (or a thinned
    /// sample); `[0]` when α₂ > 2.
    pub second: Vec<DVector<f64>>,
}

impl Dcf {
    /// Eigen-coordinates of a barycentric point.
    pub fn coordinates(&self, q: &DVector<f64>) -> DVector<f64> {
        &self.inverse * q
    }

    /// DCF(T, q, t) in barycentric coordinates (t ≥ 0; t = 1 gives q).
    pub fn evaluate(&self, q: &DVector<f64>, t: f64) -> DVector<f64> {
        let x = self.coordinates(q);
        let mut out = DVector::<f64>::zeros(q.len());
        for (k, &a) in self.alpha.iter().enumerate() {
            let w = x[k] * t.powf(a);
            if w != 0.0 {
                out.axpy(w, &self.vectors.column(k), 1.0);
            }
        }
        out
    }

    /// Eigenvector k.
    pub fn vector(&self, k: usize) -> DVector<f64> {
        self.vectors.column(k).into_owned()
    }

    /// α₂ (+∞ for a 2×2 operator).
    pub fn alpha2(&self) -> f64 {
        self.alpha.get(2).copied().unwrap_or(f64::INFINITY)
    }

    /// The member with the smallest c₂ (lower bound DCF).
    pub fn lower(&self) -> Option<&Member> {
        self.members.first()
    }

    /// The member with the largest c₂ (upper bound DCF).
    pub fn upper(&self) -> Option<&Member> {
        self.members.last()
    }

    /// w₂ = Σ_{αₖ=2} (xₖ/x₁²) vₖ of a member, and its sign-flipped companion when an
    /// α = 2 eigenvalue is negative (T flips that term at every step).
    fn second_order(&self, m: &Member) -> Vec<DVector<f64>> {
        let n = m.x.len();
        let x1 = m.x[1];
        let mut w = DVector::<f64>::zeros(n);
        let mut flipped = DVector::<f64>::zeros(n);
        let mut any_negative = false;
        for k in 2..n {
            if self.alpha[k] == 2.0 {
                let c = m.x[k] / (x1 * x1);
                w.axpy(c, &self.vectors.column(k), 1.0);
                let s = self.eigenvalues[k].signum();
                any_negative |= s < 0.0;
                flipped.axpy(s * c, &self.vectors.column(k), 1.0);
            }
        }
        if any_negative {
            vec![w, flipped]
        } else {
            vec![w]
        }
    }

    fn alpha2_terms(&self) -> usize {
        self.alpha.iter().skip(2).filter(|&&a| a == 2.0).count()
    }
}

impl OperatorAnalysis {
    /// Analyses operator `i` of `pifs`: spectrum, class and sampled family.
    pub fn new(pifs: &Pifs, i: usize, opts: &FamilyOptions) -> Self {
        let spectrum = pifs.spectrum(i).clone();
        let unavailable = |class, reason: String| Self {
            operator: i,
            spectrum: spectrum.clone(),
            class,
            reason: Some(reason),
            dcf: None,
        };
        let (vectors, inverse, alpha) = match &spectrum.structure {
            Structure::Diagonalisable {
                vectors,
                inverse,
                alpha,
            } => (vectors.clone(), inverse.clone(), alpha.clone()),
            Structure::NonDiagonalisable {
                value,
                algebraic,
                geometric,
            } => {
                return unavailable(
                    CurveClass::NonDiagonalisable,
                    format!(
                        "eigenvalue {value} has multiplicity {algebraic} but only {geometric} \
                         independent eigenvector(s) (a Jordan block: the orbit has t·log t terms)"
                    ),
                );
            }
            Structure::Complex { re, im } => {
                return unavailable(
                    CurveClass::Complex,
                    format!("complex eigenvalue pair {re} ± {im}i (the orbit spirals)"),
                );
            }
        };
        let eigenvalues: Vec<f64> = spectrum.values.iter().map(|v| v.re).collect();
        if eigenvalues[1] < 0.0 {
            return unavailable(
                CurveClass::NegativeDominant,
                format!(
                    "λ₁ = {} is negative: the orbit alternates sides of the fixed point",
                    eigenvalues[1]
                ),
            );
        }
        let mut dcf = Dcf {
            eigenvalues,
            alpha,
            vectors,
            inverse,
            members: Vec::new(),
            dropped: 0,
        };
        sample_family(pifs, i, opts, &mut dcf);
        let a2 = dcf.alpha2();
        let class = if a2 < 2.0 {
            CurveClass::Infinite
        } else if a2 == 2.0 {
            CurveClass::Finite
        } else {
            CurveClass::Zero
        };
        Self {
            operator: i,
            spectrum,
            class,
            reason: None,
            dcf: Some(dcf),
        }
    }

    /// The first- and second-order data at the fixed point, transported by `word`
    /// (None = identity). `thin`: keep at most that many family members (evenly
    /// spaced in c₂, ends included) instead of the two extreme ones — needed for
    /// non-linear functionals such as principal curvatures. None when there is no DCF.
    pub fn frame(&self, word: Option<&DMatrix<f64>>, thin: Option<usize>) -> Option<Frame> {
        let dcf = self.dcf.as_ref()?;
        let apply = |v: DVector<f64>| match word {
            Some(w) => w * v,
            None => v,
        };
        let n = dcf.vectors.nrows();
        let members: Vec<&Member> = match (self.class, thin) {
            (CurveClass::Finite, _) if dcf.alpha2_terms() > 1 && thin.is_none() => {
                dcf.members.iter().collect()
            }
            (CurveClass::Finite, None) => dcf.lower().into_iter().chain(dcf.upper()).collect(),
            (CurveClass::Finite, Some(k)) => {
                let len = dcf.members.len();
                let k = k.clamp(2, len.max(2));
                let mut idx: Vec<usize> = (0..k)
                    .map(|j| j * (len.saturating_sub(1)) / (k - 1))
                    .collect();
                idx.dedup();
                idx.into_iter().filter_map(|j| dcf.members.get(j)).collect()
            }
            _ => Vec::new(),
        };
        let second: Vec<DVector<f64>> = if self.class == CurveClass::Finite {
            members
                .iter()
                .flat_map(|m| dcf.second_order(m))
                .map(apply)
                .collect()
        } else {
            vec![DVector::zeros(n)]
        };
        if second.is_empty() {
            return None;
        }
        Some(Frame {
            sigma: if self.operator == 0 { 1.0 } else { -1.0 },
            point: apply(dcf.vector(0)),
            tangent: apply(dcf.vector(1)),
            second,
        })
    }
}

/// Fills `dcf.members` from the fundamental domain (the other operator's half).
fn sample_family(pifs: &Pifs, i: usize, opts: &FamilyOptions, dcf: &mut Dcf) {
    let n = pifs.size();
    let other = 1 - i;
    let mut starts: Vec<(f64, DVector<f64>)> = Vec::new();
    let d = opts.dyadic_depth.clamp(1, 20);
    let half = 1usize << (d - 1);
    let pts = pifs.dyadic_points(d);
    let range = if other == 1 {
        half..=2 * half
    } else {
        0..=half
    };
    for k in range {
        let q = DVector::from_column_slice(&pts[k * n..(k + 1) * n]);
        starts.push((k as f64 / (2 * half) as f64, q));
    }
    // Words w of each length whose first digit is `other`, built by appending one
    // digit to the words one shorter: W = T_{b₁}…T_{b_L}; the periodic point
    // 0.(w)^∞ is W's fixed point.
    let mut words: Vec<(usize, DMatrix<f64>)> = Vec::new();
    for len in 1..=opts.period.min(20) {
        words = if len == 1 {
            vec![(other, pifs.operator(other).clone())]
        } else {
            words
                .iter()
                .flat_map(|(w, m)| (0..2).map(move |b| ((w << 1) | b, m * pifs.operator(b))))
                .collect()
        };
        for (w, m) in &words {
            if let Some(q) = crate::pifs::fixed_point(m) {
                starts.push((*w as f64 / ((1u64 << len) - 1) as f64, q));
            }
        }
    }
    let xs: Vec<DVector<f64>> = starts.iter().map(|(_, q)| dcf.coordinates(q)).collect();
    let tol = |x: &DVector<f64>| 1e-12 * x.amax().max(1.0);
    let neg = xs.iter().filter(|x| x[1] < -tol(x)).count();
    let pos = xs.iter().filter(|x| x[1] > tol(x)).count();
    if neg > pos {
        // Orient v₁ into the attractor.
        dcf.vectors.column_mut(1).neg_mut();
        dcf.inverse.row_mut(1).neg_mut();
    }
    let sign = if neg > pos { -1.0 } else { 1.0 };
    let a2 = dcf.alpha2();
    let mut members = Vec::with_capacity(starts.len());
    for ((start, point), mut x) in starts.into_iter().zip(xs) {
        x[1] *= sign;
        if x[1] <= tol(&x) {
            dcf.dropped += 1;
            continue;
        }
        let c2 = if n > 2 && a2.is_finite() {
            x[2] / x[1].powf(a2)
        } else {
            0.0
        };
        members.push(Member {
            start,
            point,
            x,
            c2,
        });
    }
    members.sort_by(|a, b| a.c2.total_cmp(&b.c2).then(a.start.total_cmp(&b.start)));
    dcf.members = members;
}

/// 2-D cross product (z of the 3-D one).
fn cross2(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Pseudo-curvature range of a curve at a frame: κ = 2 (Pv₁ × Pw₂)/‖Pv₁‖³,
/// signed in 2-D with respect to increasing attractor parameter (positive = turning
/// left), unsigned in 3-D. None when the projected tangent vanishes.
pub fn curve_curvature(control: &[[f64; 3]], dim: usize, frame: &Frame) -> Option<[f64; 2]> {
    let p = |v: &DVector<f64>| crate::pifs::project(control, v.as_slice());
    let t = p(&frame.tangent);
    let len = norm(t);
    let scale = control
        .iter()
        .map(|&c| norm(c))
        .fold(0.0, f64::max)
        .max(1.0);
    if len <= 1e-12 * scale {
        return None;
    }
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for w in &frame.second {
        let d2 = p(w);
        let k = if dim == 2 {
            frame.sigma * 2.0 * cross2(t, d2) / len.powi(3)
        } else {
            2.0 * norm(cross(t, d2)) / len.powi(3)
        };
        lo = lo.min(k);
        hi = hi.max(k);
    }
    Some([lo, hi])
}
