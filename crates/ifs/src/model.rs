//! Model files and presets.
//!
//! A model is a plain JSON document users can copy and edit:
//!
//! ```json
//! { "name": "takagi-landsberg", "description": "…", "parameters": { "w": 0.7071067811865476 },
//!   "curve": { "operators": [ [[1, 0, 0.29], [0, 0.5, 0], [0, 0.5, 0.71]], … ],
//!              "control_points": [[0, 0], [1, 0], [0, 1]] } }
//! ```
//!
//! Operators are row-major N×N matrices (row r, column c = entry `T[r][c]`; columns
//! sum to 1). A surface has `"surface": { "s": { "operators": … }, "t": { "operators": … },
//! "control_points": [[[x, y, z] × M] × N] }`. `parameters` is informative.
//!
//! Presets (generated here; `crates/ifs/presets/*.json` hold them at their default
//! parameters, and a test keeps the files equal to the generator):
//! - `bezier-quadratic`, `bezier-cubic`, `bezier` (`--degree n`): Bézier curves as
//!   P-IFS with de Casteljau subdivision matrices at ½ (Zair & Tosan):
//!   `T0[i][j]` = C(j, i)/2ʲ, `T1[i][j]` = C(n − j, i − j)/2ⁿ⁻ʲ.
//! - `takagi-landsberg` (`--w`): y = Σ wⁿ dist(2ⁿx, ℤ) from the maps
//!   (x, y) ↦ (x/2, x/2 + wy) and ((1 + x)/2, (1 − x)/2 + wy) in barycentric
//!   coordinates of (0,0), (1,0), (0,1) (paper Fig. 2 uses w = ½'s relative).
//! - `takagi-square` (`--w`): the same curve as a 4-point P-IFS over the square
//!   (0,0), (0,1), (1,1), (1,0), the paper's set-up of Figs. 2–3 (see
//!   [`takagi_square_operators`]).
//! - `bezier-bicubic`: a bicubic Bézier patch (tensor product of cubic de Casteljau).
//! - `takagi-landsberg-surface` (`--w`, `--height`, paper Figs. 1, 4): Takagi ⊗ Takagi,
//!   z = h(T_w(s) + T_w(t)) with a small shear so the corners are not pinched
//!   (see [`takagi_grid`]).
//! - `bezier-takagi` (`--w`): smooth (cubic Bézier) along s, rough (Takagi) along t.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::error::{IfsError, Result, invalid};
use crate::pifs::{CurveIfs, Pifs, SurfaceIfs};

/// Operators of one direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatorsSpec {
    /// Row-major N×N matrices T0, T1.
    pub operators: Vec<Vec<Vec<f64>>>,
}

/// A curve model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveSpec {
    /// Row-major N×N matrices T0, T1.
    pub operators: Vec<Vec<Vec<f64>>>,
    /// N control points, 2-D or 3-D.
    pub control_points: Vec<Vec<f64>>,
}

/// A tensor-product surface model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurfaceSpec {
    /// The s factor (N×N).
    pub s: OperatorsSpec,
    /// The t factor (M×M).
    pub t: OperatorsSpec,
    /// N rows of M 3-D points.
    pub control_points: Vec<Vec<Vec<f64>>>,
}

/// A model file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// Name (the preset's, or the user's).
    pub name: String,
    /// One line on what it is.
    #[serde(default)]
    pub description: String,
    /// Parameters the model was generated with (informative).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub parameters: BTreeMap<String, f64>,
    /// A curve model …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<CurveSpec>,
    /// … or a surface model.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<SurfaceSpec>,
}

/// A validated model.
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)] // one per command; boxing would buy nothing
pub enum Model {
    /// A P-IFS curve.
    Curve(CurveIfs),
    /// A tensor-product P-IFS surface.
    Surface(SurfaceIfs),
}

impl ModelFile {
    /// Parses JSON.
    ///
    /// # Errors
    /// [`IfsError::File`] with serde's line and column.
    pub fn from_json(text: &str) -> Result<Self> {
        serde_json::from_str(text).map_err(|e| IfsError::File(e.to_string()))
    }

