//! Pseudo-curvatures of P-IFS curves and tensor-product surfaces (poull-gentil §4).
//!
//! **Surfaces (§4.1).** For 𝒯 = T⊗T′ and Q = q⊗q′ the SDCF's first derivatives at
//! (0, 0) are P D₁,₀ and P D₀,₁, the mixed one P D₁,₁ and the second ones
//! α₂(α₂−1) P D₂,₀ s^{α₂−2} (and the same in t). In the u = x₁s, v = y₁t
//! parameters of [`crate::dcf`] these are
//!
//! > S_s = P(v₁⊗w₀), S_t = P(v₀⊗w₁), S_st = P(v₁⊗w₁), S_ss = 2P(w₂⊗w₀), S_tt = 2P(v₀⊗w′₂),
//!
//! with w₂, w′₂ the families' second-order vectors (zero when α₂ > 2). Then, as in
//! the paper, n = S_s × S_t/‖·‖, E = S_s·S_s, F = S_s·S_t, G = S_t·S_t,
//! L = S_ss·n, M = S_st·n, N = S_tt·n and
//!
//! > 𝒦 = (LN − M²)/(EG − F²),  ℋ = (EN + GL − 2FM)/(2(EG − F²)),  κ₁,₂ = ℋ ± √(ℋ² − 𝒦).
//!
//! (The paper's K_□ = (L + N ± √(L² + 4M² + N² − 2LN))/2 is this expression for an
//! orthonormal parametrisation, E = G = 1, F = 0; the general form is used here.)
//! 𝒦 is bilinear and ℋ affine in the two families' second-order coefficients, so
//! their ranges over the family of SDCFs are attained at the lower/upper bound
//! DCFs of each direction — the paper's "tensor product of the lower bound DCF and
//! the upper bound DCF" — and are exact; principal curvatures are not bilinear and
//! are ranged over a thinned sample of both families (33 members each by default).
//!
//! The 3×3 table of §4.1 gives the class from α₂ (s) and α′₂ (t):
//!
//! | | α₂ < 2 | α₂ = 2 | α₂ > 2 |
//! |---|---|---|---|
//! | α′₂ < 2 | ±∞ | ±∞ | indefinite |
//! | α′₂ = 2 | ±∞ | finite | finite |
//! | α′₂ > 2 | indefinite | finite | finite |
//!
//! **Orientation.** ℋ and the 2-D curve curvature are signed with respect to the
//! attractor's own parametrisation: the normal is ∂/∂s × ∂/∂t of the attractor,
//! i.e. the SDCF normal times σσ′ (σ = +1 at the fixed point of T0, where the DCF
//! leaves towards increasing s; −1 at T1's).
//!
//! **Dyadic points (§4.2).** The point at s = k/2ⁿ is T_w c₀ for the n binary
//! digits w of k (the right-hand piece) and T_{w′} c₁ for those of k − 1 (the
//! left-hand piece). The attractor near it is the image of the attractor near c₀
//! (resp. c₁) under T_w, so its DCFs are those of T0 (resp. T1) projected with the
//! control points P·T_w: the class is unchanged and the values are recomputed —
//! one range per side for curves, per quadrant for surfaces.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::Serialize;

use asperity_core::vec3::{cross, dot, norm};

use crate::dcf::{CurveClass, FamilyOptions, Frame, OperatorAnalysis, curve_curvature};
use crate::error::{Result, invalid};
use crate::invariant::Decomposition;
use crate::pifs::{CurveIfs, Pifs, SurfaceIfs, project};

/// Members per direction used for principal-curvature ranges.
pub const PRINCIPAL_SAMPLES: usize = 33;

/// Class of a surface fixed point (the 3×3 table, plus the spectral failures).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceClass {
    /// A finite value or range.
    Finite,
    /// ±∞.
    Infinite,
    /// No limit: one second derivative vanishes while the other diverges.
    Indefinite,
    /// A factor operator is not diagonalisable.
    NonDiagonalisable,
    /// A factor operator has complex eigenvalues.
    Complex,
    /// A factor operator has a negative λ₁.
    NegativeDominant,
    /// Pinched corner: S_s and S_t are parallel.
    Degenerate,
}

