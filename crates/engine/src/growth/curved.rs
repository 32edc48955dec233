//! RD, RDSR and BD on a sphere or on any closed mesh (kim-machiraju-thompson
//! §6 Fig. 8 and §7), with W(t) and β about the substrate.

use asperity_analysis::AnalysisError;
use asperity_analysis::scaling::{GrowthFit, growth_exponent};
use asperity_core::{MemoryBudget, Progress, TriMesh};
use asperity_growth::Model;
use asperity_growth::curved::{CurvedDeposit, CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_growth::seeds::{LatticeFrame, mesh_substrate};

use crate::error::{Result, ensure};
use crate::growth::deposition::{width_plot, width_records};
use crate::plots::NamedPlot;
use crate::report::Measurements;

/// The substrate of a curved deposit.
#[derive(Clone, Debug, PartialEq)]
pub enum Substrate {
    /// A solid ball of this radius in cells.
    Sphere(f64),
    /// A closed mesh voxelised at `resolution` cells along its longest axis.
    Mesh {
        /// The mesh, in its own coordinates.
        mesh: TriMesh,
        /// Cells along its longest axis.
        resolution: usize,
    },
}

impl Substrate {
    /// `sphere` or `mesh`.
    pub fn name(&self) -> &'static str {
        match self {
            Substrate::Sphere(_) => "sphere",
            Substrate::Mesh { .. } => "mesh",
        }
    }
}

/// A curved deposit as `asperity growth rd|rdsr|bd --substrate sphere|mesh` runs it.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvedJob {
    /// RD, RDSR or BD.
    pub model: Model,
    /// The substrate.
    pub substrate: Substrate,
    /// Monolayers.
    pub layers: f64,
    /// Width samples per decade of time.
    pub samples_per_decade: usize,
}

/// What a curved run gives.
#[derive(Clone, Debug)]
pub struct CurvedRun {
    /// Substrate cells, then the particles, on the lattice.
    pub deposit: CurvedDeposit,
    /// Lattice cells to the input's coordinates.
    pub frame: LatticeFrame,
    /// β of W(t) over [1, T].
    pub plain: Result<GrowthFit, AnalysisError>,
}

/// Runs `job`.
///
/// # Errors
/// The voxeliser's (an open mesh) and the simulator's (memory budget).
pub fn deposit(
    job: &CurvedJob,
    seed: u64,
    budget: &MemoryBudget,
    progress: &dyn Progress,
) -> Result<CurvedRun> {
    let (substrate, frame) = match &job.substrate {
        Substrate::Sphere(r) => (CurvedSubstrate::Sphere(*r), LatticeFrame::IDENTITY),
        Substrate::Mesh { mesh, resolution } => {
            mesh_substrate(mesh, *resolution, job.model, job.layers, budget)?
        }
    };
    ensure(job.samples_per_decade >= 1, || {
        "⟨samples_per_decade⟩ must be at least 1".into()
    })?;
    let params = CurvedParams {
        model: job.model,
        substrate,
        layers: job.layers,
        samples_per_decade: job.samples_per_decade,
    };
    let deposit = deposit_curved(&params, seed, 0, budget, progress)?;
    let window = [1.0, job.layers.max(1.0)];
    let plain = growth_exponent(&deposit.series.t, &deposit.series.width(), window);
    Ok(CurvedRun {
        deposit,
        frame,
        plain,
    })
}

impl CurvedRun {
    /// Every occupied cell in the input's coordinates: substrate cells first.
    pub fn world_points(&self) -> Vec<[f64; 3]> {
        let f = self.frame;
        self.deposit.cells.iter().map(|&c| f.to_world(c)).collect()
    }

    /// Particles deposited (substrate cells not counted).
    pub fn particles(&self) -> usize {
        self.deposit.cells.len() - self.deposit.seeds
    }

    /// The measurements `--json` reports.
    pub fn measurements(&self, job: &CurvedJob) -> Measurements {
        let d = &self.deposit;
        let mut m = Measurements::new();
        m.set("model", job.model.name());
        m.set("substrate", job.substrate.name());
        m.set("lattice", d.size);
        m.set("substrate_cells", d.seeds);
        m.set("particles", self.particles());
        m.set("thickness", d.thickness);
        m.set("width_series", width_records(&d.series));
        m.set("beta", self.plain.as_ref().ok().map(|f| f.exponent));
        m
    }

    /// One line: particles, surface cells, thickness, W.
    pub fn summary(&self, job: &CurvedJob) -> String {
        let d = &self.deposit;
        format!(
            "{} on a {} substrate: {} particles on {} surface cells, thickness {:.1} cells, W = {:.3}",
            job.model.name(),
            job.substrate.name(),
            self.particles(),
            d.seeds,
            d.thickness,
            d.series.w2.last().map_or(0.0, |v| v.sqrt())
        )
    }

    /// `width.svg`: W(t) with its fit.
    pub fn plots(&self, job: &CurvedJob) -> Vec<NamedPlot> {
        let title = format!(
            "{} on a {} substrate",
            job.model.name(),
            job.substrate.name()
        );
        vec![NamedPlot {
            name: "width.svg",
            plot: width_plot(&title, &self.deposit.series, self.plain.as_ref().ok(), None),
        }]
    }
}
