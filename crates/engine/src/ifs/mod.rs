//! Projected-IFS fractal curves and surfaces with their DCF/SDCF families and
//! pseudo-curvature ranges (poull-gentil): models from presets or files, edited
//! through their control points; attractor meshes with per-vertex curvature;
//! the Figure 2 drawing; SDCF meshes (Figure 4); curvature reports.

use std::path::Path;

use asperity_core::{MemoryBudget, TriMesh};
use asperity_ifs::curvature::{
    CurveAtReport, CurveOperatorReport, SurfaceAtReport, SurfaceOperatorReport, curve_at,
    curve_report, surface_at, surface_report, vertex_curvature,
};
use asperity_ifs::model::{TAKAGI_SHEAR, tensor_square};
use asperity_ifs::sdcf::{Start, dcf_polyline, sdcf_mesh, start_point, tensor_dcf_polyline};
use asperity_ifs::{
    CurveIfs, DirectionAnalysis, FamilyOptions, Model, ModelFile, PresetParams, SurfaceIfs, preset,
};
use asperity_render::plot::{Drawing, Stroke, drawing_svg};
use nalgebra::DVector;
use serde_json::Value;

use crate::error::{Result, ensure, invalid};
use crate::files::read_text;

mod params;

pub use params::{
    Bound, IfsCurvatureParams, IfsCurveParams, IfsDcfParams, IfsModelParams, IfsPresetParams,
    IfsSdcfParams, IfsSurfaceParams,
};

/// Where a model comes from and how it is edited, as `asperity ifs …` says it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelSpec {
    /// A preset name …
    pub preset: Option<String>,
    /// … or a model file (JSON).
    pub file: Option<std::path::PathBuf>,
    /// A model file's JSON text given inline (the Python package builds it
    /// from arrays); used when neither a preset nor a file is named.
    pub json: Option<String>,
    /// Preset parameters (w, degree, height).
    pub params: PresetParams,
    /// A file of control points replacing the model's (JSON or CSV).
    pub control: Option<std::path::PathBuf>,
    /// Control-point moves: `I=x,y[,z]` (curves) or `I,J=x,y,z` (surfaces).
    pub moves: Vec<String>,
    /// The family of DCFs: dyadic depth and periods.
    pub family: FamilyOptions,
}

/// A model as used: built, with its control points edited.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// Its name (the preset's or the file's).
    pub name: String,
    /// The preset's or the file's description and (informative) parameters.
    pub about: (String, std::collections::BTreeMap<String, f64>),
    /// The model.
    pub model: Model,
    /// The family of DCFs to examine.
    pub opts: FamilyOptions,
}

/// Builds the model of `spec`.
///
/// # Errors
/// An unknown preset, an unreadable or invalid model or control file, a bad
/// move, or a model that breaks a constraint.
pub fn load(spec: &ModelSpec) -> Result<Loaded> {
    let p = &spec.params;
    let (name, file) = match (&spec.preset, &spec.file) {
        (Some(name), _) => (name.clone(), preset(name, p)?),
        (None, Some(path)) => {
            ensure(*p == PresetParams::default(), || {
                "⟨w⟩, ⟨degree⟩ and ⟨height⟩ apply to presets; edit the model file instead".into()
            })?;
            let f = ModelFile::from_json(&read_text(path)?)
                .map_err(|e| invalid(format!("{}: {e}", path.display())))?;
            (f.name.clone(), f)
        }
        (None, None) => match &spec.json {
            Some(text) => {
                ensure(*p == PresetParams::default(), || {
                    "⟨w⟩, ⟨degree⟩ and ⟨height⟩ apply to presets; edit the model file instead"
                        .into()
                })?;
                let f = ModelFile::from_json(text).map_err(|e| invalid(format!("model: {e}")))?;
                (f.name.clone(), f)
            }
            None => return Err(invalid("give ⟨preset⟩ or ⟨ifs⟩")),
        },
    };
    let mut model = file
        .build()
        .map_err(|e| invalid(format!("model {name}: {e}")))?;
    if let Some(path) = &spec.control {
        model = apply_control(model, &read_control(path)?, path)?;
    }
    for m in &spec.moves {
        apply_move(&mut model, m)?;
    }
    Ok(Loaded {
        name,
        about: (file.description.clone(), file.parameters.clone()),
        model,
        opts: spec.family,
    })
}