impl SurfaceClass {
    /// The name used in JSON and tables.
    pub fn name(self) -> &'static str {
        match self {
            SurfaceClass::Finite => "finite",
            SurfaceClass::Infinite => "infinite",
            SurfaceClass::Indefinite => "indefinite",
            SurfaceClass::NonDiagonalisable => "non-diagonalisable",
            SurfaceClass::Complex => "complex",
            SurfaceClass::NegativeDominant => "negative-dominant",
            SurfaceClass::Degenerate => "degenerate",
        }
    }
}

/// The §4.1 table.
pub fn surface_class(s: CurveClass, t: CurveClass) -> SurfaceClass {
    use CurveClass as C;
    for c in [s, t] {
        match c {
            C::NonDiagonalisable => return SurfaceClass::NonDiagonalisable,
            C::Complex => return SurfaceClass::Complex,
            C::NegativeDominant => return SurfaceClass::NegativeDominant,
            C::Degenerate => return SurfaceClass::Degenerate,
            _ => {}
        }
    }
    match (s, t) {
        (C::Infinite, C::Zero) | (C::Zero, C::Infinite) => SurfaceClass::Indefinite,
        (C::Infinite, _) | (_, C::Infinite) => SurfaceClass::Infinite,
        _ => SurfaceClass::Finite,
    }
}

/// Ranges of the surface pseudo-curvatures over a family of SDCFs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SurfaceRanges {
    /// [min, max] of 𝒦.
    pub gaussian: [f64; 2],
    /// [min, max] of ℋ.
    pub mean: [f64; 2],
    /// [[min, max] of κ₁, [min, max] of κ₂] (κ₁ ≥ κ₂), when computed.
    pub principal: Option<[[f64; 2]; 2]>,
}

/// An s-direction frame contracted with the control grid (Q_b = Σₐ aₐP_ab).
#[derive(Clone, Debug)]
pub struct ContractedFrame {
    sigma: f64,
    point: Vec<[f64; 3]>,
    tangent: Vec<[f64; 3]>,
    second: Vec<Vec<[f64; 3]>>,
}

impl ContractedFrame {
    /// Contracts `f` with the grid of `surface`.
    pub fn new(surface: &SurfaceIfs, f: &Frame) -> Self {
        Self {
            sigma: f.sigma,
            point: surface.contract_s(f.point.as_slice()),
            tangent: surface.contract_s(f.tangent.as_slice()),
            second: f
                .second
                .iter()
                .map(|w| surface.contract_s(w.as_slice()))
                .collect(),
        }
    }
}

fn widen(r: &mut [f64; 2], v: f64) {
    r[0] = r[0].min(v);
    r[1] = r[1].max(v);
}

const EMPTY: [f64; 2] = [f64::INFINITY, f64::NEG_INFINITY];

/// Surface pseudo-curvature ranges at one quadrant; None at a pinched corner.
pub fn surface_curvature(
    fs: &ContractedFrame,
    ft: &Frame,
    principal: bool,
) -> Option<SurfaceRanges> {
    let b0 = ft.point.as_slice();
    let b1 = ft.tangent.as_slice();
    let ss = project(&fs.tangent, b0);
    let st = project(&fs.point, b1);
    let sst = project(&fs.tangent, b1);
    let raw = cross(ss, st);
    let len = norm(raw);
    if len.is_nan() || len <= 1e-12 * norm(ss) * norm(st) || len == 0.0 {
        return None;
    }
    let o = fs.sigma * ft.sigma / len;
    let n = [raw[0] * o, raw[1] * o, raw[2] * o];
    let (e, f, g) = (dot(ss, ss), dot(ss, st), dot(st, st));
    let det = e * g - f * f;
    let m = dot(sst, n);
    let ls: Vec<f64> = fs
        .second
        .iter()
        .map(|q| 2.0 * dot(project(q, b0), n))
        .collect();
    let ns: Vec<f64> = ft
        .second
        .iter()
        .map(|w| 2.0 * dot(project(&fs.point, w.as_slice()), n))
        .collect();
    let mut gaussian = EMPTY;
    let mut mean = EMPTY;
    let mut k1 = EMPTY;
    let mut k2 = EMPTY;
    for &l in &ls {
        for &nn in &ns {
            let k = (l * nn - m * m) / det;
            let h = (e * nn + g * l - 2.0 * f * m) / (2.0 * det);
            widen(&mut gaussian, k);
            widen(&mut mean, h);
            if principal {
                let d = (h * h - k).max(0.0).sqrt();
                widen(&mut k1, h + d);
                widen(&mut k2, h - d);
            }
        }
    }
    Some(SurfaceRanges {
        gaussian,
        mean,
        principal: principal.then_some([k1, k2]),
    })
}

