//! Diffusion-limited aggregation (kim-machiraju-thompson §4.2, Figs. 4, 9–11)
//! from any seed, with the cluster's radius of gyration and fractal dimension.

use asperity_analysis::scaling::{
    ClusterDimension, density_dimension, density_profile, gyration_dimension,
    mass_radius_dimension, pair_dimension, radius_of_gyration,
};
use asperity_core::{HeightField, MemoryBudget, Progress, TimeBudget, TriMesh};
use asperity_growth::dla::{
    DlaCluster, DlaParams as Simulation, Sides as GrowthSides, dla, dla_with_walkers,
    substrate::{PairCorrelation, ShellProfile},
};
use asperity_growth::seeds::{LatticeFrame, SeedSpec};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use serde_json::{Value, json};

use crate::error::{EngineError, Result};
use crate::params::{JobParams, LatticeSize, choice};
use crate::plots::{NamedPlot, fit_line, log_log, points};
use crate::report::Measurements;

choice! {
    /// The seed a DLA cluster grows on.
    pub enum SeedShape {
        /// One cell at the lattice centre (a radial cluster).
        Point = "point",
        /// The whole bottom plane z = 0 (a deposit).
        Plane = "plane",
        /// A solid ball at the lattice centre (its radius: the seed radius).
        Sphere = "sphere",
        /// A closed mesh (an input), voxelised at the resolution.
        Mesh = "mesh",
        /// The bottom plane, seeded where an image (an input) is bright, up to the seed density.
        Image = "image",
    }
}

choice! {
    /// Plane and image seeds: what happens at the lattice's x and y sides.
    pub enum Sides {
        /// The lattice wraps (sizes multiples of 8): no edge effects, the usual set-up of growth physics.
        Periodic = "periodic",
        /// Reflecting walls: the deposit is one connected piece (a terrain), any size.
        Walls = "walls",
    }
}

impl From<Sides> for GrowthSides {
    fn from(s: Sides) -> Self {
        match s {
            Sides::Periodic => GrowthSides::Periodic,
            Sides::Walls => GrowthSides::Walls,
        }
    }
}

/// Diffusion-limited aggregation (`growth dla`): random walkers released far
/// from the cluster stick where they touch it (kim-machiraju-thompson §4.2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct DlaParams {
    /// Seed shape.
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.seed_shape)]
    pub seed_shape: SeedShape,
    /// Lattice size in cells: N (a cube; N×N in 2-D), NXxNYxNZ, or NXxNZ in 2-D.
    /// Default: sized for the particles (radial seeds), 128x128x128 (plane seeds; 512x512 in 2-D).
    #[arg(long, value_name = "NXxNYxNZ")]
    pub size: Option<LatticeSize>,
    /// Lattice dimension: 3 (cubic, 6 neighbours) or 2 (square in the x–z plane, 4 neighbours).
    #[schemars(range(min = 2, max = 3))]
    #[arg(long, default_value_t = Self::DEFAULT.dim)]
    pub dim: usize,
    /// Particles to deposit (seeds not counted).
    #[schemars(range(min = 1, max = 10_000_000_000u64))]
    #[arg(long, default_value_t = Self::DEFAULT.particles)]
    pub particles: usize,
    /// Sticking probability p in (0, 1]: 1 dendritic, small p moss-like.
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1.0))]
    #[arg(long, default_value_t = Self::DEFAULT.stick)]
    pub stick: f64,
    /// Radius of the sphere seed, in cells.
    #[schemars(range(min = 0.5, max = 1e6))]
    #[arg(long, default_value_t = Self::DEFAULT.seed_radius)]
    pub seed_radius: f64,
    /// Cells along the seed mesh's longest axis.
    #[schemars(range(min = 2, max = 4096))]
    #[arg(long, default_value_t = Self::DEFAULT.resolution)]
    pub resolution: usize,
    /// Probability of a seed in the column of the image's brightest pixel (image seeds), in (0, 1].
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1.0))]
    #[arg(long, default_value_t = Self::DEFAULT.seed_density)]
    pub seed_density: f64,
    /// Gap δ between the cluster and the launch sphere or plane, in cells.
    #[schemars(range(min = 1.0, max = 1e4))]
    #[arg(long, default_value_t = Self::DEFAULT.launch_gap)]
    pub launch_gap: f64,
    /// Plane and image seeds: the lattice's x and y sides.
    #[arg(long, value_enum, default_value_t = Self::DEFAULT.sides)]
    pub sides: Sides,
}