impl Loaded {
    /// The model as a file (to write with `ifs preset`), with the preset's or
    /// the file's description and parameters.
    pub fn file(&self) -> ModelFile {
        ModelFile {
            parameters: self.about.1.clone(),
            ..self.model.to_file(&self.name, &self.about.0)
        }
    }

    /// The curve model.
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for a surface model.
    pub fn curve(self) -> Result<(String, CurveIfs, FamilyOptions)> {
        match self.model {
            Model::Curve(c) => Ok((self.name, c, self.opts)),
            Model::Surface(_) => Err(invalid(format!(
                "{} is a surface; use `asperity ifs surface` / `ifs sdcf` (curves: bezier-quadratic, bezier-cubic, bezier, takagi-landsberg)",
                self.name
            ))),
        }
    }

    /// The surface model; a 2-D curve model becomes its tensor square
    /// (z ≈ h(f(s) + f(t)), see `asperity_ifs::model::tensor_square`), of height
    /// `height` (default 0.25).
    ///
    /// # Errors
    /// [`crate::EngineError::Invalid`] for a curve that cannot be squared.
    pub fn surface(self, height: Option<f64>) -> Result<(String, SurfaceIfs, FamilyOptions)> {
        match self.model {
            Model::Surface(s) => Ok((self.name, s, self.opts)),
            Model::Curve(c) => {
                let s = tensor_square(&c, height.unwrap_or(0.25), TAKAGI_SHEAR).map_err(|e| {
                    invalid(format!(
                        "{} is a curve and cannot be squared into a surface (surfaces: bezier-bicubic, takagi-landsberg-surface, bezier-takagi): {e}",
                        self.name
                    ))
                })?;
                Ok((format!("{} ⊗ {}", self.name, self.name), s, self.opts))
            }
        }
    }
}

/// Comma-separated finite numbers.
fn parse_numbers(s: &str, what: &str) -> Result<Vec<f64>> {
    s.split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| invalid(format!("{what}: {x:?} is not a finite number")))
        })
        .collect()
}

/// Control points from JSON (as is) or CSV (`x,y[,z]` per line; a header line
/// and `#` comments are skipped).
fn read_control(path: &Path) -> Result<Value> {
    let text = read_text(path)?;
    if path.extension().and_then(|e| e.to_str()) == Some("json") {
        return serde_json::from_str(&text)
            .map_err(|e| invalid(format!("parsing {}: {e}", path.display())));
    }
    let mut pts = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match parse_numbers(line, "control point") {
            Ok(v) => pts.push(Value::from(v)),
            Err(_) if pts.is_empty() && i == 0 => {} // a header
            Err(e) => return Err(invalid(format!("{} line {}: {e}", path.display(), i + 1))),
        }
    }
    Ok(Value::Array(pts))
}

fn points(v: &Value, what: &str) -> Result<Vec<Vec<f64>>> {
    v.as_array()
        .ok_or_else(|| invalid(format!("{what}: expected a list of points")))?
        .iter()
        .map(|p| {
            p.as_array()
                .ok_or_else(|| invalid(format!("{what}: a point is a list of 2 or 3 numbers")))?
                .iter()
                .map(|x| {
                    x.as_f64()
                        .ok_or_else(|| invalid(format!("{what}: {x} is not a number")))
                })
                .collect()
        })
        .collect()
}