/// The two operators of one direction, analysed.
#[derive(Clone, Debug)]
pub struct DirectionAnalysis {
    /// Operator 0 and operator 1.
    pub operators: [OperatorAnalysis; 2],
}

impl DirectionAnalysis {
    /// Analyses both operators of `pifs`.
    pub fn new(pifs: &Pifs, opts: &FamilyOptions) -> Self {
        Self {
            operators: [
                OperatorAnalysis::new(pifs, 0, opts),
                OperatorAnalysis::new(pifs, 1, opts),
            ],
        }
    }
}

/// A dyadic parameter s = k/2ⁿ in lowest terms.
///
/// # Errors
/// Outside [0, 1], NaN, or not dyadic with n ≤ 52.
pub fn dyadic(s: f64) -> Result<(u64, u32)> {
    if !(0.0..=1.0).contains(&s) {
        return Err(invalid("at", format!("{s} is outside [0, 1]")));
    }
    for n in 0..=52u32 {
        let x = s * (1u64 << n) as f64;
        if x.fract() == 0.0 {
            return Ok((x as u64, n));
        }
    }
    Err(invalid(
        "at",
        format!(
            "{s} is not a dyadic parameter k/2ⁿ (pseudo-curvature is defined at dyadic points)"
        ),
    ))
}

/// One side of a dyadic point: which operator's DCF and which word transports it.
#[derive(Clone, Debug, PartialEq)]
pub struct Side {
    /// "left" (the piece ending here, operator 1) or "right" (operator 0).
    pub side: &'static str,
    /// The operator whose DCF applies.
    pub operator: usize,
    /// Binary digits of the word.
    pub word: String,
    /// Its matrix.
    pub matrix: DMatrix<f64>,
}

/// The sides of the dyadic point s of `pifs`.
///
/// # Errors
/// As [`dyadic`].
pub fn sides(pifs: &Pifs, s: f64) -> Result<Vec<Side>> {
    let (k, n) = dyadic(s)?;
    let digits = |v: u64| -> String {
        (0..n)
            .rev()
            .map(|d| if (v >> d) & 1 == 1 { '1' } else { '0' })
            .collect()
    };
    let mut out = Vec::new();
    if k > 0 {
        out.push(Side {
            side: "left",
            operator: 1,
            word: digits(k - 1),
            matrix: pifs.word(k - 1, n),
        });
    }
    if s < 1.0 {
        out.push(Side {
            side: "right",
            operator: 0,
            word: digits(k),
            matrix: pifs.word(k, n),
        });
    }
    Ok(out)
}

/// Family summary for reports.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FamilyReport {
    /// Members sampled.
    pub members: usize,
    /// Starting points left out (x₁ ≈ 0).
    pub dropped: usize,
    /// [min, max] of c₂ = x₂/x₁^{α₂}.
    pub c2: [f64; 2],
    /// Parameter of the lower-bound member's starting point.
    pub lower_start: f64,
    /// Parameter of the upper-bound member's starting point.
    pub upper_start: f64,
}

fn family_report(a: &OperatorAnalysis) -> Option<FamilyReport> {
    let d = a.dcf.as_ref()?;
    let (lo, hi) = (d.lower()?, d.upper()?);
    Some(FamilyReport {
        members: d.members.len(),
        dropped: d.dropped,
        c2: [lo.c2, hi.c2],
        lower_start: lo.start,
        upper_start: hi.start,
    })
}

/// Exponents α from the eigenvalue moduli (None = +∞), whatever the structure.
fn alphas(a: &OperatorAnalysis) -> Vec<Option<f64>> {
    if let Some(d) = &a.dcf {
        return d
            .alpha
            .iter()
            .map(|x| x.is_finite().then_some(*x))
            .collect();
    }
    let l1 = a.spectrum.subdominant_modulus();
    a.spectrum
        .values
        .iter()
        .enumerate()
        .map(|(k, v)| match k {
            0 => Some(0.0),
            _ if v.modulus() == 0.0 => None,
            _ => Some(crate::spectrum::snap(v.modulus().ln() / l1.ln())),
        })
        .collect()
}

