//! The parameters of `reconstruct` and of the two pipelines `generate
//! dla-terrain` and `generate rdsr-sphere` (kim-machiraju-thompson §5–6):
//! the level-set settings they share ([`LevelSetParams`]) and what each
//! pipeline grows.

use asperity_levelset::{
    Band, CloudChoice, DistanceMethod, ExtractOptions, FlowChoice, Length, Neighbourhood,
    ReconstructParams, Scheme, Sizing, TagRule,
};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{Job, MIN_SHELL_TRIANGLES, PAPER_TERRAIN_PARTICLES};
use crate::error::{EngineError, Result};
use crate::growth::dla::Sides;
use crate::params::{JobParams, LatticeSize, choice};

choice! {
    /// The space discretisation of the flow.
    pub enum SchemeChoice {
        /// Second-order ENO (the paper's).
        Eno2 = "eno2",
        /// First-order upwind.
        Upwind = "upwind",
    }
}

choice! {
    /// The level-set flow.
    pub enum FlowName {
        /// φ_t = d|∇φ| (Eq. 6): keeps the roughness.
        Convection = "convection",
        /// Convection plus a curvature term weighted by d (Zhao's weighted minimal surface): smoother.
        Regularized = "regularized",
        /// Zhao's φ_t = ∇d·∇φ (velocity −∇d), which the paper replaces by Eq. 6: ∇d is unstable on rough data.
        Zhao = "zhao",
    }
}

choice! {
    /// What the points are.
    pub enum CloudName {
        /// Measured: a sampled surface when the points' neighbourhoods are flat, else a deposit.
        Auto = "auto",
        /// Samples of a surface (a scan, a random sample): outliers dropped, noise averaged, the
        /// inside held behind the gaps and holes between samples.
        Surface = "surface",
        /// A growth model's occupied cells, used as they are: the front stops δ from each point.
        Deposit = "deposit",
    }
}

choice! {
    /// How the unsigned distance to the points is computed.
    pub enum DistanceName {
        /// Closest-point wavefront in the band (nearly exact, fast).
        ClosestPoint = "closest-point",
        /// Godunov fast sweeping over the whole grid (the paper's, first order).
        Godunov = "godunov",
    }
}

choice! {
    /// How the flow tube T grows into the redistancing tube N.
    pub enum TubeN {
        /// One node along each axis (6 neighbours; fastest).
        Axes = "axes",
        /// The 3×3×3 block (26 neighbours), the paper's N (Eq. 10's outline, step 1).
        Cube = "cube",
    }
}

choice! {
    /// The inside/outside tagging rule of Algorithm 1.
    pub enum Tagging {
        /// As published: never step onto a node with a farther interior neighbour.
        Paper = "paper",
        /// The ε rule only: flood fill of {d ≥ ε} from the box.
        Threshold = "threshold",
    }
}

/// A length in the points' units (a number, `0.5`) or in grid cells (`3h`).
#[derive(Clone, Copy, Debug, PartialEq, JsonSchema)]
#[schemars(with = "OffsetForm")]
pub struct Offset(pub Length);

/// The JSON forms of an [`Offset`] (for its schema).
#[derive(JsonSchema)]
#[allow(dead_code)]
#[serde(untagged)]
enum OffsetForm {
    /// In the points' units.
    World(#[schemars(range(min = -1e12, max = 1e12))] f64),
    /// In grid cells: a number followed by h, e.g. "3h".
    Cells(String),
}

impl std::str::FromStr for Offset {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Length::parse(s).map(Offset)
    }
}

impl std::fmt::Display for Offset {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Length::World(v) => write!(f, "{v}"),
            Length::Cells(c) => write!(f, "{c}h"),
        }
    }
}

impl Serialize for Offset {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self.0 {
            Length::World(v) => s.serialize_f64(v),
            Length::Cells(_) => s.serialize_str(&self.to_string()),
        }
    }
}

