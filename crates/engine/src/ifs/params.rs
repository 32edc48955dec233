//! The parameters of the poull-gentil commands: `ifs preset`, `ifs curve`,
//! `ifs surface`, `ifs dcf`, `ifs sdcf` and `ifs curvature`. Each starts from
//! a model ([`IfsModelParams`]: a preset with its parameters, a model file or
//! its text, edited through its control points) and adds its own.

use std::path::PathBuf;

use asperity_core::{MemoryBudget, TriMesh};
use asperity_ifs::sdcf::Start;
use asperity_ifs::{CurveIfs, FamilyOptions, PresetParams, SurfaceIfs};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{
    CurvatureReport, DcfCurve, Loaded, ModelSpec, curvature_doc, curvature_report, dcf_for, load,
    sdcf_for, surface_mesh,
};
use crate::error::{EngineError, Result};
use crate::params::{JobParams, Numbers, choice};

choice! {
    /// Which member of a DCF family starts the curve.
    pub enum Bound {
        /// The smallest c₂ (the lower-bound DCF).
        Lower = "lower",
        /// The largest c₂ (the upper-bound DCF).
        Upper = "upper",
    }
}

/// Where a model comes from and how it is edited (every `ifs` command).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsModelParams {
    /// Built-in preset (`asperity ifs presets` lists them).
    #[arg(long, value_name = "NAME", conflicts_with = "ifs")]
    pub preset: Option<String>,
    /// Model file (JSON), e.g. one written by `asperity ifs preset NAME -o FILE` and edited.
    #[arg(long, value_name = "FILE")]
    pub ifs: Option<PathBuf>,
    /// A model file's JSON text, given inline (Python builds it from arrays).
    #[arg(skip)]
    pub model: Option<String>,
    /// Takagi–Landsberg roughness w, |w| < 1 (takagi presets; default 1/√2 ≈ 0.7071).
    #[schemars(range(min = -1.0, max = 1.0))]
    #[arg(long, allow_hyphen_values = true)]
    pub w: Option<f64>,
    /// Degree of the `bezier` preset (default 3).
    #[schemars(range(min = 1, max = 64))]
    #[arg(long)]
    pub degree: Option<usize>,
    /// Height scale of the surface presets (default 0.25 for takagi-landsberg-surface, 0.5
    /// otherwise; a squared curve 0.25).
    #[schemars(range(min = -1e6, max = 1e6))]
    #[arg(long, allow_hyphen_values = true)]
    pub height: Option<f64>,
    /// Replace the control points: JSON (a list of points, or N rows of M points) or CSV (x,y
    /// or x,y,z per line; surfaces row-major).
    #[arg(long, value_name = "FILE")]
    pub control: Option<PathBuf>,
    /// Move control points: I=x,y or I=x,y,z (curves), I,J=x,y,z (surfaces).
    #[arg(long = "move", value_name = "SPEC", allow_hyphen_values = true)]
    pub r#move: Vec<String>,
    /// Family of DCFs: dyadic starting points k/2^D in the fundamental domain.
    #[schemars(range(min = 1, max = 20))]
    #[arg(long, default_value_t = Self::DEFAULT.family_depth)]
    pub family_depth: u32,
    /// Family of DCFs: periodic starting points of every period up to P.
    #[schemars(range(max = 20))]
    #[arg(long, default_value_t = Self::DEFAULT.family_period)]
    pub family_period: u32,
}

impl IfsModelParams {
    /// No model yet, the family of the paper's figures.
    pub const DEFAULT: Self = Self {
        preset: None,
        ifs: None,
        model: None,
        w: None,
        degree: None,
        height: None,
        control: None,
        r#move: Vec::new(),
        family_depth: 10,
        family_period: 12,
    };

    /// The model, built and edited.
    ///
    /// # Errors
    /// As [`load`].
    pub fn load(&self) -> Result<Loaded> {
        load(&ModelSpec {
            preset: self.preset.clone(),
            file: self.ifs.clone(),
            json: self.model.clone(),
            params: PresetParams {
                w: self.w,
                degree: self.degree,
                height: self.height,
            },
            control: self.control.clone(),
            moves: self.r#move.clone(),
            family: FamilyOptions {
                dyadic_depth: self.family_depth,
                period: self.family_period,
            },
        })
    }
}

impl Default for IfsModelParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Declares an IFS job: a model plus the job's own fields.
macro_rules! ifs_job {
    ($t:ident, $job:literal) => {
        impl JobParams for $t {
            const JOB: &'static str = $job;
            const SEEDED: bool = false;
        }
    };
}

