//! The parameters of `surface-ca` (gobron-chiba) and the job that runs them:
//! the mesh covered with cells, the application built on them, run step by
//! step.

use asperity_core::{MemoryBudget, PointSet, Progress, TimeBudget, TriMesh};
use asperity_surfca::corrosion::CorrosionParams;
use asperity_surfca::reaction_diffusion::GrayScott;
use asperity_surfca::{CellSize, Pairing};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{AppRequest, AppRun, Covered, OutputShape, check_time, cover, run_app, start_progress};
use crate::error::Result;
use crate::params::{JobParams, choice};

choice! {
    /// How cells are linked across triangle edges.
    pub enum PairingName {
        /// Each side neighbour's position unfolded across the edge, linked to the cell
        /// containing it (nearly one-to-one).
        Unfolded = "unfolded",
        /// The paper's Figure 7: projected onto the shared edge, linked to the opposite
        /// edge cell with the nearest projection (many-to-one where the grids differ).
        Paper = "paper",
    }
}

impl PairingName {
    /// The library's pairing.
    pub fn pairing(self) -> Pairing {
        match self {
            PairingName::Unfolded => Pairing::Unfolded,
            PairingName::Paper => Pairing::Paper,
        }
    }
}

choice! {
    /// The cellular automaton run on the surface.
    pub enum AppName {
        /// Surface Voronoi diagram by regular probabilistic growth (§4.1).
        Voronoi = "voronoi",
        /// Copper corrosion and its green patina (§4.2).
        Corrosion = "corrosion",
        /// Gray–Scott reaction–diffusion (spots, stripes) on the surface.
        GrayScott = "gray-scott",
    }
}

