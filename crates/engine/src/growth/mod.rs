//! Surface growth (kim-machiraju-thompson §4, §6 Fig. 8, §7): the simulators of
//! `asperity-growth` with the measurements of `asperity-analysis`.
//!
//! | Module | Job |
//! | --- | --- |
//! | [`deposition`] | RD, RDSR, BD on a flat periodic substrate; W(t), β, α |
//! | [`curved`] | RD, RDSR, BD on a sphere or a closed mesh |
//! | [`dla`] | DLA from a point, the plane, a ball, a mesh or an image; R_g, D |
//!
//! The jobs `growth rd`, `growth rdsr` and `growth bd` share their parameters
//! ([`DepositParams`]; RDSR adds its relaxation radius) and run through
//! [`deposit`], on the substrate the parameters name.

pub mod curved;
pub mod deposition;
pub mod dla;

use asperity_core::{MemoryBudget, PointSet, Progress, TimeBudget, TriMesh};
use asperity_growth::Model;
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{EngineError, Result};
use crate::params::{JobParams, Window, choice};
use crate::plots::NamedPlot;
use crate::report::Measurements;

choice! {
    /// What RD, RDSR and BD deposit on.
    pub enum SubstrateShape {
        /// A periodic L (1+1D) or L×L (2+1D) lattice of columns.
        Flat = "flat",
        /// A ball (its radius: the radius); particles arrive radially.
        Sphere = "sphere",
        /// A closed mesh (an input) voxelised at the resolution; particles arrive along its normals.
        Mesh = "mesh",
    }
}

/// The parameters RD, RDSR and BD share (`growth rd|rdsr|bd`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct DepositParams {
    /// Columns per side L of the flat substrate.
    #[schemars(range(min = 1, max = 16_777_216))]
    #[arg(long, default_value_t = Self::DEFAULT.size)]
    pub size: usize,
    /// Substrate dimension d: 1 (a row of L columns) or 2 (L×L).
    #[schemars(range(min = 1, max = 2))]
    #[arg(long, default_value_t = Self::DEFAULT.dim)]
    pub dim: usize,
    /// Monolayers T to deposit (depositions = T × columns).
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, default_value_t = Self::DEFAULT.layers)]
    pub layers: f64,
    /// Independent runs averaged for W(t) (in parallel; each reproducible from the seed).
    #[schemars(range(min = 1, max = 1_000_000))]
    #[arg(long, default_value_t = Self::DEFAULT.runs)]
    pub runs: usize,
    /// Max-height binning side ε for a coarse-grained width, in columns (must divide L); BD needs it.
    #[schemars(range(min = 1, max = 16_777_216))]
    #[arg(long, value_name = "EPS")]
    pub bin: Option<usize>,
    /// Width samples per decade of time.
    #[schemars(range(min = 1, max = 1_000))]
    #[arg(long, default_value_t = Self::DEFAULT.samples_per_decade)]
    pub samples_per_decade: usize,
    /// Fit window of β in monolayers, TMIN,TMAX (default: 10 to T, or 1 to T when T < 100).
    #[arg(long, value_name = "TMIN,TMAX")]
    pub fit_window: Option<Window>,
    /// Also measure α: the saturated widths of these sizes L (at least 3), each run to 2·L^z monolayers.
    #[schemars(with = "Option<Vec<crate::params::Side>>")]
    #[arg(long, value_delimiter = ',', value_name = "L1,L2,...")]
    pub alpha_sizes: Option<Vec<usize>>,
    /// Substrate shape.
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.substrate)]
    pub substrate: SubstrateShape,
    /// Radius of the sphere substrate, in cells.
    #[schemars(range(min = 1.0, max = 1e6))]
    #[arg(long, default_value_t = Self::DEFAULT.radius)]
    pub radius: f64,
    /// Cells along the mesh substrate's longest axis.
    #[schemars(range(min = 2, max = 4096))]
    #[arg(long, default_value_t = Self::DEFAULT.resolution)]
    pub resolution: usize,
}

impl DepositParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        size: 256,
        dim: 2,
        layers: 100.0,
        runs: 1,
        bin: None,
        samples_per_decade: 10,
        fit_window: None,
        alpha_sizes: None,
        substrate: SubstrateShape::Flat,
        radius: 40.0,
        resolution: 64,
    };
}

impl Default for DepositParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Random deposition (`growth rd`, kim-machiraju-thompson §4.1): each
/// particle falls on a random column and stays on top of it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct RdParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub deposit: DepositParams,
}

/// Random deposition with surface relaxation (`growth rdsr`,
/// kim-machiraju-thompson §4.1): a particle settles in the lowest column
/// within the relaxation radius (Family's model).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct RdsrParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub deposit: DepositParams,
    /// Relaxation radius in columns (1 is Family's nearest-neighbour rule).
    #[schemars(range(min = 1, max = 1_000_000))]
    #[arg(long, default_value_t = Self::DEFAULT.relax)]
    pub relax: u32,
}

impl RdsrParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        deposit: DepositParams::DEFAULT,
        relax: 1,
    };
}

impl Default for RdsrParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Ballistic deposition (`growth bd`, kim-machiraju-thompson §4.1): a particle
/// sticks at the first contact with a neighbouring column (KPZ class).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct BdParams {
    #[serde(flatten)]
    #[command(flatten)]
    #[allow(missing_docs)]
    pub deposit: DepositParams,
}