    /// Pretty JSON (rows of a matrix on one line each would be nicer; serde_json
    /// writes one number per line, which every editor and `jq` handle).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("model files serialise");
        s.push('\n');
        s
    }

    /// Validates into a [`Model`].
    ///
    /// # Errors
    /// [`IfsError::File`] when neither or both of `curve`/`surface` are given;
    /// the constraint violations of [`Pifs::new`].
    pub fn build(&self) -> Result<Model> {
        match (&self.curve, &self.surface) {
            (Some(c), None) => Ok(Model::Curve(CurveIfs::new(
                Pifs::from_rows(&c.operators)?,
                &c.control_points,
            )?)),
            (None, Some(s)) => Ok(Model::Surface(SurfaceIfs::new(
                Pifs::from_rows(&s.s.operators)?,
                Pifs::from_rows(&s.t.operators)?,
                &s.control_points,
            )?)),
            _ => Err(IfsError::File(
                "a model has exactly one of \"curve\" or \"surface\"".into(),
            )),
        }
    }
}

impl Model {
    /// Back to a model file (e.g. after moving control points).
    pub fn to_file(&self, name: &str, description: &str) -> ModelFile {
        let pts = |c: &[[f64; 3]], dim: usize| -> Vec<Vec<f64>> {
            c.iter().map(|p| p[..dim].to_vec()).collect()
        };
        match self {
            Model::Curve(c) => ModelFile {
                name: name.into(),
                description: description.into(),
                parameters: BTreeMap::new(),
                curve: Some(CurveSpec {
                    operators: c.pifs.to_rows(),
                    control_points: pts(c.control(), c.dim()),
                }),
                surface: None,
            },
            Model::Surface(s) => {
                let (_, m) = s.grid_size();
                ModelFile {
                    name: name.into(),
                    description: description.into(),
                    parameters: BTreeMap::new(),
                    curve: None,
                    surface: Some(SurfaceSpec {
                        s: OperatorsSpec {
                            operators: s.s.to_rows(),
                        },
                        t: OperatorsSpec {
                            operators: s.t.to_rows(),
                        },
                        control_points: s.control().chunks(m).map(|r| pts(r, 3)).collect(),
                    }),
                }
            }
        }
    }
}

/// Parameters of the parametrised presets.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PresetParams {
    /// Takagi–Landsberg roughness w (default 1/√2).
    pub w: Option<f64>,
    /// Bézier degree for `bezier` (default 3).
    pub degree: Option<usize>,
    /// Height scale of the surface presets and of a curve squared into a surface
    /// (default ¼ for the Takagi surface, ½ otherwise).
    pub height: Option<f64>,
}

/// Default Takagi–Landsberg w: 1/√2, where α₂ = 2 exactly (a finite range).
pub const DEFAULT_W: f64 = std::f64::consts::FRAC_1_SQRT_2;

const PRESETS: &[(&str, &str)] = &[
    (
        "bezier-quadratic",
        "quadratic Bézier curve (0,0),(1,0),(1,1) as a P-IFS of de Casteljau matrices; κ(0) = 1/2",
    ),
    (
        "bezier-cubic",
        "cubic Bézier curve as a P-IFS of de Casteljau matrices",
    ),
    (
        "bezier",
        "Bézier curve of degree n (parameter degree, default 3) on an arc",
    ),
    (
        "takagi-landsberg",
        "Takagi–Landsberg curve y = Σ wⁿ dist(2ⁿx, ℤ) (parameter w, default 1/√2: a finite curvature range)",
    ),
    (
        "takagi-square",
        "Takagi–Landsberg curve as a 4-point P-IFS over the square (0,0),(0,1),(1,1),(1,0), as in the paper's Figs. 2–3 (parameter w); moving (1,1) bends it",
    ),
    (
        "bezier-bicubic",
        "bicubic Bézier patch (tensor product of cubic de Casteljau P-IFS)",
    ),
    (
        "takagi-landsberg-surface",
        "Takagi ⊗ Takagi surface z = h(T_w(s) + T_w(t)), slightly sheared (paper Figs. 1 and 4; parameters w, height)",
    ),
    (
        "bezier-takagi",
        "smooth along s (cubic Bézier), rough along t (Takagi, parameter w): one surface, two roughness orders",
    ),
];