/// Rows of control points of an N × M surface grid: nested rows, or a flat
/// list in row-major order.
fn grid_rows(v: &Value, m: usize, what: &str) -> Result<Vec<Vec<Vec<f64>>>> {
    let nested = v
        .as_array()
        .and_then(|a| a.first())
        .and_then(|r| r.as_array())
        .and_then(|r| r.first())
        .is_some_and(Value::is_array);
    if nested {
        return v
            .as_array()
            .into_iter()
            .flatten()
            .map(|r| points(r, what))
            .collect();
    }
    let flat = points(v, what)?;
    ensure(flat.len().is_multiple_of(m), || {
        format!(
            "{what}: {} points do not fill rows of {m} (the grid is N×{m}, row-major)",
            flat.len()
        )
    })?;
    Ok(flat.chunks(m).map(<[Vec<f64>]>::to_vec).collect())
}

fn apply_control(model: Model, v: &Value, path: &Path) -> Result<Model> {
    let what = path.display().to_string();
    Ok(match model {
        Model::Curve(c) => Model::Curve(CurveIfs::new(c.pifs.clone(), &points(v, &what)?)?),
        Model::Surface(s) => {
            let rows = grid_rows(v, s.grid_size().1, &what)?;
            Model::Surface(SurfaceIfs::new(s.s.clone(), s.t.clone(), &rows)?)
        }
    })
}

fn apply_move(model: &mut Model, spec: &str) -> Result<()> {
    let (idx, to) = spec
        .split_once('=')
        .ok_or_else(|| invalid(format!("⟨move⟩ {spec:?}: expected I=x,y[,z] or I,J=x,y,z")))?;
    let idx: Vec<usize> = idx
        .split(',')
        .map(|x| {
            x.trim()
                .parse()
                .map_err(|_| invalid(format!("⟨move⟩ {spec:?}: {x:?} is not an index")))
        })
        .collect::<Result<_>>()?;
    let v = parse_numbers(to, &format!("⟨move⟩ {spec:?}"))?;
    ensure((2..=3).contains(&v.len()), || {
        format!("⟨move⟩ {spec:?}: a point has 2 or 3 coordinates")
    })?;
    let p = [v[0], v[1], v.get(2).copied().unwrap_or(0.0)];
    match (model, idx.as_slice()) {
        (Model::Curve(c), [i]) => c.move_point(*i, p)?,
        (Model::Surface(s), [a, b]) => {
            ensure(v.len() == 3, || {
                format!("⟨move⟩ {spec:?}: surface points are x,y,z")
            })?;
            s.move_point(*a, *b, p)?;
        }
        (Model::Curve(_), _) => {
            return Err(invalid(format!(
                "⟨move⟩ {spec:?}: a curve point is I=x,y[,z]"
            )));
        }
        (Model::Surface(_), _) => {
            return Err(invalid(format!(
                "⟨move⟩ {spec:?}: a surface point is I,J=x,y,z"
            )));
        }
    }
    Ok(())
}

const T0_COLOR: [u8; 3] = [214, 39, 40];
const T1_COLOR: [u8; 3] = [31, 119, 180];

fn lighter(c: [u8; 3]) -> [u8; 3] {
    c.map(|x| (x as u32 + 2 * 255).div_euclid(3) as u8)
}

fn xy(p: &[[f64; 3]]) -> Vec<(f64, f64)> {
    p.iter().map(|q| (q[0], q[1])).collect()
}

