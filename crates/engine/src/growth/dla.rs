//! Diffusion-limited aggregation (kim-machiraju-thompson §4.2, Figs. 4, 9–11)
//! from any seed, with the cluster's radius of gyration and fractal dimension.

use asperity_analysis::scaling::{
    density_dimension, density_profile, gyration_dimension, mass_radius_dimension,
    radius_of_gyration,
};
use asperity_core::{MemoryBudget, Progress, TimeBudget};
pub use asperity_growth::dla::Sides;
use asperity_growth::dla::{DlaCluster, DlaParams, dla};
use asperity_growth::seeds::{LatticeFrame, SeedSpec};
use serde_json::{Value, json};

use crate::error::Result;
use crate::plots::{NamedPlot, log_log, points};
use crate::report::Measurements;

/// A DLA run as `asperity growth dla` runs it.
#[derive(Clone, Debug, PartialEq)]
pub struct DlaJob {
    /// 2 (square lattice in the x–z plane) or 3. Default 3.
    pub dim: usize,
    /// Lattice size (default: [`SeedSpec::default_size`]).
    pub size: Option<[usize; 3]>,
    /// Particles released. Default 10 000.
    pub particles: usize,
    /// Sticking probability p in (0, 1]. Default 1.
    pub stick: f64,
    /// The seed. Default a point.
    pub seed: SeedSpec,
    /// Gap between the cluster and the launch sphere (plane), in cells. Default 2.
    pub launch_gap: f64,
    /// Plane seeds: periodic sides or walls. Default periodic.
    pub sides: Sides,
}

impl Default for DlaJob {
    fn default() -> Self {
        Self {
            dim: 3,
            size: None,
            particles: 10_000,
            stick: 1.0,
            seed: SeedSpec::Point,
            launch_gap: 2.0,
            sides: Sides::Periodic,
        }
    }
}

/// The cluster's fractal dimension and how it was measured.
#[derive(Clone, Debug)]
pub struct Dimension {
    /// D, when the fit could be made.
    pub value: Option<f64>,
    /// The method, in words.
    pub method: &'static str,
    /// The fits behind it (JSON).
    pub details: Value,
    /// Why `value` is absent or was withheld, for the user.
    pub warning: Option<String>,
}

impl Dimension {
    /// Withholds a fitted D outside [1, d] (a fit that measured something
    /// else), with a warning saying so.
    fn within(mut self, dim: usize) -> Self {
        if let Some(d) = self.value.filter(|d| !(1.0..=dim as f64).contains(d)) {
            self.value = None;
            self.warning = Some(format!(
                "the fractal dimension is not reported: the fit ({}) gave D = {d:.2}, outside [1, {dim}]",
                self.method
            ));
        }
        self
    }
}

/// What a DLA run gives.
#[derive(Clone, Debug)]
pub struct DlaRun {
    /// The parameters it ran with (the lattice size filled in).
    pub params: DlaParams,
    /// The cluster, in lattice cells.
    pub cluster: DlaCluster,
    /// Lattice cells to the input's coordinates (a mesh seed's).
    pub frame: LatticeFrame,
    /// R_g of the particles.
    pub radius_of_gyration: f64,
    /// D by R_g(n) (radial seeds) or ρ(z) (plane seeds).
    pub dimension: Dimension,
}

/// Grows the cluster of `job` and measures it.
///
/// # Errors
/// The seed's (a mesh that does not fit, an image density out of range) and
/// the simulator's (parameters, lattice capacity, memory budget).
pub fn grow(
    job: DlaJob,
    seed: u64,
    budget: &MemoryBudget,
    time: &TimeBudget,
    progress: &dyn Progress,
) -> Result<DlaRun> {
    crate::estimate::check(time, &crate::estimate::dla(job.particles as f64))?;
    let size = job
        .size
        .unwrap_or_else(|| job.seed.default_size(job.dim, job.particles, job.stick));
    let plane = job.seed.is_plane();
    let (seed_shape, frame) = job.seed.place(job.dim, size, budget)?;
    let params = DlaParams {
        dim: job.dim,
        size,
        particles: job.particles,
        stick: job.stick,
        seed_shape,
        launch_gap: job.launch_gap,
        sides: job.sides,
    };
    let cluster = dla(&params, seed, 0, budget, progress)?;
    let parts = particle_points(&cluster);
    let radius_of_gyration = if parts.is_empty() {
        0.0
    } else {
        radius_of_gyration(&parts)
    };
    let dimension = if plane {
        plane_dimension(&parts, size, job.dim)
    } else {
        radial_dimension(&cluster)
    }
    .within(job.dim);
    Ok(DlaRun {
        params,
        cluster,
        frame,
        radius_of_gyration,
        dimension,
    })
}

fn particle_points(c: &DlaCluster) -> Vec<[f64; 3]> {
    c.particles().iter().map(|p| p.map(f64::from)).collect()
}

/// D from the density profile ρ(z) ∝ z^(D−d) of a plane deposit.
fn plane_dimension(parts: &[[f64; 3]], size: [usize; 3], dim: usize) -> Dimension {
    let rho = density_profile(parts, (size[0] * size[1]) as f64);
    let dd = density_dimension(&rho, dim);
    Dimension {
        value: dd.as_ref().ok().map(|d| d.d),
        method: "density profile rho(z) ~ z^(D-d)",
        details: json!({"density_profile": rho, "fit": dd.as_ref().ok().map(|d| d.fit)}),
        warning: dd
            .as_ref()
            .err()
            .map(|e| format!("the fractal dimension is not reported: {e}")),
    }
}