impl DlaParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        seed_shape: SeedShape::Point,
        size: None,
        dim: 3,
        particles: 20_000,
        stick: 1.0,
        seed_radius: 10.0,
        resolution: 32,
        seed_density: 0.02,
        launch_gap: Simulation::DEFAULT_LAUNCH_GAP,
        sides: Sides::Periodic,
    };
}

impl Default for DlaParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl JobParams for DlaParams {
    const JOB: &'static str = "growth dla";

    fn check(&self) -> Result<()> {
        if let Some(size) = &self.size {
            size.resolve(self.dim)?;
        }
        Ok(())
    }
}

/// What a DLA run takes beside its parameters: the seed's inputs, and how
/// many walks run at once (none of which the cluster depends on).
#[derive(Clone, Debug, Default)]
pub struct SeedInputs {
    /// The seed mesh (`seed_shape` mesh).
    pub mesh: Option<TriMesh>,
    /// The seed-density image (`seed_shape` image).
    pub image: Option<HeightField>,
    /// Concurrent walkers (default: one a core of the current pool, at most
    /// `DEFAULT_WALKERS_MAX`). More
    /// than the cores measure the concurrency a larger machine would see; the
    /// cluster is the same for any number.
    pub walkers: Option<usize>,
}

impl DlaParams {
    /// The simulator's seed: the shape with its input.
    fn seed_spec(&self, inputs: SeedInputs) -> Result<SeedSpec> {
        let missing = |what: &str| {
            EngineError::Invalid(format!(
                "{} needs {}",
                asperity_core::wording::param_value("seed_shape", what),
                asperity_core::wording::param(what)
            ))
        };
        Ok(match self.seed_shape {
            SeedShape::Point => SeedSpec::Point,
            SeedShape::Plane => SeedSpec::Plane,
            SeedShape::Sphere => SeedSpec::Sphere(self.seed_radius),
            SeedShape::Mesh => SeedSpec::Mesh {
                mesh: inputs.mesh.ok_or_else(|| missing("mesh"))?,
                resolution: self.resolution,
            },
            SeedShape::Image => SeedSpec::Image {
                image: inputs.image.ok_or_else(|| missing("image"))?,
                density: self.seed_density,
            },
        })
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
    /// The pair count and its fit, about a point or a substrate
    /// ([`asperity_growth::dla::substrate`]).
    pub pairs: Option<PairFit>,
}

/// A deposit's pair count N(s) and the fit N ∝ s^D.
#[derive(Clone, Debug)]
pub struct PairFit {
    /// The counts.
    pub counts: PairCorrelation,
    /// D and its fit.
    pub fit: ClusterDimension,
    /// The window of particles counted about (volume-equivalent radius).
    pub window: [f64; 2],
}

impl PairFit {
    fn of(profile: &ShellProfile) -> Option<Self> {
        let counts = profile.pairs.clone()?;
        let fit = pair_dimension(&counts.radius, &counts.neighbours).ok()?;
        Some(Self {
            counts,
            fit,
            window: profile.fit_range(),
        })
    }