/// Strokes of one operator's family of DCFs: `family` members (light) and the
/// lower and upper bounds (bold).
fn family_strokes(
    c: &CurveIfs,
    a: &asperity_ifs::OperatorAnalysis,
    family: usize,
) -> Result<Vec<Stroke>> {
    let color = if a.operator == 0 { T0_COLOR } else { T1_COLOR };
    let Some(d) = &a.dcf else {
        return Ok(Vec::new());
    };
    let len = d.members.len();
    if len == 0 {
        return Ok(Vec::new());
    }
    let k = family.min(len);
    let mut strokes = Vec::new();
    for j in 0..k {
        let m = &d.members[j * (len - 1) / (k - 1).max(1)];
        strokes.push(Stroke {
            points: xy(&dcf_polyline(c, a, &m.point, 200)?),
            color: lighter(color),
            width: 1,
            label: (j == 0).then(|| format!("family of DCF(T{}) ({})", a.operator, a.class.name())),
        });
    }
    for (m, which) in [(d.lower(), "lower"), (d.upper(), "upper")] {
        if let Some(m) = m {
            strokes.push(Stroke {
                points: xy(&dcf_polyline(c, a, &m.point, 200)?),
                color,
                width: 2,
                label: Some(format!(
                    "{which} bound of T{} (start s = {:.4}, c₂ = {:.4})",
                    a.operator, m.start, m.c2
                )),
            });
        }
    }
    Ok(strokes)
}

/// The paper's Figure 2 as SVG: the attractor (black) with, for each operator,
/// members of its family of DCFs (light) and the lower/upper bound members
/// (bold); `highlight` adds one requested DCF in green.
///
/// # Errors
/// The IFS's (a depth too large) and the plot's.
pub fn figure(
    c: &CurveIfs,
    an: &DirectionAnalysis,
    name: &str,
    family: usize,
    highlight: Option<(usize, &[[f64; 3]])>,
) -> Result<String> {
    let mut strokes = vec![Stroke {
        points: xy(&c.attractor(12)?),
        color: [0, 0, 0],
        width: 2,
        label: Some(format!("attractor ({name})")),
    }];
    for a in &an.operators {
        strokes.extend(family_strokes(c, a, family)?);
    }
    if let Some((op, pts)) = highlight {
        strokes.push(Stroke {
            points: xy(pts),
            color: [44, 160, 44],
            width: 3,
            label: Some(format!("the requested DCF of T{op}")),
        });
    }
    let title = format!("{name}: attractor and families of DCFs");
    Ok(drawing_svg(&Drawing { title, strokes }, 900, 700)?)
}

/// The elements of the paper's Figures 2 and 3 on curve `c` as SVG: the
/// attractor (black) and its control polygon (grey), the family of DCFs of
/// T0 (red), the DCF of T1 from the fixed point c₀ of T0 (blue), the orbit
/// T1ⁿ·c₀ (green crosses, n = 0 … 10, running into c₁), and with `tangents`
/// the pseudo-tangents of both transformations at their fixed points (purple:
/// the projected eigenvector of λ₁).
///
/// # Errors
/// The IFS's (a depth too large), no DCF for an operator, and the plot's.
pub fn orbit_figure(
    c: &CurveIfs,
    an: &DirectionAnalysis,
    title: &str,
    tangents: bool,
) -> Result<String> {
    let control: Vec<[f64; 3]> = c.control().to_vec();
    let mut strokes = vec![
        Stroke {
            points: xy(&control),
            color: [150, 150, 150],
            width: 1,
            label: Some("control polygon".into()),
        },
        Stroke {
            points: xy(&c.attractor(12)?),
            color: [0, 0, 0],
            width: 2,
            label: Some("attractor".into()),
        },
    ];
    let [t0, t1] = &an.operators;
    strokes.extend(family_strokes(c, t0, 10)?);
    let c0 = c.pifs.fixed_point(0).clone();
    strokes.push(Stroke {
        points: xy(&dcf_polyline(c, t1, &c0, 200)?),
        color: T1_COLOR,
        width: 2,
        label: Some("DCF of T1 from c₀".into()),
    });
    let size = control
        .iter()
        .flat_map(|p| {
            control
                .iter()
                .map(move |q| (p[0] - q[0]).hypot(p[1] - q[1]))
        })
        .fold(0.0, f64::max);
    strokes.extend(orbit_strokes(c, 0.008 * size));
    if tangents {
        strokes.extend(
            [t0, t1]
                .into_iter()
                .filter_map(|a| tangent_stroke(c, a, 0.25 * size)),
        );
    }
    let title = title.to_string();
    Ok(drawing_svg(&Drawing { title, strokes }, 900, 700)?)
}

