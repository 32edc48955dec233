//! The parameters of the peridier commands: `ca run`, `ca rule`, `ca gallery`,
//! `facet` and `interpolate`.

use asperity_ca::{Boundary, Weights};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{EngineError, Result};
use crate::params::{JobParams, Numbers, Size2, choice, require};

choice! {
    /// A CA rule family (peridier §2; Mathematica's numbering).
    pub enum FamilyName {
        /// Sum of the 3×3 Moore neighbourhood, centre included (k colours).
        Totalistic9 = "totalistic9",
        /// Sum of the von Neumann cross, centre included (k colours).
        Totalistic5 = "totalistic5",
        /// Centre + 2 × sum of the 8 Moore neighbours (two states; Life's family).
        Outer9 = "outer9",
        /// Centre + 2 × sum of the 4 von Neumann neighbours (two states).
        Outer5 = "outer5",
    }
}

choice! {
    /// What lies beyond the grid.
    pub enum BoundaryName {
        /// The grid wraps around.
        Cyclic = "cyclic",
        /// A growing region on a background (a seed without a size).
        Infinite = "infinite",
    }
}

impl From<BoundaryName> for Boundary {
    fn from(b: BoundaryName) -> Self {
        match b {
            BoundaryName::Cyclic => Boundary::Cyclic,
            BoundaryName::Infinite => Boundary::Infinite,
        }
    }
}

/// A rule code: a Wolfram code (450) or a B/S string (B3/S23). JSON takes a
/// number or a string.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, JsonSchema)]
#[schemars(with = "RuleForm")]
pub struct RuleCode(pub String);

/// The JSON forms of a [`RuleCode`] (for its schema).
#[derive(JsonSchema)]
#[allow(dead_code)]
#[serde(untagged)]
enum RuleForm {
    /// A Wolfram code (any 64-bit number; the family's rule space bounds it
    /// further).
    Code(#[schemars(range(min = 0, max = u64::MAX))] u64),
    /// A code or a B/S string.
    Text(String),
}

impl<'de> Deserialize<'de> for RuleCode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = RuleCode;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a rule: a Wolfram code (450) or a B/S string (\"B3/S23\")")
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<RuleCode, E> {
                Ok(RuleCode(v.to_string()))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<RuleCode, E> {
                Ok(RuleCode(v.to_owned()))
            }
        }
        d.deserialize_any(V)
    }
}

impl std::str::FromStr for RuleCode {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Ok(Self(s.to_owned()))
    }
}

impl std::fmt::Display for RuleCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// The rule family and colours shared by the `ca` commands.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct RuleFamily {
    /// Rule family.
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.family)]
    pub family: FamilyName,
    /// Number of states k (the totalistic families; the outer families have two).
    #[schemars(range(min = 2, max = 12))]
    #[arg(long, default_value_t = Self::DEFAULT.states)]
    pub states: u8,
}

impl RuleFamily {
    /// Two-colour totalistic rules of the 3×3 block (the paper's).
    pub const DEFAULT: Self = Self {
        family: FamilyName::Totalistic9,
        states: 2,
    };

    /// The rule `code` of this family.
    ///
    /// # Errors
    /// The CA's refusals (a code out of range, a B/S string for a totalistic family).
    pub fn rule(&self, code: &RuleCode) -> Result<asperity_ca::Rule> {
        super::rule(self.family.name(), self.states, &code.0)
    }
}

impl Default for RuleFamily {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// `ca run`: a height field accumulated from a 2-D totalistic cellular
/// automaton (peridier §2–3): each step's states summed, weighted, into heights.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct CaRunParams {
    /// Wolfram code (e.g. 450) or a B/S string (e.g. B3/S23). Required.
    #[arg(long)]
    pub rule: Option<RuleCode>,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub family: RuleFamily,
    /// Number of steps T. Required.
    #[schemars(range(min = 0, max = 1_000_000_000_000u64))]
    #[arg(long)]
    pub steps: Option<usize>,
    /// Initial grid: seed (one cell), random:DENSITY (or random:DENSITY@SEED), or a file (.npy
    /// states, or an image thresholded at 50 %).
    #[arg(long, default_value_t = Self::default().init)]
    pub init: String,
    /// Grid size WxH (columns x rows); without it a seed sits on an infinite background.
    #[arg(long, value_name = "WxH")]
    pub size: Option<Size2>,
    /// Boundary (default: infinite for a seed without a size, cyclic otherwise).
    #[arg(long, value_enum)]
    pub boundary: Option<BoundaryName>,
    /// Leave step 0 (the initial grid) out of the sum.
    #[arg(long)]
    pub no_step0: bool,
    /// Weight step t by R^t (geometric decay).
    #[schemars(range(min = -1e3, max = 1e3))]
    #[arg(long, value_name = "R", conflicts_with = "weights")]
    pub decay: Option<f64>,
    /// Explicit weight of each step 0…T (T + 1 values).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "W0,W1,…",
        allow_negative_numbers = true
    )]
    #[schemars(with = "Option<Vec<crate::params::Finite>>")]
    pub weights: Option<Vec<f64>>,
    /// Height of each state (k values; default 0, 1, …).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "V0,V1,…",
        allow_negative_numbers = true
    )]
    #[schemars(with = "Option<Vec<crate::params::Finite>>")]
    pub values: Option<Vec<f64>>,
}