/// D from R_g(n) ∝ n^(1/D) (and the mass–radius relation) of a cluster grown
/// from a point. Around a seed of many cells (a sphere, a mesh) R_g(n) stays
/// near the seed's own size, and the law measures the seed, not the deposit
/// (it gave D = 6.4 on a sphere, 7.5 on a mesh): D is then not reported.
fn radial_dimension(c: &DlaCluster) -> Dimension {
    let method = "radius of gyration R_g(n) ~ n^(1/D)";
    if c.seeds > 1 {
        return Dimension {
            value: None,
            method,
            details: json!({"gyration_fit": null, "mass_radius": null}),
            warning: Some(format!(
                "the fractal dimension is not reported for a seed of {} cells: R_g(n) ~ n^(1/D) holds for a cluster grown from a point (use --seed-shape point), or measure a plane deposit's density profile",
                c.seeds
            )),
        };
    }
    // A point seed starts the deposition order.
    let all = c.points();
    let g = gyration_dimension(&all);
    let m = mass_radius_dimension(&all, 2.0);
    Dimension {
        value: g.as_ref().ok().map(|d| d.d),
        method,
        details: json!({
            "gyration_fit": g.as_ref().ok().map(|d| d.fit),
            "mass_radius": m.as_ref().ok().map(|d| json!({"D": d.d, "fit": d.fit})),
        }),
        warning: g
            .as_ref()
            .err()
            .map(|e| format!("the fractal dimension is not reported: {e}")),
    }
}

impl DlaRun {
    /// Seeds and particles in the input's coordinates, in deposition order.
    pub fn world_points(&self) -> Vec<[f64; 3]> {
        let f = self.frame;
        self.cluster.cells.iter().map(|&c| f.to_world(c)).collect()
    }

    /// The notes and warnings a user should see: the deposit capped at the
    /// lattice top (a note), or a run stopped early (a warning).
    pub fn warnings(&self) -> Vec<(&'static str, String)> {
        let mut out = Vec::new();
        if let Some(k) = self.cluster.capped_at {
            out.push((
                "note",
                format!(
                    "the deposit reached the lattice top after {k} particles; later particles were released from the top layer"
                ),
            ));
        }
        if let Some(why) = &self.cluster.stopped {
            out.push(("warning", why.clone()));
        }
        if let Some(why) = &self.dimension.warning {
            out.push(("warning", why.clone()));
        }
        out
    }

    /// The measurements `asperity growth dla --json` reports.
    pub fn measurements(&self) -> Measurements {
        let (p, c) = (&self.params, &self.cluster);
        let mut m = Measurements::new();
        m.set("seed_shape", p.seed_shape.name());
        m.set("dim", p.dim);
        m.set("lattice", p.size);
        m.set("stick", p.stick);
        m.set("particles", c.particles().len());
        m.set("seeds", c.seeds);
        m.set("radius_of_gyration", self.radius_of_gyration);
        m.set("fractal_dimension", self.dimension.value);
        m.set("fractal_dimension_method", self.dimension.method);
        m.set("dimension_details", &self.dimension.details);
        m.set("walk", c.stats);
        m.set("stopped_early", &c.stopped);
        m
    }

    /// One line: particles, R_g, D.
    pub fn summary(&self) -> String {
        format!(
            "DLA ({}D, {} seed, p = {}): {} particles, R_g = {:.2}, D = {}",
            self.params.dim,
            self.params.seed_shape.name(),
            self.params.stick,
            self.cluster.particles().len(),
            self.radius_of_gyration,
            self.dimension_text()
        )
    }

    fn dimension_text(&self) -> String {
        self.dimension
            .value
            .map_or("n/a".into(), |d| format!("{d:.3}"))
    }

    /// `gyration.svg` (R_g(n)) and, for plane seeds, `density.svg` (ρ(z)).
    pub fn plots(&self) -> Vec<NamedPlot> {
        let all = self.cluster.points();
        let ns = (6..).map(|k| 1usize << k).take_while(|&n| n <= all.len());
        let rg = ns
            .map(|n| (n as f64, radius_of_gyration(&all[..n])))
            .collect();
        let mut out = vec![NamedPlot {
            name: "gyration.svg",
            plot: log_log(
                format!("DLA radius of gyration, D = {}", self.dimension_text()),
                "particles n",
                "R_g",
                vec![points("R_g(n)", rg)],
            ),
        }];
        if self.params.seed_shape.is_plane() {
            let size = self.params.size;
            let rho = density_profile(&particle_points(&self.cluster), (size[0] * size[1]) as f64);
            let data = rho
                .iter()
                .enumerate()
                .map(|(z, r)| (z as f64, *r))
                .collect();
            out.push(NamedPlot {
                name: "density.svg",
                plot: log_log(
                    "DLA deposit density profile".into(),
                    "height z",
                    "density",
                    vec![points("ρ(z)", data)],
                ),
            });
        }
        out
    }
}