fn eigen_json(a: &OperatorAnalysis) -> Vec<serde_json::Value> {
    a.spectrum
        .values
        .iter()
        .map(|v| {
            if v.im == 0.0 {
                serde_json::json!(v.re)
            } else {
                serde_json::json!(format!("{}{:+}i", v.re, v.im))
            }
        })
        .collect()
}

/// Pseudo-curvature of one curve operator's fixed point.
#[derive(Clone, Debug, Serialize)]
pub struct CurveOperatorReport {
    /// Operator index.
    pub index: usize,
    /// Attractor parameter of the fixed point (0 or 1).
    pub parameter: f64,
    /// Barycentric fixed point.
    pub fixed_point: Vec<f64>,
    /// Its position in the modelling space.
    pub position: Vec<f64>,
    /// Eigenvalues (numbers, or "a+bi" strings for complex ones).
    pub eigenvalues: Vec<serde_json::Value>,
    /// α exponents (null = +∞).
    pub alpha: Vec<Option<f64>>,
    /// Class name.
    pub class: &'static str,
    /// Why there is no DCF.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// [min, max] of the pseudo-curvature (null unless finite or zero).
    pub curvature: Option<[f64; 2]>,
    /// The sampled family.
    pub family: Option<FamilyReport>,
}

fn position(p: [f64; 3], dim: usize) -> Vec<f64> {
    p[..dim].to_vec()
}

fn curve_range(
    curve: &CurveIfs,
    a: &OperatorAnalysis,
    word: Option<&DMatrix<f64>>,
) -> (CurveClass, Option<[f64; 2]>) {
    if !matches!(a.class, CurveClass::Finite | CurveClass::Zero) {
        return (a.class, None);
    }
    match a
        .frame(word, None)
        .and_then(|f| curve_curvature(curve.control(), curve.dim(), &f))
    {
        Some(r) => (a.class, Some(r)),
        None => (CurveClass::Degenerate, None),
    }
}

/// Reports for both operators of a curve.
pub fn curve_report(curve: &CurveIfs, an: &DirectionAnalysis) -> Vec<CurveOperatorReport> {
    an.operators
        .iter()
        .map(|a| {
            let c = curve.pifs.fixed_point(a.operator);
            let (class, curvature) = curve_range(curve, a, None);
            CurveOperatorReport {
                index: a.operator,
                parameter: a.operator as f64,
                fixed_point: c.iter().copied().collect(),
                position: position(curve.project(c.as_slice()), curve.dim()),
                eigenvalues: eigen_json(a),
                alpha: alphas(a),
                class: class.name(),
                reason: a.reason.clone(),
                curvature,
                family: family_report(a),
            }
        })
        .collect()
}

/// Curvature on one side of a dyadic point of a curve.
#[derive(Clone, Debug, Serialize)]
pub struct CurveSideReport {
    /// "left" or "right".
    pub side: &'static str,
    /// Operator whose DCF family applies.
    pub operator: usize,
    /// The transporting word (binary digits).
    pub word: String,
    /// Class name.
    pub class: &'static str,
    /// [min, max], null unless finite or zero.
    pub curvature: Option<[f64; 2]>,
}

/// Pseudo-curvature at a dyadic parameter of a curve.
#[derive(Clone, Debug, Serialize)]
pub struct CurveAtReport {
    /// The parameter.
    pub at: f64,
    /// Its position.
    pub position: Vec<f64>,
    /// One entry per side.
    pub sides: Vec<CurveSideReport>,
}

/// Pseudo-curvature ranges at the dyadic parameter `s` (§4.2).
///
/// # Errors
/// `s` not dyadic or outside [0, 1].
pub fn curve_at(curve: &CurveIfs, an: &DirectionAnalysis, s: f64) -> Result<CurveAtReport> {
    let sides = sides(&curve.pifs, s)?;
    let point = curve.pifs.point_at(s)?;
    Ok(CurveAtReport {
        at: s,
        position: position(curve.project(point.as_slice()), curve.dim()),
        sides: sides
            .into_iter()
            .map(|sd| {
                let (class, curvature) =
                    curve_range(curve, &an.operators[sd.operator], Some(&sd.matrix));
                CurveSideReport {
                    side: sd.side,
                    operator: sd.operator,
                    word: sd.word,
                    class: class.name(),
                    curvature,
                }
            })
            .collect(),
    })
}