/// A deposition job: its model and its shared parameters.
pub trait DepositJob: JobParams {
    /// The growth model (with RDSR's radius).
    fn model(&self) -> Model;
    /// The parameters the three models share.
    fn deposit(&self) -> &DepositParams;
}

macro_rules! deposit_job {
    ($t:ty, $job:literal, |$p:ident| $model:expr) => {
        impl JobParams for $t {
            const JOB: &'static str = $job;
            fn check(&self) -> Result<()> {
                check_deposit(&self.deposit)
            }
        }
        impl DepositJob for $t {
            fn model(&self) -> Model {
                let $p = self;
                $model
            }
            fn deposit(&self) -> &DepositParams {
                &self.deposit
            }
        }
    };
}

deposit_job!(RdParams, "growth rd", |_p| Model::Rd);
deposit_job!(RdsrParams, "growth rdsr", |p| Model::Rdsr {
    radius: p.relax
});
deposit_job!(BdParams, "growth bd", |_p| Model::Bd);

fn check_deposit(d: &DepositParams) -> Result<()> {
    if let Some(w) = &d.fit_window {
        w.check("fit_window", "TMIN,TMAX")?;
    }
    if let Some(sizes) = &d.alpha_sizes
        && sizes.contains(&0)
    {
        return Err(EngineError::Invalid(format!(
            "{} are lattice sizes of at least 1, got {sizes:?}",
            asperity_core::wording::param("alpha_sizes")
        )));
    }
    Ok(())
}

/// What a deposition gives, on a flat or a curved substrate.
#[derive(Clone, Debug)]
pub enum Deposited {
    /// A flat substrate: heights, W(t), β and α.
    Flat(deposition::DepositionJob, Box<deposition::DepositionRun>),
    /// A sphere or a mesh: the occupied cells, W(t) about the substrate, β.
    Curved(curved::CurvedJob, Box<curved::CurvedRun>),
}

/// Runs a deposition job on the substrate its parameters name (`mesh` is the
/// mesh substrate); `keep_points` keeps every particle's cell of a flat run
/// (for a point-set output; curved runs always have them).
///
/// # Errors
/// The parameters' ([`crate::params::validate`]), a missing mesh, and the
/// simulators' (lattice, binning, memory and time budgets).
pub fn deposit<P: DepositJob>(
    p: &P,
    mesh: Option<TriMesh>,
    keep_points: bool,
    seed: u64,
    (budget, time): (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
) -> Result<Deposited> {
    crate::params::validate(p)?;
    let d = p.deposit();
    let substrate = match d.substrate {
        SubstrateShape::Flat => {
            let job = deposition::DepositionJob {
                model: p.model(),
                size: d.size,
                dim: d.dim,
                layers: d.layers,
                runs: d.runs,
                bin: d.bin,
                samples_per_decade: d.samples_per_decade,
                fit_window: d.fit_window.map(|w| w.0),
                alpha_sizes: d.alpha_sizes.clone(),
                keep_points,
            };
            let run = deposition::deposit(&job, seed, budget, time, progress)?;
            return Ok(Deposited::Flat(job, Box::new(run)));
        }
        SubstrateShape::Sphere => curved::Substrate::Sphere(d.radius),
        SubstrateShape::Mesh => curved::Substrate::Mesh {
            mesh: mesh.ok_or_else(|| {
                EngineError::Invalid(format!(
                    "{} needs {}",
                    asperity_core::wording::param_value("substrate", "mesh"),
                    asperity_core::wording::param("mesh")
                ))
            })?,
            resolution: d.resolution,
        },
    };
    let job = curved::CurvedJob {
        model: p.model(),
        substrate,
        layers: d.layers,
        samples_per_decade: d.samples_per_decade,
    };
    let run = curved::deposit(&job, seed, budget, progress)?;
    Ok(Deposited::Curved(job, Box::new(run)))
}

impl Deposited {
    /// The measurements the job reports.
    pub fn measurements(&self) -> Measurements {
        match self {
            Deposited::Flat(job, run) => run.measurements(job),
            Deposited::Curved(job, run) => run.measurements(job),
        }
    }

    /// One line for the user.
    pub fn summary(&self) -> String {
        match self {
            Deposited::Flat(job, run) => run.summary(job),
            Deposited::Curved(job, run) => run.summary(job),
        }
    }

    /// `width.svg`, and `saturation.svg` with an α study.
    pub fn plots(&self) -> Vec<NamedPlot> {
        match self {
            Deposited::Flat(job, run) => run.plots(job),
            Deposited::Curved(job, run) => run.plots(job),
        }
    }

    /// Every occupied cell as a point: a flat run's particles (when kept),
    /// a curved run's substrate cells then particles, in the input's coordinates.
    pub fn points(&self) -> PointSet {
        match self {
            Deposited::Flat(_, run) => run.deposit.point_set(),
            Deposited::Curved(_, run) => PointSet::new(run.world_points()),
        }
    }

    /// The title of what it writes (`rdsr L=256 T=100`, or the model).
    pub fn title(&self) -> String {
        match self {
            Deposited::Flat(job, _) => job.title(),
            Deposited::Curved(job, _) => job.model.name().to_owned(),
        }
    }

    /// W(t) (mean over the runs on a flat substrate).
    pub fn series(&self) -> &asperity_growth::WidthSeries {
        match self {
            Deposited::Flat(_, run) => &run.series,
            Deposited::Curved(_, run) => &run.deposit.series,
        }
    }
}