impl<'de> Deserialize<'de> for Offset {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = Offset;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a length: a number (the points' units) or \"3h\" (grid cells)")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Offset, E> {
                Ok(Offset(Length::World(v)))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Offset, E> {
                Ok(Offset(Length::World(v as f64)))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Offset, E> {
                Ok(Offset(Length::World(v as f64)))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<Offset, E> {
                v.parse().map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// The level-set reconstruction's settings (kim-machiraju-thompson §5): the
/// grid, the initial offset surface, the convection flow and its
/// redistancing, the mesh. `reconstruct` takes them alone, the pipelines
/// after what they grow. Settings left unset take the job's defaults, or the
/// paper's with `paper`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct LevelSetParams {
    /// The paper's own settings and algorithms for what is not given: ε = 3h, 30 steps, Godunov
    /// distance, the 3×3×3 tube N (reconstruct: 128 cells; pipelines: 96 cells along the
    /// lattice, the paper's 115 nodes).
    #[arg(long)]
    pub paper: bool,
    /// Cells along the longest axis of the points' bounding box (default 128; pipelines: from
    /// the spacing).
    #[schemars(range(min = 2, max = 16_384))]
    #[arg(long, conflicts_with = "spacing")]
    pub resolution: Option<usize>,
    /// Grid spacing h in the points' units, instead of the resolution (pipelines: 0.7).
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long)]
    pub spacing: Option<f64>,
    /// Offset ε of the initial surface from the points: in their units (0.5) or in grid cells
    /// with an h suffix (3h, the paper's "3 grid cells"). Default 3h; pipelines 3 units.
    #[arg(long, value_name = "EPS")]
    pub offset: Option<Offset>,
    /// Time steps of the flow (default 30, 200 for a sampled surface; pipelines 60).
    #[schemars(range(min = 0, max = 1_000_000))]
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Stop early once the front moves less than this many cells per step.
    #[schemars(range(min = 0.0, max = 1e6))]
    #[arg(long, value_name = "CELLS")]
    pub tolerance: Option<f64>,
    /// Radius δ at which the front stops around each point, in the points' units (default:
    /// 0.75 × the sample spacing up to 60 steps, growing to 1 × at 200 steps; at least 0.6h; 0
    /// is the paper's model).
    #[schemars(range(min = 0.0, max = 1e12))]
    #[arg(long, value_name = "R")]
    pub point_radius: Option<f64>,
    /// Space discretisation.
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.scheme)]
    pub scheme: SchemeChoice,
    /// What the points are (reconstruct: auto, measured from the points; pipelines: deposit).
    #[arg(long, value_enum)]
    pub cloud: Option<CloudName>,
    /// Keep a sampled surface's points and the level set's vertices as they are: no denoising
    /// of the points by local quadric fits, no projection of the vertices onto them.
    #[arg(long)]
    pub keep_noise: bool,
    /// The flow (default: zhao for a sampled surface, convection for a deposit).
    #[arg(long, value_enum)]
    pub flow: Option<FlowName>,
    /// Curvature weight λ of the regularized flow, in cells.
    #[schemars(range(min = 0.0, max = 1e6))]
    #[arg(long, default_value_t = Self::DEFAULT.curvature_weight)]
    pub curvature_weight: f64,
    /// Unsigned-distance method (default closest-point; paper: godunov).
    #[arg(long, value_enum)]
    pub distance: Option<DistanceName>,
    /// The neighbourhood that grows the flow tube T into the redistancing tube N (default axes;
    /// paper: cube).
    #[arg(long, value_enum, value_name = "NEIGHBOURHOOD")]
    pub tube_n: Option<TubeN>,
    /// Tagging rule.
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.tagging)]
    pub tagging: Tagging,
    /// Tube half-width γ, in cells.
    #[schemars(range(max = 1e4), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, default_value_t = Self::DEFAULT.tube)]
    pub tube: f64,
    /// Full-speed half-width β of the cut-off, in cells (below the tube's γ).
    #[schemars(range(max = 1e4), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, default_value_t = Self::DEFAULT.beta)]
    pub beta: f64,
    /// CFL number of the time step.
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1.0))]
    #[arg(long, default_value_t = Self::DEFAULT.cfl)]
    pub cfl: f64,
    /// Redistancing iterations per step (Eq. 11).
    #[schemars(range(min = 0, max = 1_000))]
    #[arg(long, default_value_t = Self::DEFAULT.redistance)]
    pub redistance: usize,
    /// Update every node every step (the naive scheme, for comparison) instead of the tubes.
    #[arg(long)]
    pub full_grid: bool,
    /// Store the mean curvature H = (κ₁ + κ₂)/2 and the Gaussian curvature K per vertex as
    /// `mean_curvature` and `gaussian_curvature`, from quadrics fitted within the curvature
    /// scale to the input points about each vertex (a sampled surface, every flow) or to the
    /// mesh (a deposit).
    #[arg(long)]
    pub curvature: bool,
    /// The radius of the curvature fits: in the points' units (0.05) or in grid cells (3h).
    /// Default: 3 sample spacings, at least 3.5h; at most 16h.
    #[arg(long, value_name = "R")]
    pub curvature_scale: Option<Offset>,
    /// Keep a sampled surface that is open by nature open: remove the triangles that span holes
    /// in the data (farther than two sample spacings from every point) and the far side of thin
    /// sheets, so a partial scan or a terrain patch keeps its boundary (a deposit stays closed).
    #[arg(long)]
    pub open: bool,
    /// Drop connected pieces with fewer triangles than this (single-node voids the flow opens
    /// inside a deposit have 8); 0 keeps everything.
    #[schemars(range(min = 0, max = 1_000_000_000_000u64))]
    #[arg(long, default_value_t = Self::DEFAULT.min_shell, value_name = "TRIANGLES")]
    pub min_shell: usize,
    /// Also give the surface every K steps (and the initial one); the CLI writes them as
    /// OUT_stepNNNN.EXT.
    #[schemars(range(min = 1, max = 1_000_000_000))]
    #[arg(long, value_name = "K")]
    pub save_every: Option<usize>,
}