/// Pseudo-curvature of one tensor operator's fixed point.
#[derive(Clone, Debug, Serialize)]
pub struct SurfaceOperatorReport {
    /// [i, j] for 𝒯ᵢⱼ = Tᵢ ⊗ T′ⱼ.
    pub index: [usize; 2],
    /// Attractor parameters (s, t) of the fixed point.
    pub parameter: [f64; 2],
    /// Barycentric fixed point cᵢ ⊗ c′ⱼ (N·M entries).
    pub fixed_point: Vec<f64>,
    /// Its position.
    pub position: [f64; 3],
    /// Eigenvalues of Tᵢ and of T′ⱼ (those of 𝒯ᵢⱼ are their products).
    pub eigenvalues: [Vec<serde_json::Value>; 2],
    /// The spectrum of 𝒯ᵢⱼ itself, from its general decomposition
    /// ([`crate::invariant`]): each distinct eigenvalue with its algebraic and
    /// geometric multiplicity. `None` when it has no real decomposition
    /// (complex eigenvalues).
    pub tensor_spectrum: Option<Vec<crate::invariant::SpectrumEntry>>,
    /// α of Tᵢ and α′ of T′ⱼ (one list per direction; null = +∞).
    pub alpha: [Vec<Option<f64>>; 2],
    /// Class from the §4.1 table.
    pub class: &'static str,
    /// Class of the s direction alone.
    pub class_s: &'static str,
    /// Class of the t direction alone.
    pub class_t: &'static str,
    /// [min, max] of the Gaussian pseudo-curvature.
    pub gaussian: Option<[f64; 2]>,
    /// [min, max] of the mean pseudo-curvature.
    pub mean: Option<[f64; 2]>,
    /// [[min, max] of κ₁, [min, max] of κ₂].
    pub principal: Option<[[f64; 2]; 2]>,
}

/// One quadrant of a surface point for [`sdcf_curvature`]: the factor's
/// decomposition, the starting point, the transporting word and σ (+1 when the
/// SDCF leaves towards increasing parameter, −1 otherwise).
pub type Direction<'a> = (&'a Decomposition, &'a DVector<f64>, &'a DMatrix<f64>, f64);

/// 𝒦, ℋ (and κ₁, κ₂) of one SDCF at its corner, transported by the words, from
/// the general spectra of its factors. None when a direction's second order is not
/// finite (see [`Decomposition::second_order_is_finite`]) or the corner is pinched.
pub fn sdcf_curvature(
    surface: &SurfaceIfs,
    (ds, q, ws, sigma_s): Direction,
    (dt, q2, wt, sigma_t): Direction,
) -> Option<SurfaceRanges> {
    if !(ds.second_order_is_finite() && dt.second_order_is_finite()) {
        return None;
    }
    let fs = ContractedFrame::new(surface, &ds.frame(q, ws, sigma_s));
    surface_curvature(&fs, &dt.frame(q2, wt, sigma_t), true)
}

fn quadrant(
    surface: &SurfaceIfs,
    a: &OperatorAnalysis,
    b: &OperatorAnalysis,
    ws: Option<&DMatrix<f64>>,
    wt: Option<&DMatrix<f64>>,
) -> (SurfaceClass, Option<SurfaceRanges>) {
    let class = surface_class(a.class, b.class);
    if class != SurfaceClass::Finite {
        return (class, None);
    }
    let (Some(fs), Some(ft)) = (
        a.frame(ws, Some(PRINCIPAL_SAMPLES)),
        b.frame(wt, Some(PRINCIPAL_SAMPLES)),
    ) else {
        return (SurfaceClass::Degenerate, None);
    };
    let cs = ContractedFrame::new(surface, &fs);
    let Some(mut r) = surface_curvature(&cs, &ft, true) else {
        return (SurfaceClass::Degenerate, None);
    };
    // 𝒦 and ℋ exactly from the bound members (they are bilinear / affine).
    if let (Some(fs), Some(ft)) = (a.frame(ws, None), b.frame(wt, None))
        && let Some(exact) = surface_curvature(&ContractedFrame::new(surface, &fs), &ft, false)
    {
        r.gaussian = exact.gaussian;
        r.mean = exact.mean;
    }
    (class, Some(r))
}