/// Green crosses of half-size `r` at the orbit T1ⁿ·c₀, n = 0 … 10 (c₀ the
/// fixed point of T0).
fn orbit_strokes(c: &CurveIfs, r: f64) -> Vec<Stroke> {
    let mut strokes = Vec::new();
    let mut q = c.pifs.fixed_point(0).clone();
    for n in 0..=10 {
        let p = c.project(q.as_slice());
        for (dx, dy) in [(r, r), (r, -r)] {
            strokes.push(Stroke {
                points: vec![(p[0] - dx, p[1] - dy), (p[0] + dx, p[1] + dy)],
                color: [44, 160, 44],
                width: 2,
                label: (n == 0 && dx == dy).then(|| "T1ⁿ·c₀, n = 0 … 10".to_string()),
            });
        }
        q = c.pifs.operator(1) * q;
    }
    strokes
}

/// The pseudo-tangent of operator `a` at its fixed point, a purple segment of
/// half-length `half`: the projected eigenvector of λ₁ (a barycentric vector,
/// entries summing to 0, projects to Σ vₖPₖ). None without an eigenbasis.
fn tangent_stroke(c: &CurveIfs, a: &asperity_ifs::OperatorAnalysis, half: f64) -> Option<Stroke> {
    let asperity_ifs::spectrum::Structure::Diagonalisable { vectors, .. } = &a.spectrum.structure
    else {
        return None;
    };
    let control = c.control();
    let at = c.project(c.pifs.fixed_point(a.operator).as_slice());
    let v = vectors.column(1);
    let dir: Vec<f64> = (0..2)
        .map(|k| (0..v.len()).map(|i| v[i] * control[i][k]).sum::<f64>())
        .collect();
    let h = half / dir[0].hypot(dir[1]).max(1e-300);
    Some(Stroke {
        points: vec![
            (at[0] - h * dir[0], at[1] - h * dir[1]),
            (at[0] + h * dir[0], at[1] + h * dir[1]),
        ],
        color: [128, 0, 160],
        width: 2,
        label: Some(format!(
            "pseudo-tangent of T{} at c{}",
            a.operator, a.operator
        )),
    })
}

/// Grid lines of a surface's control net (rows, then columns).
pub fn control_net(s: &SurfaceIfs) -> Vec<Vec<[f64; 3]>> {
    let (n, m) = s.grid_size();
    let p = s.control();
    let mut lines: Vec<Vec<[f64; 3]>> = (0..n).map(|a| p[a * m..(a + 1) * m].to_vec()).collect();
    lines.extend((0..m).map(|b| (0..n).map(|a| p[a * m + b]).collect()));
    lines
}

/// The attractor mesh at `depth` with per-vertex pseudo-curvature when asked
/// and finite; the note says why there is none otherwise.
///
/// # Errors
/// The IFS's (the memory budget).
pub fn surface_mesh(
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    depth: u32,
    curvature: bool,
    budget: &MemoryBudget,
) -> Result<(TriMesh, Option<String>)> {
    let mut mesh = s.attractor_mesh(depth, budget)?;
    if !curvature {
        return Ok((mesh, None));
    }
    let (an_s, an_t) = (
        DirectionAnalysis::new(&s.s, opts),
        DirectionAnalysis::new(&s.t, opts),
    );
    match vertex_curvature(s, &an_s, &an_t, depth) {
        Ok(attrs) => {
            for (name, v) in attrs {
                mesh = mesh.with_scalar(name, v)?;
            }
            Ok((mesh, None))
        }
        Err(e) => Ok((mesh, Some(format!("no curvature attributes: {e}")))),
    }
}