/// Preset names with their one-line descriptions.
pub fn preset_names() -> &'static [(&'static str, &'static str)] {
    PRESETS
}

fn binomial(n: usize, k: usize) -> f64 {
    if k > n {
        return 0.0;
    }
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// De Casteljau subdivision operators at ½ for degree `n` (row-major).
pub fn bezier_operators(n: usize) -> Vec<Vec<Vec<f64>>> {
    let size = n + 1;
    let t0 = (0..size)
        .map(|i| {
            (0..size)
                .map(|j| binomial(j, i) / 2f64.powi(j as i32))
                .collect()
        })
        .collect();
    let t1 = (0..size)
        .map(|i| {
            (0..size)
                .map(|j| {
                    if i >= j {
                        binomial(n - j, i - j) / 2f64.powi((n - j) as i32)
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    vec![t0, t1]
}

/// Takagi–Landsberg operators for roughness `w` (row-major; control points
/// (0,0), (1,0), (0,1)).
pub fn takagi_operators(w: f64) -> Vec<Vec<Vec<f64>>> {
    vec![
        vec![
            vec![1.0, 0.0, 1.0 - w],
            vec![0.0, 0.5, 0.0],
            vec![0.0, 0.5, w],
        ],
        vec![
            vec![0.0, 0.0, -w],
            vec![0.5, 1.0, 0.5],
            vec![0.5, 0.0, 0.5 + w],
        ],
    ]
}

/// The Takagi–Landsberg maps as a 4-point P-IFS (row-major) for the control
/// points (0,0), (0,1), (1,1), (1,0) — the paper's Figs. 2–3 use a 4-point
/// P-IFS on this square, without printing its operators; this is one.
///
/// A 3-point P-IFS carries (1, x, y); the maps (x, y) ↦ (x/2, x/2 + wy) and
/// ((1 + x)/2, (1 − x)/2 + wy) also act linearly on x², so (1, x, y, x²) is
/// closed under them: S₀, S₁ below. The square's corners are the states
/// (1, xₖ, yₖ, qₖ) with q = xy at the corners (so the four are independent),
/// the columns of E, and Tᵢ = E⁻¹SᵢE. On the attractor q = x², so with the
/// square as control points the curve is y = Σ wⁿ dist(2ⁿx, ℤ); moving (1,1)
/// by δ adds x²·δ — Fig. 3's (1,1) → (1,−1) bends it down by 2x². The
/// eigenvalues are 1, ½, w, ¼: for w = 1/√2, λ₁ = w and α₂ = 2, as for the
/// 3-point P-IFS.
pub fn takagi_square_operators(w: f64) -> Vec<Vec<Vec<f64>>> {
    // E⁻¹SᵢE, worked out once (columns sum to 1).
    vec![
        vec![
            vec![1.0, 1.0 - w, 0.25 - w, 0.0],
            vec![0.0, w, w + 0.25, 0.5],
            vec![0.0, 0.0, 0.25, 0.0],
            vec![0.0, 0.0, 0.25, 0.5],
        ],
        vec![
            vec![0.25, 0.25 - w, 1.0 - w, 0.75],
            vec![0.25, w + 0.25, w - 1.0, -0.75],
            vec![0.25, 0.25, 1.0, 0.75],
            vec![0.25, 0.25, 0.0, 0.25],
        ],
    ]
}

const TAKAGI_X: [f64; 3] = [0.0, 1.0, 0.0];
const TAKAGI_Y: [f64; 3] = [0.0, 0.0, 1.0];

/// Horizontal shear of the Takagi surface (see [`takagi_grid`]).
pub const TAKAGI_SHEAR: f64 = 0.1;

/// Control grid of the Takagi ⊗ Takagi surface:
/// P_ab = (x_a + c·y_b, x_b + c·y_a, h(y_a + y_b)), so the attractor is
/// (s + c·T(t), t + c·T(s), h(T(s) + T(t))).
///
/// For w > ½ both factors leave every dyadic point with a vertical pseudo-tangent
/// (λ₁ = w has eigenvector (0, 1)); with c = 0 the two surface tangents would both
/// be vertical — the "pinched corner" the paper excludes (§4.1) — at every dyadic
/// point. The shear c tilts them apart while keeping the surface a height field
/// for small c.
pub fn takagi_grid(h: f64, c: f64) -> Vec<Vec<Vec<f64>>> {
    (0..3)
        .map(|a| {
            (0..3)
                .map(|b| {
                    vec![
                        TAKAGI_X[a] + c * TAKAGI_Y[b],
                        TAKAGI_X[b] + c * TAKAGI_Y[a],
                        h * (TAKAGI_Y[a] + TAKAGI_Y[b]),
                    ]
                })
                .collect()
        })
        .collect()
}

/// The tensor square of a 2-D curve: 𝕋 ⊗ 𝕋 with the control grid of
/// [`takagi_grid`] built from the curve's points (xₐ, yₐ):
/// P_ab = (x_a + c·y_b, x_b + c·y_a, h(y_a + y_b)), so a graph y = f(x) becomes the
/// surface z ≈ h(f(s) + f(t)).
///
/// # Errors
/// [`IfsError::InvalidParameter`] for a 3-D curve or non-finite h, c.
pub fn tensor_square(curve: &CurveIfs, h: f64, c: f64) -> Result<SurfaceIfs> {
    if curve.dim() != 2 {
        return Err(invalid(
            "preset",
            "only a 2-D curve can be squared into a surface",
        ));
    }
    if !(h.is_finite() && c.is_finite()) {
        return Err(invalid("height", format!("{h} is not finite")));
    }
    let p = curve.control();
    let grid: Vec<Vec<Vec<f64>>> = p
        .iter()
        .map(|a| {
            p.iter()
                .map(|b| vec![a[0] + c * b[1], b[0] + c * a[1], h * (a[1] + b[1])])
                .collect()
        })
        .collect();
    SurfaceIfs::new(curve.pifs.clone(), curve.pifs.clone(), &grid)
}

/// Cubic profile used by the mixed surface (x = a/3, y = these).
const CUBIC_PROFILE: [f64; 4] = [0.0, 0.25, -0.15, 0.1];

/// Heights of the bicubic preset's control grid (x = a/3, y = b/3).
const BICUBIC_Z: [[f64; 4]; 4] = [
    [0.0, 0.2, 0.15, 0.0],
    [0.25, 0.6, 0.45, 0.1],
    [0.05, 0.4, 0.75, 0.25],
    [0.0, 0.15, 0.3, 0.1],
];

/// The checked parameters of a preset: w, the height, the description and the
/// parameters recorded in the model file.
struct Checked {
    w: f64,
    h: f64,
    description: String,
    parameters: BTreeMap<String, f64>,
}

/// Checks the parameters `name` takes and their ranges.
fn check_preset(name: &str, p: &PresetParams) -> Result<Checked> {
    let takes_w = matches!(
        name,
        "takagi-landsberg" | "takagi-square" | "takagi-landsberg-surface" | "bezier-takagi"
    );
    if p.w.is_some() && !takes_w {
        return Err(invalid(
            "w",
            format!("preset {name} has no roughness parameter (⟨w⟩ applies to the takagi presets)"),
        ));
    }
    if p.degree.is_some() && name != "bezier" {
        return Err(invalid(
            "degree",
            format!("preset {name} has a fixed degree (⟨degree⟩ applies to `bezier`)"),
        ));
    }
    let surface = matches!(
        name,
        "bezier-bicubic" | "takagi-landsberg-surface" | "bezier-takagi"
    );
    let w = p.w.unwrap_or(DEFAULT_W);
    if !(w.is_finite() && w.abs() < 1.0) {
        return Err(invalid(
            "w",
            format!("{w} is outside (−1, 1) (|w| < 1 keeps the maps contractive)"),
        ));
    }
    let h = p.height.unwrap_or(if name == "takagi-landsberg-surface" {
        0.25
    } else {
        0.5
    });
    if !h.is_finite() {
        return Err(invalid("height", format!("{h} is not finite")));
    }
    let description = PRESETS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, d)| (*d).to_owned())
        .ok_or_else(|| {
            let names: Vec<&str> = PRESETS.iter().map(|(n, _)| *n).collect();
            invalid(
                "preset",
                format!("unknown preset {name:?}; known: {}", names.join(", ")),
            )
        })?;
    let mut parameters = BTreeMap::new();
    if takes_w {
        parameters.insert("w".to_owned(), w);
    }
    if surface {
        parameters.insert("height".to_owned(), h);
    }
    Ok(Checked {
        w,
        h,
        description,
        parameters,
    })
}

/// Row-major matrices or lists of points, as model files hold them.
type Rows = Vec<Vec<f64>>;

/// The Bézier curve of degree `n` (default 3) on a half circle: its
/// operators, control points and degree.
fn bezier_curve(n: Option<usize>) -> Result<(Vec<Rows>, Rows, f64)> {
    let n = n.unwrap_or(3);
    if !(1..=30).contains(&n) {
        return Err(invalid("degree", format!("{n} is outside 1..=30")));
    }
    let pts = (0..=n)
        .map(|i| {
            let a = std::f64::consts::PI * (1.0 - i as f64 / n as f64);
            vec![a.cos(), a.sin()]
        })
        .collect();
    Ok((bezier_operators(n), pts, n as f64))
}

/// The control grid of `bezier-bicubic`: heights from [`BICUBIC_Z`].
fn bicubic_grid(h: f64) -> Vec<Vec<Vec<f64>>> {
    (0..4)
        .map(|a| {
            (0..4)
                .map(|b| vec![a as f64 / 3.0, b as f64 / 3.0, h * 2.0 * BICUBIC_Z[a][b]])
                .collect()
        })
        .collect()
}

/// The control grid of `bezier-takagi`: a cubic profile along s, Takagi along t.
fn bezier_takagi_grid(h: f64) -> Vec<Vec<Vec<f64>>> {
    (0..4)
        .map(|a| {
            (0..3)
                .map(|b| {
                    vec![
                        a as f64 / 3.0,
                        TAKAGI_X[b],
                        2.0 * h * CUBIC_PROFILE[a] + h * TAKAGI_Y[b],
                    ]
                })
                .collect()
        })
        .collect()
}

/// Builds a preset.
///
/// # Errors
/// Unknown name; a parameter the preset does not take or out of range.
pub fn preset(name: &str, p: &PresetParams) -> Result<ModelFile> {
    let c = check_preset(name, p)?;
    let (w, h) = (c.w, c.h);
    let file = |parameters: BTreeMap<String, f64>| ModelFile {
        name: name.into(),
        description: c.description.clone(),
        parameters,
        curve: None,
        surface: None,
    };
    let curve = |operators, control_points| ModelFile {
        curve: Some(CurveSpec {
            operators,
            control_points,
        }),
        ..file(c.parameters.clone())
    };
    let surf = |s, t, control_points| ModelFile {
        surface: Some(SurfaceSpec {
            s: OperatorsSpec { operators: s },
            t: OperatorsSpec { operators: t },
            control_points,
        }),
        ..file(c.parameters.clone())
    };
    Ok(match name {
        "bezier-quadratic" => curve(
            bezier_operators(2),
            vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]],
        ),
        "bezier-cubic" => curve(
            bezier_operators(3),
            vec![
                vec![0.0, 0.0],
                vec![1.0, 1.0],
                vec![2.0, -1.0],
                vec![3.0, 0.0],
            ],
        ),
        "bezier" => {
            let (ops, pts, degree) = bezier_curve(p.degree)?;
            let mut f = curve(ops, pts);
            f.parameters.insert("degree".to_owned(), degree);
            f
        }
        "takagi-landsberg" => curve(
            takagi_operators(w),
            vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![0.0, 1.0]],
        ),
        "takagi-square" => curve(
            takagi_square_operators(w),
            vec![
                vec![0.0, 0.0],
                vec![0.0, 1.0],
                vec![1.0, 1.0],
                vec![1.0, 0.0],
            ],
        ),
        "bezier-bicubic" => surf(bezier_operators(3), bezier_operators(3), bicubic_grid(h)),
        "takagi-landsberg-surface" => surf(
            takagi_operators(w),
            takagi_operators(w),
            takagi_grid(h, TAKAGI_SHEAR),
        ),
        "bezier-takagi" => surf(
            bezier_operators(3),
            takagi_operators(w),
            bezier_takagi_grid(h),
        ),
        _ => unreachable!("checked against PRESETS"),
    })
}