/// Reports for the four tensor operators of a surface.
pub fn surface_report(
    surface: &SurfaceIfs,
    an_s: &DirectionAnalysis,
    an_t: &DirectionAnalysis,
) -> Vec<SurfaceOperatorReport> {
    let mut out = Vec::with_capacity(4);
    for a in &an_s.operators {
        for b in &an_t.operators {
            let (i, j) = (a.operator, b.operator);
            let cs = surface.s.fixed_point(i);
            let ct = surface.t.fixed_point(j);
            let (class, r) = quadrant(surface, a, b, None, None);
            out.push(SurfaceOperatorReport {
                index: [i, j],
                parameter: [i as f64, j as f64],
                fixed_point: cs.kronecker(ct).iter().copied().collect(),
                position: surface.project(cs.as_slice(), ct.as_slice()),
                eigenvalues: [eigen_json(a), eigen_json(b)],
                tensor_spectrum: Decomposition::new(&surface.operator(i, j))
                    .ok()
                    .map(|d| d.entries()),
                alpha: [alphas(a), alphas(b)],
                class: class.name(),
                class_s: a.class.name(),
                class_t: b.class.name(),
                gaussian: r.map(|r| r.gaussian),
                mean: r.map(|r| r.mean),
                principal: r.and_then(|r| r.principal),
            });
        }
    }
    out
}