/// Both directions analysed, and the starting points `starts` of 𝒯ᵢⱼ's factors.
fn factor_starts(
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    (i, j): (usize, usize),
    starts: (Start, Start),
) -> Result<(
    DirectionAnalysis,
    DirectionAnalysis,
    DVector<f64>,
    DVector<f64>,
)> {
    let (an_s, an_t) = (
        DirectionAnalysis::new(&s.s, opts),
        DirectionAnalysis::new(&s.t, opts),
    );
    let q = start_point(&s.s, &an_s.operators[i], starts.0)?;
    let q2 = start_point(&s.t, &an_t.operators[j], starts.1)?;
    Ok((an_s, an_t, q, q2))
}

/// The SDCF mesh of 𝒯ᵢⱼ from the starting points `starts` (one per direction).
///
/// # Errors
/// The IFS's (no DCF for the operator, the memory budget).
pub fn sdcf_for(
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    (i, j): (usize, usize),
    starts: (Start, Start),
    resolution: usize,
    budget: &MemoryBudget,
) -> Result<TriMesh> {
    let (an_s, an_t, q, q2) = factor_starts(s, opts, (i, j), starts)?;
    let (a, b) = (&an_s.operators[i], &an_t.operators[j]);
    Ok(sdcf_mesh(s, (a, &q), (b, &q2), resolution, budget)?)
}

/// The DCF of the tensor operator 𝒯ᵢⱼ from its own spectrum, from the same
/// starting points as [`sdcf_for`], as `samples + 1` points.
///
/// # Errors
/// No DCF for a factor (the starting point) or for 𝒯ᵢⱼ; `samples` out of range.
pub fn tensor_dcf_for(
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    (i, j): (usize, usize),
    starts: (Start, Start),
    samples: usize,
) -> Result<Vec<[f64; 3]>> {
    let (_, _, q, q2) = factor_starts(s, opts, (i, j), starts)?;
    Ok(tensor_dcf_polyline(s, (i, j), (&q, &q2), samples)?)
}

/// The pseudo-curvature of every operator of a model and at given points.
#[derive(Clone, Debug)]
pub enum CurvatureReport {
    /// A curve's: per operator, and at parameters s.
    Curve(Vec<CurveOperatorReport>, Vec<CurveAtReport>),
    /// A surface's: per operator pair, and at parameters (s, t).
    Surface(Vec<SurfaceOperatorReport>, Vec<SurfaceAtReport>),
}

/// The curvature report of `l` at the points `at` (`S` for curves, `S,T` for surfaces).
///
/// # Errors
/// [`crate::EngineError::Invalid`] for a point that does not parse; the IFS's
/// (a point outside [0, 1]).
pub fn curvature_report(l: &Loaded, at: &[String]) -> Result<CurvatureReport> {
    match &l.model {
        Model::Curve(c) => {
            let an = DirectionAnalysis::new(&c.pifs, &l.opts);
            let ops = curve_report(c, &an);
            let pts = at
                .iter()
                .map(|s| {
                    let s: f64 = s.trim().parse().map_err(|_| {
                        invalid(format!("⟨at⟩ {s:?}: a curve point is one parameter S"))
                    })?;
                    Ok(curve_at(c, &an, s)?)
                })
                .collect::<Result<_>>()?;
            Ok(CurvatureReport::Curve(ops, pts))
        }
        Model::Surface(s) => {
            let (an_s, an_t) = (
                DirectionAnalysis::new(&s.s, &l.opts),
                DirectionAnalysis::new(&s.t, &l.opts),
            );
            let ops = surface_report(s, &an_s, &an_t);
            let pts = at
                .iter()
                .map(|v| {
                    let (u, w): (f64, f64) = pair(v, "⟨at⟩")?;
                    Ok(surface_at(s, &an_s, &an_t, u, w)?)
                })
                .collect::<Result<_>>()?;
            Ok(CurvatureReport::Surface(ops, pts))
        }
    }
}