/// `ifs preset`: a model (a preset, or a file, with its edits) as an editable
/// model file (poull-gentil §2).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsPresetParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub model: IfsModelParams,
}
ifs_job!(IfsPresetParams, "ifs preset");

/// `ifs curve`: a projected-IFS curve's attractor (poull-gentil §2.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsCurveParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub model: IfsModelParams,
    /// Dyadic depth D: 2^D + 1 points.
    #[schemars(range(max = 26))]
    #[arg(long, default_value_t = Self::DEFAULT.depth)]
    pub depth: u32,
}

impl IfsCurveParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        model: IfsModelParams::DEFAULT,
        depth: 12,
    };

    /// The model's name, the curve and its attractor.
    ///
    /// # Errors
    /// As [`load`]; a surface model.
    pub fn attractor(&self) -> Result<(String, CurveIfs, FamilyOptions, Vec<[f64; 3]>)> {
        crate::params::validate(self)?;
        let (name, c, opts) = self.model.load()?.curve()?;
        let pts = c.attractor(self.depth)?;
        Ok((name, c, opts, pts))
    }
}

impl Default for IfsCurveParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}
ifs_job!(IfsCurveParams, "ifs curve");

/// `ifs surface`: a tensor-product IFS surface's attractor mesh with
/// per-vertex pseudo-curvature (poull-gentil §3–4; a 2-D curve model is
/// squared, z ≈ h(f(s) + f(t))).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsSurfaceParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub model: IfsModelParams,
    /// Dyadic depth D: (2^D + 1)² vertices (10 ≈ 1M).
    #[schemars(range(max = 14))]
    #[arg(long, default_value_t = Self::DEFAULT.depth)]
    pub depth: u32,
    /// The per-vertex pseudo-curvature attributes (the CLI's --no-curvature leaves them out).
    #[arg(long = "no-curvature", action = clap::ArgAction::SetFalse)]
    pub curvature: bool,
}

impl IfsSurfaceParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        model: IfsModelParams::DEFAULT,
        depth: 8,
        curvature: true,
    };

    /// The model's name, the surface, the attractor mesh and a note for the
    /// user (curvature left out where it is not defined).
    ///
    /// # Errors
    /// As [`load`]; a curve that cannot be squared; the budget.
    pub fn mesh(
        &self,
        budget: &MemoryBudget,
    ) -> Result<(String, SurfaceIfs, TriMesh, Option<String>)> {
        crate::params::validate(self)?;
        let (name, s, opts) = self.model.load()?.surface(self.model.height)?;
        let (mesh, note) = surface_mesh(&s, &opts, self.depth, self.curvature, budget)?;
        Ok((name, s, mesh, note))
    }
}

impl Default for IfsSurfaceParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}
ifs_job!(IfsSurfaceParams, "ifs surface");

/// `ifs dcf`: one DCF of a curve operator Tᵢ from its fixed point to a start
/// point (poull-gentil §3, Fig. 2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsDcfParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub model: IfsModelParams,
    /// Operator i (0 or 1).
    #[schemars(range(max = 1))]
    #[arg(long, default_value_t = Self::DEFAULT.operator)]
    pub operator: usize,
    /// Starting point as an attractor parameter (default: the other operator's fixed point).
    #[schemars(range(min = -1e6, max = 1e6))]
    #[arg(long, conflicts_with = "bound")]
    pub start: Option<f64>,
    /// Start from the lower- or upper-bound member of the family instead.
    #[arg(long, value_enum)]
    pub bound: Option<Bound>,
    /// Samples along t ∈ [0, 1].
    #[schemars(range(min = 1, max = 100_000_000))]
    #[arg(long, default_value_t = Self::DEFAULT.samples)]
    pub samples: usize,
    /// Family members drawn in an .svg figure.
    #[schemars(range(min = 0, max = 10_000))]
    #[arg(long, default_value_t = Self::DEFAULT.family)]
    pub family: usize,
}

impl IfsDcfParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        model: IfsModelParams::DEFAULT,
        operator: 0,
        start: None,
        bound: None,
        samples: 256,
        family: 12,
    };

    /// The start: a bound, the given parameter, or the other operator's
    /// fixed point (parameter 1 for T₀, 0 for T₁).
    pub fn first(&self) -> Start {
        start(self.bound, self.start.unwrap_or(1.0 - self.operator as f64))
    }

    /// The model's name, the curve, its family options and the DCF.
    ///
    /// # Errors
    /// As [`load`]; a surface model; the DCF's.
    pub fn dcf(&self) -> Result<(String, CurveIfs, FamilyOptions, DcfCurve)> {
        crate::params::validate(self)?;
        let (name, c, opts) = self.model.load()?.curve()?;
        let d = dcf_for(&c, &opts, self.operator, Some(self.first()), self.samples)?;
        Ok((name, c, opts, d))
    }
}