/// One quadrant around a dyadic point of a surface.
#[derive(Clone, Debug, Serialize)]
pub struct QuadrantReport {
    /// Side in s ("left"/"right") and in t ("below"/"above").
    pub side: [&'static str; 2],
    /// The tensor operator [i, j] whose SDCF family applies.
    pub operator: [usize; 2],
    /// Transporting words (binary digits) in s and t.
    pub word: [String; 2],
    /// Class name.
    pub class: &'static str,
    /// [min, max] of 𝒦.
    pub gaussian: Option<[f64; 2]>,
    /// [min, max] of ℋ.
    pub mean: Option<[f64; 2]>,
    /// Principal ranges.
    pub principal: Option<[[f64; 2]; 2]>,
}

/// Pseudo-curvature at a dyadic point of a surface.
#[derive(Clone, Debug, Serialize)]
pub struct SurfaceAtReport {
    /// (s, t).
    pub at: [f64; 2],
    /// Its position.
    pub position: [f64; 3],
    /// One entry per quadrant that exists (1 at a corner, 2 on an edge, 4 inside).
    pub quadrants: Vec<QuadrantReport>,
}

/// Pseudo-curvature ranges at the dyadic point (s, t) (§4.2).
///
/// # Errors
/// A parameter that is not dyadic or is outside [0, 1].
pub fn surface_at(
    surface: &SurfaceIfs,
    an_s: &DirectionAnalysis,
    an_t: &DirectionAnalysis,
    s: f64,
    t: f64,
) -> Result<SurfaceAtReport> {
    let ss = sides(&surface.s, s)?;
    let ts = sides(&surface.t, t)?;
    let (ps, pt) = (surface.s.point_at(s)?, surface.t.point_at(t)?);
    let mut quadrants = Vec::new();
    for a in &ss {
        for b in &ts {
            let (class, r) = quadrant(
                surface,
                &an_s.operators[a.operator],
                &an_t.operators[b.operator],
                Some(&a.matrix),
                Some(&b.matrix),
            );
            quadrants.push(QuadrantReport {
                side: [a.side, if b.side == "left" { "below" } else { "above" }],
                operator: [a.operator, b.operator],
                word: [a.word.clone(), b.word.clone()],
                class: class.name(),
                gaussian: r.map(|r| r.gaussian),
                mean: r.map(|r| r.mean),
                principal: r.and_then(|r| r.principal),
            });
        }
    }
    Ok(SurfaceAtReport {
        at: [s, t],
        position: surface.project(ps.as_slice(), pt.as_slice()),
        quadrants,
    })
}

/// Frames of one operator transported to every dyadic point of a depth:
/// entry k is the frame at s = k/2^depth (None where that side does not exist).
fn transported_frames(pifs: &Pifs, a: &OperatorAnalysis, depth: u32) -> Vec<Option<Frame>> {
    let count = 1usize << depth;
    let Some(base) = a.frame(None, None) else {
        return vec![None; count + 1];
    };
    let n = pifs.size();
    let words = |v: &DVector<f64>| pifs.apply_words(v.as_slice(), depth);
    let point = words(&base.point);
    let tangent = words(&base.tangent);
    let second: Vec<Vec<f64>> = base.second.iter().map(words).collect();
    let at = |w: usize| Frame {
        sigma: base.sigma,
        point: DVector::from_column_slice(&point[w * n..(w + 1) * n]),
        tangent: DVector::from_column_slice(&tangent[w * n..(w + 1) * n]),
        second: second
            .iter()
            .map(|s| DVector::from_column_slice(&s[w * n..(w + 1) * n]))
            .collect(),
    };
    (0..=count)
        .map(|k| match a.operator {
            // Right-hand piece T_w(𝒜), w = digits of k.
            0 => (k < count).then(|| at(k)),
            // Left-hand piece, w = digits of k − 1.
            _ => (k > 0).then(|| at(k - 1)),
        })
        .collect()
}

/// Per-vertex pseudo-curvature ranges on the dyadic attractor mesh of `depth`
/// (vertex order of [`SurfaceIfs::attractor_mesh`]): `gaussian_min`,
/// `gaussian_max`, `mean_min`, `mean_max`, each over the quadrants meeting at
/// the vertex and over the family of SDCFs.
///
/// # Errors
/// [`crate::IfsError::InvalidParameter`] when some tensor operator's class is not
/// finite (the values would be infinite or undefined everywhere).
pub fn vertex_curvature(
    surface: &SurfaceIfs,
    an_s: &DirectionAnalysis,
    an_t: &DirectionAnalysis,
    depth: u32,
) -> Result<Vec<(&'static str, Vec<f64>)>> {
    for a in &an_s.operators {
        for b in &an_t.operators {
            let c = surface_class(a.class, b.class);
            if c != SurfaceClass::Finite {
                return Err(invalid(
                    "curvature",
                    format!(
                        "the pseudo-curvature at the fixed point of T{}⊗T'{} is {} (α₂ = {:?}, α'₂ = {:?}), \
                         so it has no finite per-vertex value",
                        a.operator,
                        b.operator,
                        c.name(),
                        a.dcf.as_ref().map(|d| d.alpha2()),
                        b.dcf.as_ref().map(|d| d.alpha2())
                    ),
                ));
            }
        }
    }
    let fs: Vec<Vec<Option<ContractedFrame>>> = an_s
        .operators
        .iter()
        .map(|a| {
            transported_frames(&surface.s, a, depth)
                .into_par_iter()
                .map(|f| f.map(|f| ContractedFrame::new(surface, &f)))
                .collect()
        })
        .collect();
    let ft: Vec<Vec<Option<Frame>>> = an_t
        .operators
        .iter()
        .map(|b| transported_frames(&surface.t, b, depth))
        .collect();
    let side = 1usize << depth;
    let cols = side + 1;
    let rows: Vec<[Vec<f64>; 4]> = (0..cols)
        .into_par_iter()
        .map(|k| {
            let mut out: [Vec<f64>; 4] = std::array::from_fn(|_| Vec::with_capacity(cols));
            for l in 0..cols {
                let mut g = EMPTY;
                let mut h = EMPTY;
                for fsk in fs.iter().filter_map(|v| v[k].as_ref()) {
                    for ftl in ft.iter().filter_map(|v| v[l].as_ref()) {
                        if let Some(r) = surface_curvature(fsk, ftl, false) {
                            widen(&mut g, r.gaussian[0]);
                            widen(&mut g, r.gaussian[1]);
                            widen(&mut h, r.mean[0]);
                            widen(&mut h, r.mean[1]);
                        }
                    }
                }
                // A pinched vertex (no quadrant with a normal) gets 0.
                let fix = |x: f64| if x.is_finite() { x } else { 0.0 };
                out[0].push(fix(g[0]));
                out[1].push(fix(g[1]));
                out[2].push(fix(h[0]));
                out[3].push(fix(h[1]));
            }
            out
        })
        .collect();
    let names = ["gaussian_min", "gaussian_max", "mean_min", "mean_max"];
    Ok(names
        .iter()
        .enumerate()
        .map(|(q, &name)| {
            (
                name,
                rows.iter().flat_map(|r| r[q].iter().copied()).collect(),
            )
        })
        .collect())
}