impl LevelSetParams {
    /// The defaults every front end shows (unset settings: the job's).
    pub const DEFAULT: Self = Self {
        paper: false,
        resolution: None,
        spacing: None,
        offset: None,
        iterations: None,
        tolerance: None,
        point_radius: None,
        scheme: SchemeChoice::Eno2,
        cloud: None,
        keep_noise: false,
        flow: None,
        curvature_weight: 1.0,
        distance: None,
        tube_n: None,
        tagging: Tagging::Paper,
        tube: asperity_levelset::evolve::TUBE_CELLS,
        beta: asperity_levelset::evolve::BETA_CELLS,
        cfl: asperity_levelset::evolve::CFL,
        redistance: 2,
        full_grid: false,
        curvature: false,
        curvature_scale: None,
        open: false,
        min_shell: MIN_SHELL_TRIANGLES,
        save_every: None,
    };

    /// The reconstruction settings of `job` with these choices over its
    /// defaults (the paper's with `paper`).
    pub fn settings(&self, job: Job) -> ReconstructParams {
        let d = job.defaults(self.paper);
        let sizing = match (self.resolution, self.spacing) {
            (Some(n), _) => Sizing::Resolution(n),
            (None, Some(h)) => Sizing::Spacing(h),
            (None, None) => d.sizing,
        };
        ReconstructParams {
            sizing,
            offset: self.offset.map(|o| o.0).or(d.offset),
            tube_cells: self.tube,
            beta_cells: self.beta,
            distance: self.distance.map_or(d.distance, |m| match m {
                DistanceName::ClosestPoint => DistanceMethod::ClosestPoint,
                DistanceName::Godunov => DistanceMethod::GODUNOV,
            }),
            tag_rule: match self.tagging {
                Tagging::Paper => TagRule::Paper,
                Tagging::Threshold => TagRule::Threshold,
            },
            iterations: self.iterations.unwrap_or(d.iterations),
            surface_iterations: Some(self.iterations.unwrap_or(d.surface_iterations)),
            scheme: match self.scheme {
                SchemeChoice::Eno2 => Scheme::Eno2,
                SchemeChoice::Upwind => Scheme::Upwind,
            },
            flow: match self.flow {
                None => FlowChoice::Auto,
                Some(FlowName::Convection) => FlowChoice::Convection,
                Some(FlowName::Regularized) => FlowChoice::Regularized {
                    weight_cells: self.curvature_weight,
                },
                Some(FlowName::Zhao) => FlowChoice::Zhao,
            },
            cloud: self.cloud.map_or(d.cloud, |c| match c {
                CloudName::Auto => CloudChoice::Auto,
                CloudName::Surface => CloudChoice::Surface,
                CloudName::Deposit => CloudChoice::Deposit,
            }),
            denoise: !self.keep_noise,
            project: !self.keep_noise,
            cfl: self.cfl,
            redistance_iterations: self.redistance,
            tolerance: self.tolerance,
            band: if self.full_grid {
                Band::Full
            } else {
                Band::Narrow
            },
            point_radius: self.point_radius.or(d.point_radius),
            extract: ExtractOptions {
                // The curvature comes from the mesh (see `reconstruct::surface`).
                curvature: false,
                min_shell_triangles: self.min_shell,
            },
            snapshot_every: self.save_every,
            neighbourhood: self.tube_n.map_or(d.neighbourhood, |n| match n {
                TubeN::Axes => Neighbourhood::Axes,
                TubeN::Cube => Neighbourhood::Cube,
            }),
        }
    }