/// `surface-ca`: a cellular automaton on any triangle mesh (gobron-chiba):
/// cells on every triangle, linked across edges, stepped in parallel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct SurfaceCaParams {
    /// The application.
    #[arg(long, value_enum, default_value_t = Self::default().app)]
    pub app: AppName,
    /// Drop degenerate triangles and reorient inconsistent ones instead of refusing the mesh.
    #[arg(long)]
    pub repair: bool,
    /// Approximate number of cells (their side h = √(area / cells)).
    #[schemars(range(min = 1, max = 1_000_000_000))]
    #[arg(long, default_value_t = Self::default().cells, conflicts_with = "cell_size")]
    pub cells: usize,
    /// Cell side h in mesh units (instead of the count).
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long)]
    pub cell_size: Option<f64>,
    /// Voronoi: number of random sites (area-weighted).
    #[schemars(range(min = 1, max = 1_000_000_000))]
    #[arg(long, default_value_t = Self::default().sites)]
    pub sites: usize,
    /// Voronoi: probability that a corner neighbour passes its label (default √2/2 − ½, the
    /// paper's; (√2 − 1)² ≈ 0.1716 is isotropic at large radii).
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long)]
    pub diagonal_p: Option<f64>,
    /// Voronoi: step limit (it stops earlier when no cell changes).
    #[schemars(range(min = 0, max = 1_000_000_000_000u64))]
    #[arg(long, default_value_t = Self::default().max_steps)]
    pub max_steps: u64,
    /// Corrosion and Gray–Scott: steps to run.
    #[schemars(range(min = 0, max = 1_000_000_000_000u64))]
    #[arg(long, default_value_t = Self::default().steps)]
    pub steps: u64,
    /// Gray–Scott: feed rate F.
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long, default_value_t = Self::default().feed)]
    pub feed: f32,
    /// Gray–Scott: kill rate k.
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long, default_value_t = Self::default().kill)]
    pub kill: f32,
    /// Gray–Scott: number of seeded patches.
    #[schemars(range(min = 1, max = 1_000_000))]
    #[arg(long, default_value_t = Self::default().patches)]
    pub patches: usize,
    /// Corrosion: metal lost per corroded step (k1).
    #[schemars(range(min = 0.0, max = 1e6))]
    #[arg(long, default_value_t = Self::default().k1)]
    pub k1: f32,
    /// Corrosion: oxide gained per corroded step (k2).
    #[schemars(range(min = 0.0, max = 1e6))]
    #[arg(long, default_value_t = Self::default().k2)]
    pub k2: f32,
    /// Corrosion: oxide cap (k3).
    #[schemars(range(min = 0.0, max = 1e6))]
    #[arg(long, default_value_t = Self::default().k3)]
    pub k3: f32,
    /// Corrosion: probability per step that a metal cell becomes a new seed.
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long, default_value_t = Self::default().seed_rate)]
    pub seed_rate: f64,
    /// Corrosion: most seeds over the run.
    #[schemars(range(min = 0, max = 1_000_000_000_000u64))]
    #[arg(long, default_value_t = Self::default().max_seeds)]
    pub max_seeds: usize,
    /// Corrosion: share of strong (resistant) cells.
    #[schemars(range(min = 0.0, max = 1.0))]
    #[arg(long, default_value_t = Self::default().strong_fraction)]
    pub strong_fraction: f64,
    /// Corrosion: strong cells from a value-noise field of this feature size (mesh units).
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, value_name = "SCALE")]
    pub strong_noise: Option<f64>,
    /// Corrosion: most neighbours one corroded cell attacks per step (1–7).
    #[schemars(range(min = 1, max = 7))]
    #[arg(long, default_value_t = Self::default().max_attacked)]
    pub max_attacked: u32,
    /// Corrosion: attack strength of a mature corroded cell (defence: 0.35 weak, 0.8 strong).
    #[schemars(range(min = 0.0, max = 1e6))]
    #[arg(long, default_value_t = Self::default().attack)]
    pub attack: f64,
    /// Corrosion: age (steps) at which a corroded cell attacks at full strength.
    #[schemars(range(min = 0, max = 1_000_000_000))]
    #[arg(long, default_value_t = Self::default().maturity)]
    pub maturity: u32,
    /// The cells as their own mesh with vertex colours, even where a format takes the original
    /// mesh with a texture atlas (.glb, .obj).
    #[arg(long)]
    pub cell_mesh: bool,
    /// Displace the cell mesh along the normal by SCALE × the per-cell thickness (corrosion:
    /// oxide; gray-scott: activator), averaged across cells and triangle edges.
    #[schemars(range(min = -1e6, max = 1e6))]
    #[arg(long, value_name = "SCALE", allow_hyphen_values = true)]
    pub displace: Option<f64>,
    /// How cells are linked across triangle edges: `unfolded` (asperity's) or `paper`
    /// (Figure 7's projection on the edge).
    #[arg(long, value_enum, default_value_t = Self::default().pairing)]
    pub pairing: PairingName,
}

impl Default for SurfaceCaParams {
    /// The methods' own defaults: corrosion's from [`CorrosionParams`],
    /// Gray–Scott's from [`GrayScott`] (Pearson's spots).
    fn default() -> Self {
        let c = CorrosionParams::default();
        let g = GrayScott::default();
        Self {
            app: AppName::Voronoi,
            repair: false,
            cells: 100_000,
            cell_size: None,
            sites: 12,
            diagonal_p: None,
            max_steps: 100_000,
            steps: 600,
            feed: g.feed,
            kill: g.kill,
            patches: 20,
            k1: c.k1,
            k2: c.k2,
            k3: c.k3,
            seed_rate: c.seed_rate,
            max_seeds: c.max_seeds,
            strong_fraction: c.strong_fraction,
            strong_noise: c.strong_noise_scale,
            max_attacked: c.max_attacked,
            attack: c.attack,
            maturity: c.maturity,
            cell_mesh: false,
            displace: None,
            pairing: PairingName::Unfolded,
        }
    }
}

impl JobParams for SurfaceCaParams {
    const JOB: &'static str = "surface-ca";