impl Default for CaRunParams {
    fn default() -> Self {
        Self {
            rule: None,
            family: RuleFamily::DEFAULT,
            steps: None,
            init: "seed".into(),
            size: None,
            boundary: None,
            no_step0: false,
            decay: None,
            weights: None,
            values: None,
        }
    }
}

impl CaRunParams {
    /// The example terrain a front end offers first (the Blender add-on's CA
    /// terrain): rule 450, a random 64 × 64 cyclic grid of density 0.3, 24
    /// steps accumulated — a rough, isotropic relief (peridier §3, whose
    /// figures use code 450's family; the benches' workload uses the same rule
    /// and density).
    pub fn terrain_example() -> Self {
        Self {
            rule: Some(RuleCode("450".into())),
            steps: Some(24),
            init: "random:0.3".into(),
            size: Some(Size2([64, 64])),
            ..Self::default()
        }
    }

    /// The step weights.
    pub fn step_weights(&self) -> Weights {
        match (&self.weights, self.decay) {
            (Some(w), _) => Weights::Explicit(w.clone()),
            (None, Some(r)) => Weights::Geometric(r),
            (None, None) => Weights::Uniform,
        }
    }
}

impl JobParams for CaRunParams {
    const JOB: &'static str = "ca run";
    const REQUIRED: &'static [&'static str] = &["rule", "steps"];

    fn check(&self) -> Result<()> {
        require(&self.rule, "rule")?;
        require(&self.steps, "steps")?;
        if self.decay.is_some() && self.weights.is_some() {
            return Err(EngineError::Invalid(format!(
                "give {} or {}, not both",
                asperity_core::wording::param("decay"),
                asperity_core::wording::param("weights")
            )));
        }
        Ok(())
    }
}

/// `ca rule`: a rule's look-up table (peridier Figure 2).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct CaRuleParams {
    /// Wolfram code or B/S string. Required.
    #[arg(value_name = "RULE")]
    pub rule: Option<RuleCode>,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub family: RuleFamily,
}

impl JobParams for CaRuleParams {
    const JOB: &'static str = "ca rule";
    const SEEDED: bool = false;
    const REQUIRED: &'static [&'static str] = &["rule"];

    fn check(&self) -> Result<()> {
        require(&self.rule, "rule").map(|_| ())
    }
}

/// `ca gallery`: rules × initial conditions as a grid of rendered surfaces
/// (peridier Figure 4).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct CaGalleryParams {
    /// Rules, one row each.
    #[arg(long, value_delimiter = ',', default_values_t = Self::default().rules)]
    pub rules: Vec<RuleCode>,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub family: RuleFamily,
    /// Initial conditions, one column each: seed, random:DENSITY or random:DENSITY@SEED, or files.
    #[arg(long, value_delimiter = ',', default_values_t = Self::default().inits)]
    pub inits: Vec<String>,
    /// Steps per run.
    #[schemars(range(min = 0, max = 1_000_000_000_000u64))]
    #[arg(long, default_value_t = Self::default().steps)]
    pub steps: usize,
    /// Cyclic grid size WxH of every run.
    #[arg(long, default_value_t = Self::default().size, value_name = "WxH")]
    pub size: Size2,
    /// Size of each tile in pixels, WxH.
    #[arg(long, default_value_t = Self::default().tile, value_name = "WxH")]
    pub tile: Size2,
}

impl Default for CaGalleryParams {
    fn default() -> Self {
        Self {
            rules: ["8", "480", "450"].map(|r| RuleCode(r.into())).to_vec(),
            family: RuleFamily::DEFAULT,
            inits: vec!["seed".into(), "random:0.3".into()],
            steps: 10,
            size: Size2([41, 41]),
            tile: Size2([320, 240]),
        }
    }
}

impl JobParams for CaGalleryParams {
    const JOB: &'static str = "ca gallery";
}

/// `facet`: the alternating-diagonal facet mesh of a height field with curves
/// draped on it (peridier §3, Figures 7–9).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct FacetParams {
    /// Share vertices between facets (smooth shading in viewers) instead of flat facets.
    #[arg(long)]
    pub shared: bool,
    /// Ordinary triangulation (the same diagonal in every cell) for comparison.
    #[arg(long)]
    pub smooth: bool,
    /// Draw a circle CX,CY,R (physical units) on the surface (Figure 9).
    #[arg(long, value_name = "CX,CY,R", allow_negative_numbers = true)]
    pub circle: Option<Numbers<3>>,
}

impl JobParams for FacetParams {
    const JOB: &'static str = "facet";
    const SEEDED: bool = false;
}

/// `interpolate`: heights on the facets at (x, y) points (peridier's
/// consistent interpolation); it has no parameters besides its inputs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct InterpolateParams {}

impl JobParams for InterpolateParams {
    const JOB: &'static str = "interpolate";
    const SEEDED: bool = false;
}