    /// These settings with the job's defaults written in (what a record
    /// holds): the sizing, ε, the steps, the distance and the tube N. The arrest
    /// distance δ, when unset, follows the data and is reported with the mesh.
    pub fn resolved(&self, job: Job) -> Self {
        let s = self.settings(job);
        let (resolution, spacing) = match s.sizing {
            Sizing::Resolution(n) => (Some(n), None),
            Sizing::Spacing(h) => (None, Some(h)),
        };
        Self {
            resolution,
            spacing,
            offset: Some(Offset(s.offset.unwrap_or(Length::Cells(3.0)))),
            // With the cloud measured, the steps follow what it is found to be.
            iterations: (s.cloud != CloudChoice::Auto).then(|| match s.cloud {
                CloudChoice::Surface => s.surface_iterations.unwrap_or(s.iterations),
                _ => s.iterations,
            }),
            distance: Some(if s.distance == DistanceMethod::ClosestPoint {
                DistanceName::ClosestPoint
            } else {
                DistanceName::Godunov
            }),
            tube_n: Some(match s.neighbourhood {
                Neighbourhood::Axes => TubeN::Axes,
                Neighbourhood::Cube => TubeN::Cube,
            }),
            cloud: Some(match s.cloud {
                CloudChoice::Auto => CloudName::Auto,
                CloudChoice::Surface => CloudName::Surface,
                CloudChoice::Deposit => CloudName::Deposit,
            }),
            ..self.clone()
        }
    }

    fn check_settings(&self) -> Result<()> {
        if self.beta >= self.tube {
            return Err(EngineError::Invalid(format!(
                "{} must be below {} (the cut-off's full-speed band lies inside the tube), got {} and {}",
                asperity_core::wording::param("beta"),
                asperity_core::wording::param("tube"),
                self.beta,
                self.tube
            )));
        }
        if let Some(Offset(l)) = self.curvature_scale {
            let v = l.world(1.0);
            if !(v.is_finite() && v > 0.0) {
                return Err(EngineError::Invalid(format!(
                    "{} must be positive and finite, got {v}",
                    asperity_core::wording::param("curvature_scale")
                )));
            }
        }
        Ok(())
    }
}