/// `A,B` as two values.
///
/// # Errors
/// [`crate::EngineError::Invalid`] naming `what`.
pub fn pair<T: std::str::FromStr>(s: &str, what: &str) -> Result<(T, T)> {
    let (a, b) = s
        .split_once(',')
        .ok_or_else(|| invalid(format!("{what} {s:?}: expected two values A,B")))?;
    let p = |x: &str| {
        x.trim()
            .parse::<T>()
            .map_err(|_| invalid(format!("{what} {s:?}: {x:?} is not valid")))
    };
    Ok((p(a)?, p(b)?))
}

/// Every preset with its kind ("curve" or "surface") and description, as the
/// CLI's `ifs presets --json` lists them.
pub fn presets() -> Vec<Value> {
    asperity_ifs::preset_names()
        .iter()
        .map(|(n, d)| {
            let kind = match preset(n, &PresetParams::default()).map(|f| f.surface.is_some()) {
                Ok(true) => "surface",
                _ => "curve",
            };
            serde_json::json!({"name": n, "kind": kind, "description": d})
        })
        .collect()
}

/// A DCF drawn as a polyline, with what its operator is.
#[derive(Clone, Debug, PartialEq)]
pub struct DcfCurve {
    /// The polyline's points.
    pub points: Vec<[f64; 3]>,
    /// The operator's class name.
    pub class: &'static str,
    /// Its α exponents, when it has a DCF.
    pub alpha: Option<Vec<f64>>,
}

/// The DCF of operator `i` of a curve (poull-gentil §3): its polyline of
/// `samples` + 1 points from the start (`start`, else the operator's fixed
/// end 1 − i, or a bound), with the operator's class and its α exponents.
///
/// # Errors
/// The IFS's (no DCF for the operator, a start outside [0, 1]).
pub fn dcf_for(
    c: &CurveIfs,
    opts: &FamilyOptions,
    i: usize,
    start: Option<Start>,
    samples: usize,
) -> Result<DcfCurve> {
    ensure(i < 2, || format!("⟨operator={i}⟩: the operator is 0 or 1"))?;
    let an = DirectionAnalysis::new(&c.pifs, opts);
    let op = &an.operators[i];
    let q = start_point(
        &c.pifs,
        op,
        start.unwrap_or(Start::Parameter(1.0 - i as f64)),
    )?;
    Ok(DcfCurve {
        points: dcf_polyline(c, op, &q, samples)?,
        class: op.class.name(),
        alpha: op.dcf.as_ref().map(|d| d.alpha.clone()),
    })
}

/// The CLI's `ifs curvature --json` document (without its timing): the
/// model, its family options, control points, per-operator reports and the
/// reports at the asked points.
///
/// # Errors
/// Serialising a report (never for finite numbers).
pub fn curvature_doc(l: &Loaded, report: &CurvatureReport) -> Result<Value> {
    let file = l.file();
    let mut doc = serde_json::json!({
        "model": l.name,
        "family": {"dyadic_depth": l.opts.dyadic_depth, "period": l.opts.period},
    });
    match report {
        CurvatureReport::Curve(ops, at) => {
            doc["kind"] = "curve".into();
            doc["control_points"] =
                serde_json::json!(file.curve.as_ref().map(|c| &c.control_points));
            doc["operators"] = json_value(ops)?;
            doc["at"] = json_value(at)?;
        }
        CurvatureReport::Surface(ops, at) => {
            doc["kind"] = "surface".into();
            doc["control_points"] =
                serde_json::json!(file.surface.as_ref().map(|s| &s.control_points));
            doc["operators"] = json_value(ops)?;
            doc["at"] = json_value(at)?;
        }
    }
    Ok(doc)
}

fn json_value(v: &impl serde::Serialize) -> Result<Value> {
    serde_json::to_value(v).map_err(|e| invalid(format!("a curvature report: {e}")))
}