    /// `displace` needs an application with a per-cell thickness (refused
    /// here, before the mesh is covered and the automaton run).
    fn check(&self) -> crate::error::Result<()> {
        if self.displace.is_some() && self.app == AppName::Voronoi {
            return Err(crate::error::invalid(
                "⟨displace⟩ needs a per-cell thickness (corrosion: oxide; gray-scott: activator)",
            ));
        }
        Ok(())
    }
}

impl SurfaceCaParams {
    /// The cell size asked for.
    pub fn cell_size(&self) -> CellSize {
        match self.cell_size {
            Some(h) => CellSize::Size(h),
            None => CellSize::Count(self.cells),
        }
    }

    /// The application as requested; `at` are site points (Voronoi) or
    /// initial corrosion sites, named in messages.
    pub fn request(&self, at: Option<(PointSet, String)>) -> AppRequest {
        match self.app {
            AppName::Voronoi => AppRequest::Voronoi {
                sites: self.sites,
                at,
                diagonal_p: self.diagonal_p,
                max_steps: self.max_steps,
            },
            AppName::Corrosion => AppRequest::Corrosion {
                params: CorrosionParams {
                    k1: self.k1,
                    k2: self.k2,
                    k3: self.k3,
                    seed_rate: self.seed_rate,
                    max_seeds: self.max_seeds,
                    strong_fraction: self.strong_fraction,
                    strong_noise_scale: self.strong_noise,
                    max_attacked: self.max_attacked,
                    attack: self.attack,
                    maturity: self.maturity,
                    ..CorrosionParams::default()
                },
                steps: self.steps,
                at,
            },
            AppName::GrayScott => AppRequest::GrayScott {
                feed: self.feed,
                kill: self.kill,
                patches: self.patches,
                steps: self.steps,
            },
        }
    }

    /// How the result mesh is made; `textured`: the original mesh with the
    /// cell atlas where no cell mesh is asked for.
    pub fn shape(&self, textured: bool) -> OutputShape {
        OutputShape {
            textured,
            cell_mesh: self.cell_mesh,
            displace: self.displace,
        }
    }
}

/// The inputs of a surface-CA job beside its parameters.
pub struct SurfaceCaInputs {
    /// The mesh.
    pub mesh: TriMesh,
    /// Its name in messages (a file, `builtin:cup`, `mesh`).
    pub name: String,
    /// Voronoi sites, or initial corrosion sites, at these points (and their
    /// name in messages).
    pub at: Option<(PointSet, String)>,
}

/// Runs `surface-ca`: refuses a run no machine could finish before any cell
/// is built, covers the mesh with cells, builds the application (its sites
/// chosen with `seed`) and runs it, calling `on_step(cells, step, colour of
/// cell c)` after every step (animation frames). The progress bar counts
/// the steps.
///
/// # Errors
/// The parameters' ([`crate::params::validate`]); a mesh the cells cannot
/// cover; sites that do not fit; the memory and time budgets.
pub fn run_job(
    p: &SurfaceCaParams,
    inputs: SurfaceCaInputs,
    seed: u64,
    (budget, time): (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
    mut on_step: impl FnMut(&Covered, u64, &dyn Fn(usize) -> [u8; 4]),
) -> Result<(Covered, AppRun)> {
    crate::params::validate(p)?;
    let request = p.request(inputs.at);
    let size = p.cell_size();
    if let Ok(cells) = asperity_surfca::cells::estimated_count(&inputs.mesh, size) {
        check_time(cells, &request.kind(), time)?;
    }
    let cov = cover(
        inputs.mesh,
        &inputs.name,
        p.repair,
        (size, p.pairing.pairing()),
        budget,
    )?;
    let app = request.build(&cov, seed)?;
    start_progress(progress, &app);
    let run = run_app(&cov, app, seed, time, |step, color| {
        progress.advance(1);
        on_step(&cov, step, color);
    })?;
    progress.finish();
    Ok((cov, run))
}