impl Default for LevelSetParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl JobParams for LevelSetParams {
    const JOB: &'static str = "reconstruct";
    const SEEDED: bool = false;

    fn check(&self) -> Result<()> {
        self.check_settings()
    }
}

/// `generate dla-terrain`: a plane DLA deposit grown between walls, then
/// reconstructed as a terrain with arches (kim-machiraju-thompson Figs. 9–11).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct DlaTerrainParams {
    /// Lattice in cells, NXxNYxNZ (or N for a cube).
    #[arg(long, default_value_t = Self::default().size, value_name = "NXxNYxNZ")]
    pub size: LatticeSize,
    /// DLA particles released from above the plane (default 6000, below the lattice top; paper:
    /// 2500, a deposit about 20 cells high as the paper's 49-node grid height implies).
    #[schemars(range(min = 1, max = 10_000_000_000u64))]
    #[arg(long)]
    pub particles: Option<usize>,
    /// Sticking probability p in (0, 1].
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1.0))]
    #[arg(long, default_value_t = Self::default().stick)]
    pub stick: f64,
    /// The lattice's x and y sides: walls keep the terrain in one piece; periodic sides wrap the
    /// deposit, which the bounded reconstruction then cuts into pieces.
    #[arg(long, value_enum, default_value_t = Self::default().sides)]
    pub sides: Sides,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub level_set: LevelSetParams,
}

impl Default for DlaTerrainParams {
    fn default() -> Self {
        Self {
            size: LatticeSize::cube(64),
            particles: None,
            stick: 1.0,
            sides: Sides::Walls,
            level_set: LevelSetParams::DEFAULT,
        }
    }
}

impl DlaTerrainParams {
    /// The particles released: as given, else 6 000 (the paper's 2 500 with `paper`).
    pub fn particle_count(&self) -> usize {
        self.particles.unwrap_or(if self.level_set.paper {
            PAPER_TERRAIN_PARTICLES
        } else {
            6_000
        })
    }

    /// These parameters with the job's defaults written in.
    pub fn resolved(&self) -> Result<Self> {
        Ok(Self {
            size: LatticeSize::new(&self.size.resolve(3)?)?,
            particles: Some(self.particle_count()),
            level_set: self.level_set.resolved(Job::DlaTerrain),
            ..self.clone()
        })
    }
}

impl JobParams for DlaTerrainParams {
    const JOB: &'static str = "generate dla-terrain";

    fn check(&self) -> Result<()> {
        self.size.resolve(3)?;
        self.level_set.check_settings()
    }
}

/// `generate rdsr-sphere`: RDSR layers grown on a ball, then reconstructed as
/// a rough sphere (kim-machiraju-thompson Fig. 8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct RdsrSphereParams {
    /// Radius of the substrate ball, in cells.
    #[schemars(range(min = 1.0, max = 1e6))]
    #[arg(long, default_value_t = Self::DEFAULT.radius)]
    pub radius: f64,
    /// Monolayers deposited.
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, default_value_t = Self::DEFAULT.layers)]
    pub layers: f64,
    /// RDSR relaxation radius, in cells.
    #[schemars(range(min = 1, max = 1_000_000))]
    #[arg(long, default_value_t = Self::DEFAULT.relax)]
    pub relax: u32,
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub level_set: LevelSetParams,
}

impl RdsrSphereParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        radius: 20.0,
        layers: 10.0,
        relax: 1,
        level_set: LevelSetParams::DEFAULT,
    };

    /// These parameters with the job's defaults written in.
    pub fn resolved(&self) -> Self {
        Self {
            level_set: self.level_set.resolved(Job::RdsrSphere),
            ..self.clone()
        }
    }
}

impl Default for RdsrSphereParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl JobParams for RdsrSphereParams {
    const JOB: &'static str = "generate rdsr-sphere";

    fn check(&self) -> Result<()> {
        self.level_set.check_settings()
    }
}