impl Default for IfsDcfParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}
ifs_job!(IfsDcfParams, "ifs dcf");

fn start(bound: Option<Bound>, parameter: f64) -> Start {
    match bound {
        Some(Bound::Lower) => Start::Lower,
        Some(Bound::Upper) => Start::Upper,
        None => Start::Parameter(parameter),
    }
}

/// `ifs sdcf`: one SDCF of a surface operator 𝒯ᵢⱼ as a mesh (poull-gentil §4,
/// Fig. 4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsSdcfParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub model: IfsModelParams,
    /// Tensor operator I,J (each 0 or 1).
    #[arg(long, default_value_t = Self::DEFAULT.operator, value_name = "I,J")]
    pub operator: Numbers<2>,
    /// Starting point S,T as attractor parameters (default: the opposite corner).
    #[arg(long, conflicts_with = "bound", value_name = "S,T")]
    pub start: Option<Numbers<2>>,
    /// Start from the lower- or upper-bound members of both families instead.
    #[arg(long, value_enum)]
    pub bound: Option<Bound>,
    /// Grid resolution of the SDCF mesh (cells per side).
    #[schemars(range(min = 1, max = 4096))]
    #[arg(long, default_value_t = Self::DEFAULT.resolution)]
    pub resolution: usize,
    /// Also include the attractor at this depth (grey; the SDCF is blue), for viewing.
    #[schemars(range(max = 14))]
    #[arg(long, value_name = "DEPTH")]
    pub with_attractor: Option<u32>,
}

impl IfsSdcfParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        model: IfsModelParams::DEFAULT,
        operator: Numbers([0.0, 0.0]),
        start: None,
        bound: None,
        resolution: 64,
        with_attractor: None,
    };

    /// The operator's indices (i, j).
    ///
    /// # Errors
    /// [`EngineError::Invalid`] unless both are 0 or 1.
    pub fn indices(&self) -> Result<(usize, usize)> {
        match self.operator.0 {
            [i, j] if [i, j].iter().all(|v| *v == 0.0 || *v == 1.0) => Ok((i as usize, j as usize)),
            _ => Err(EngineError::Invalid(format!(
                "{} {}: I and J are 0 or 1",
                asperity_core::wording::param("operator"),
                self.operator
            ))),
        }
    }

    /// The model's name and the SDCF mesh (with the attractor when asked).
    ///
    /// # Errors
    /// As [`load`]; a curve that cannot be squared; the budget.
    pub fn mesh(&self, budget: &MemoryBudget) -> Result<(String, TriMesh)> {
        crate::params::validate(self)?;
        let (i, j) = self.indices()?;
        let (name, s, opts) = self.model.load()?.surface(self.model.height)?;
        let st = self
            .start
            .map_or((1.0 - i as f64, 1.0 - j as f64), |p| (p.0[0], p.0[1]));
        let starts = (start(self.bound, st.0), start(self.bound, st.1));
        let mut mesh = sdcf_for(&s, &opts, (i, j), starts, self.resolution, budget)?;
        if let Some(d) = self.with_attractor {
            let att = s.attractor_mesh(d, budget)?;
            mesh = TriMesh::merge_colored(&[
                (&att, [190, 190, 190, 255]),
                (&mesh, [40, 90, 220, 255]),
            ])?;
        }
        Ok((name, mesh))
    }
}

impl Default for IfsSdcfParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl JobParams for IfsSdcfParams {
    const JOB: &'static str = "ifs sdcf";
    const SEEDED: bool = false;

    fn check(&self) -> Result<()> {
        self.indices().map(|_| ())
    }
}

/// `ifs curvature`: pseudo-curvature ranges at the fixed points of every
/// operator and at dyadic points (poull-gentil §4.1, §5).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct IfsCurvatureParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub model: IfsModelParams,
    /// Dyadic points to evaluate: S for curves, S,T for surfaces.
    #[arg(long, value_name = "S[,T]")]
    pub at: Vec<String>,
}
ifs_job!(IfsCurvatureParams, "ifs curvature");

impl IfsCurvatureParams {
    /// The model, its report and the report as a JSON document.
    ///
    /// # Errors
    /// As [`load`] and [`curvature_report`].
    pub fn report(&self) -> Result<(Loaded, CurvatureReport, serde_json::Value)> {
        crate::params::validate(self)?;
        let l = self.model.load()?;
        let report = curvature_report(&l, &self.at)?;
        let doc = curvature_doc(&l, &report)?;
        Ok((l, report, doc))
    }
}