    fn details(&self) -> Value {
        json!({
            "D": self.fit.d,
            "fit": self.fit.fit,
            "centres_from": self.window,
            "centres": self.counts.centres,
            "radius": self.counts.radius,
            "neighbours": self.counts.neighbours,
        })
    }
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
    /// The job's parameters with the lattice size filled in (what
    /// [`crate::params::record`] records).
    pub resolved: DlaParams,
    /// The simulator's parameters.
    pub params: Simulation,
    /// The cluster, in lattice cells.
    pub cluster: DlaCluster,
    /// Lattice cells to the input's coordinates (a mesh seed's).
    pub frame: LatticeFrame,
    /// R_g of the particles.
    pub radius_of_gyration: f64,
    /// D by R_g(n) (radial seeds) or ρ(z) (plane seeds).
    pub dimension: Dimension,
}

/// Grows the cluster of `p` from its seed and measures it.
///
/// # Errors
/// The parameters' ([`crate::params::validate`]), the seed's (a mesh that does
/// not fit, a missing input) and the simulator's (lattice capacity, memory
/// budget, time budget).
pub fn grow(
    p: &DlaParams,
    inputs: SeedInputs,
    seed: u64,
    budget: &MemoryBudget,
    time: &TimeBudget,
    progress: &dyn Progress,
) -> Result<DlaRun> {
    crate::params::validate(p)?;
    crate::estimate::check(time, &crate::estimate::dla(p.particles as f64))?;
    if inputs.walkers == Some(0) {
        return Err(EngineError::Invalid(format!(
            "{} must be at least 1",
            asperity_core::wording::param("walkers")
        )));
    }
    let walkers = inputs.walkers;
    let spec = p.seed_spec(inputs)?;
    let size = match &p.size {
        Some(s) => s.resolve(p.dim)?,
        None => spec.default_size(p.dim, p.particles, p.stick),
    };
    let plane = spec.is_plane();
    let (seed_shape, frame) = spec.place(p.dim, size, budget)?;
    let params = Simulation {
        dim: p.dim,
        size,
        particles: p.particles,
        stick: p.stick,
        seed_shape,
        launch_gap: p.launch_gap,
        sides: p.sides.into(),
    };
    let resolved = DlaParams {
        size: Some(LatticeSize::new(&size)?),
        ..p.clone()
    };
    let cluster = match walkers {
        Some(w) => dla_with_walkers(&params, seed, 0, budget, progress, w)?,
        None => dla(&params, seed, 0, budget, progress)?,
    };
    let parts = particle_points(&cluster);
    let radius_of_gyration = if parts.is_empty() {
        0.0
    } else {
        radius_of_gyration(&parts)
    };
    let dimension = if plane {
        plane_dimension(&parts, size, p.dim)
    } else {
        radial_dimension(&cluster, &params.seed_shape, budget)
    }
    .within(p.dim);
    Ok(DlaRun {
        resolved,
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
        pairs: None,
    }
}

/// D from R_g(n) ∝ n^(1/D) (and the mass–radius relation) of a cluster grown
/// from a point. Around a seed of many cells (a sphere, a mesh) R_g(n) stays
/// near the seed's own size, and the law measures the seed, not the deposit
/// (it gave D = 6.4 on a sphere, 7.5 on a mesh): D is then measured about the
/// substrate instead, from the deposit's pair correlation N(s) ∝ s^D about the
/// particles from the seed's radius + 5 cells to where the cluster thins
/// ([`asperity_growth::dla::substrate`]). A point seed reports the same pair
/// count beside R_g(n), so the two can be compared like for like.
fn radial_dimension(
    c: &DlaCluster,
    seed: &asperity_growth::dla::SeedShape,
    budget: &MemoryBudget,
) -> Dimension {
    let method = "radius of gyration R_g(n) ~ n^(1/D)";
    if c.seeds > 1 {
        return substrate_dimension(c, seed, budget);
    }
    // A point seed starts the deposition order.
    let all = c.points();
    let g = gyration_dimension(&all);
    let m = mass_radius_dimension(&all, 2.0);
    // The pair count is a second measure: over the memory budget it is
    // skipped with a warning, and R_g(n) still gives D.
    let about_the_seed = asperity_growth::dla::substrate::shell_profile(c, seed, budget);
    let pairs = about_the_seed
        .as_ref()
        .ok()
        .and_then(Option::as_ref)
        .and_then(PairFit::of);
    let warning = match (&g, &about_the_seed) {
        (Err(e), _) => Some(format!("the fractal dimension is not reported: {e}")),
        (Ok(_), Err(e)) => Some(format!("the pair count beside R_g(n) is not reported: {e}")),
        _ => None,
    };
    Dimension {
        value: g.as_ref().ok().map(|d| d.d),
        method,
        details: json!({
            "gyration_fit": g.as_ref().ok().map(|d| d.fit),
            "mass_radius": m.as_ref().ok().map(|d| json!({"D": d.d, "fit": d.fit})),
            "pair_correlation": pairs.as_ref().map(PairFit::details),
        }),
        warning,
        pairs,
    }
}

/// D about the substrate of a cluster grown on a sphere or a mesh: the pair
/// correlation of the particles from the seed's radius + 5 cells to half the
/// particles' R_g about the seed. The shell density about the seed is reported
/// beside it as a profile (its slope mixes the deposit with the seed's
/// curvature: see `asperity_growth::dla::substrate`).
fn substrate_dimension(
    c: &DlaCluster,
    seed: &asperity_growth::dla::SeedShape,
    budget: &MemoryBudget,
) -> Dimension {
    let method = "pair correlation N(s) ~ s^D of the deposit about the substrate";
    // Over the memory budget the cluster is still delivered, without D.
    let profile = match asperity_growth::dla::substrate::shell_profile(c, seed, budget) {
        Ok(Some(p)) => p,
        absent => {
            let why = match absent {
                Err(e) => e.to_string(),
                _ => format!(
                    "{} particles on a seed of {} cells are too few (need ≥ 256)",
                    c.particles().len(),
                    c.seeds
                ),
            };
            return Dimension {
                value: None,
                method,
                details: json!({"substrate": null}),
                warning: Some(format!("the fractal dimension is not reported: {why}")),
                pairs: None,
            };
        }
    };
    let [from, to] = profile.fit_range();
    let pairs = PairFit::of(&profile);
    let mut warning = match (&pairs, to > from) {
        (Some(_), _) => None,
        (None, true) => Some(format!(
            "the fractal dimension is not reported: the cluster thins at radius {to:.1}, \
             too close to the seed for pair radii of 4 to {:.1} cells: grow more particles",
            0.5 * to
        )),
        (None, false) => Some(format!(
            "the fractal dimension is not reported: the cluster thins at radius {to:.1}, \
             inside the window's start {from:.1} (the seed's radius + 5): grow more particles"
        )),
    };
    if profile.clipped && warning.is_none() {
        warning = Some(format!(
            "the lattice boundary cut the shells about the seed short; the window stops at radius {:.1}",
            profile.thin_radius
        ));
    }
    Dimension {
        value: pairs.as_ref().map(|p| p.fit.d),
        method,
        details: json!({
            "substrate": {
                "seed_radius": profile.seed_radius,
                "gyration_about_seed": profile.gyration,
                "fit_range": profile.fit_range(),
                "pair_correlation": pairs.as_ref().map(PairFit::details),
                "radius": profile.radius,
                "density": profile.density,
            }
        }),
        warning,
        pairs,
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
        m.set("walkers", c.concurrency);
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
        // D comes from R_g(n) only about a point.
        let title = if self.cluster.seeds == 1 && !self.params.seed_shape.is_plane() {
            format!("DLA radius of gyration, D = {}", self.dimension_text())
        } else {
            "DLA radius of gyration (about the seed's centre: it measures the seed)".into()
        };
        let mut out = vec![NamedPlot {
            name: "gyration.svg",
            plot: log_log(title, "particles n", "R_g", vec![points("R_g(n)", rg)]),
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
        if let Some(p) = &self.dimension.pairs {
            let data = p
                .counts
                .radius
                .iter()
                .copied()
                .zip(p.counts.neighbours.iter().copied())
                .collect();
            out.push(NamedPlot {
                name: "pairs.svg",
                plot: log_log(
                    format!(
                        "DLA pair count about the particles at radius {:.0}–{:.0} (volume-equivalent, about the seed), D = {:.3}",
                        p.window[0], p.window[1], p.fit.d
                    ),
                    "radius s (cells)",
                    "particles within s",
                    vec![
                        points("N(s)", data),
                        fit_line(format!("N ∝ s^{:.3}", p.fit.d), &p.fit.fit),
                    ],
                ),
            });
        }
        out
    }
}
