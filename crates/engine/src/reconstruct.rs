//! Level-set reconstruction (kim-machiraju-thompson §5) and the paper's
//! two-pass pipelines (Fig. 2: growth, then reconstruction): a DLA terrain
//! (Figs. 9–11) and an RDSR-grown sphere (Fig. 8).

use asperity_core::{MemoryBudget, Progress, TimeBudget, TriMesh};
use asperity_growth::Model;
use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_growth::dla::{DlaParams, SeedShape, dla};
use asperity_levelset::{Length, ReconstructParams, Reconstruction, Sizing, extract, reconstruct};
use serde_json::json;

use crate::error::{Result, invalid};
use crate::report::Measurements;

/// The settings a command uses when the user gives no sizing, offset or step count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Defaults {
    /// Grid sizing.
    pub sizing: Sizing,
    /// ε; `None` is 3h.
    pub offset: Option<Length>,
    /// Time steps.
    pub iterations: usize,
}

/// `asperity reconstruct`: 128 cells along the longest axis, ε = 3h, 30 steps.
pub const RECONSTRUCT: Defaults = Defaults {
    sizing: Sizing::Resolution(128),
    offset: None,
    iterations: 30,
};

/// The pipelines: the paper's ε = 3 lattice units, h = 0.7 (a 64-cell lattice
/// gives about the paper's 115-node grid with its padding), 60 steps.
pub const PIPELINE: Defaults = Defaults {
    sizing: Sizing::Spacing(0.7),
    offset: Some(Length::World(3.0)),
    iterations: 60,
};

/// Reconstructs a watertight surface from `points`; every `save_every` steps
/// (and at step 0) the current surface is handed to `on_snapshot` with its step.
///
/// # Errors
/// The pipeline's (parameters, memory budget); [`crate::EngineError::Invalid`]
/// for `save_every` = 0 or when the offset surface vanished.
pub fn surface(
    points: &[[f64; 3]],
    params: &ReconstructParams,
    save_every: Option<usize>,
    (budget, time): (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
    on_snapshot: &mut dyn FnMut(usize, TriMesh),
) -> Result<Reconstruction> {
    if save_every == Some(0) {
        return Err(invalid("--save-every needs K ≥ 1"));
    }
    params.validate()?;
    let grid = asperity_levelset::pipeline::grid_for(points, params, budget)?;
    let iterations = params.iterations as f64;
    crate::estimate::check(
        time,
        &crate::estimate::level_set(grid.len() as f64, iterations),
    )?;
    if let Some(k) = save_every {
        crate::estimate::check_file_count(params.iterations as u64 / k as u64 + 1, "--save-every")?;
    }
    let rec = reconstruct(points, params, budget, progress, &mut |step, ls| {
        let Some(k) = save_every else { return };
        if !step.step.is_multiple_of(k) {
            return;
        }
        let (mesh, _) = extract(&ls.phi, &ls.grid, &params.extract);
        if mesh.n_faces() > 0 {
            on_snapshot(step.step, mesh);
        }
    })?;
    if rec.mesh.n_faces() == 0 {
        return Err(invalid(
            "the reconstruction is empty: the offset surface vanished (try a smaller --offset or more points)",
        ));
    }
    Ok(rec)
}

/// The mesh's counts and topology.
fn mesh_facts(r: &mut Measurements, rec: &Reconstruction) {
    let m = &rec.mesh;
    r.set("vertices", m.n_vertices());
    r.set("triangles", m.n_faces());
    r.set("euler_characteristic", m.euler_characteristic());
    r.set("genus", m.genus());
    r.set("watertight", m.is_watertight());
    r.set("manifold", m.is_manifold());
    r.set("components", rec.extraction.components);
    r.set("shells_removed", rec.extraction.shells_removed);
    r.set("area", m.area());
    if m.is_watertight() {
        r.set("volume", m.signed_volume());
    }
}

/// The measurements `asperity reconstruct --json` reports for `rec` of `points` points.
pub fn measurements(rec: &Reconstruction, points: usize) -> Measurements {
    let t = &rec.timings;
    let mut r = Measurements::new();
    r.set("grid", rec.grid.dims);
    r.set("spacing", rec.grid.spacing);
    r.set("origin", rec.grid.origin);
    r.set("offset", rec.offset);
    r.set("point_radius", rec.point_radius);
    r.set("sample_spacing", rec.sample_spacing);
    r.set(
        "timings_s",
        json!({
            "distance": t.distance,
            "tagging": t.tagging,
            "initial_surface": t.initial,
            "evolution": t.evolution,
            "marching_cubes": t.extraction,
            "total": t.total,
        }),
    );
    r.set("points", points);
    mesh_facts(&mut r, rec);
    let steps = &rec.evolution.steps;
    r.set("iterations", steps.len());
    r.set("converged", rec.evolution.converged);
    let movement: Vec<f64> = steps.iter().map(|s| s.front_movement).collect();
    r.set("front_movement", movement);
    r.set("tagged_exterior", rec.tagged.0);
    r.set("tagging_refused", rec.tagged.1);
    r.set("distance_sweeps", rec.distance_sweeps);
    r
}

/// One line: grid, ε, δ, counts, topology and stage times.
pub fn summary(rec: &Reconstruction) -> String {
    let (m, t, g) = (&rec.mesh, &rec.timings, &rec.grid);
    format!(
        "grid {}×{}×{} (h = {:.4}), ε = {:.3}, δ = {:.3}: {} vertices, {} triangles, χ = {}, {} piece(s), {}watertight; {:.2} s (distance {:.2}, tagging {:.2}, flow {:.2} for {} steps, marching cubes {:.2})",
        g.dims[0],
        g.dims[1],
        g.dims[2],
        g.spacing,
        rec.offset,
        rec.point_radius,
        m.n_vertices(),
        m.n_faces(),
        m.euler_characteristic(),
        rec.extraction.components,
        if m.is_watertight() { "" } else { "not " },
        t.total,
        t.distance,
        t.tagging,
        t.evolution,
        rec.evolution.steps.len(),
        t.extraction,
    )
}

/// The first pass of a pipeline: the points to reconstruct and what was grown.
#[derive(Clone, Debug)]
pub struct Grown {
    /// Every occupied cell (seeds first), as points.
    pub points: Vec<[f64; 3]>,
    /// What the growth measured (`particles`, `lattice` or `thickness`).
    pub facts: Measurements,
    /// Why the growth stopped early, if it did.
    pub warnings: Vec<String>,
}

/// A DLA terrain: a plane deposit of `particles` on a lattice of `size` with
/// sticking probability `stick` (kim-machiraju-thompson Figs. 9–11).
///
/// # Errors
/// The simulator's (parameters, memory budget).
pub fn dla_terrain(
    size: [usize; 3],
    particles: usize,
    stick: f64,
    (seed, budget, time, progress): (u64, &MemoryBudget, &TimeBudget, &dyn Progress),
) -> Result<Grown> {
    crate::estimate::check(time, &crate::estimate::dla(particles as f64))?;
    let params = DlaParams {
        dim: 3,
        size,
        particles,
        stick,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
    };
    let cluster = dla(&params, seed, 0, budget, progress)?;
    let mut facts = Measurements::new();
    facts.set("particles", cluster.particles().len());
    facts.set("lattice", size);
    facts.set("reached_top_after", cluster.capped_at);
    // The same words as `growth dla` (#22: only that command said it).
    let capped = cluster.capped_at.map(|k| {
        format!(
            "the deposit reached the lattice top after {k} particles; later particles were released from the top layer (a taller --size keeps the growth free)"
        )
    });
    Ok(Grown {
        points: cluster.points(),
        facts,
        warnings: capped.into_iter().chain(cluster.stopped).collect(),
    })
}

/// An RDSR deposit of `layers` monolayers (relaxation radius `relax`) on a ball
/// of `radius` cells (kim-machiraju-thompson Fig. 8).
///
/// # Errors
/// The simulator's (parameters, memory budget).
pub fn rdsr_sphere(
    radius: f64,
    layers: f64,
    relax: u32,
    (seed, budget, progress): (u64, &MemoryBudget, &dyn Progress),
) -> Result<Grown> {
    let params = CurvedParams {
        model: Model::Rdsr { radius: relax },
        substrate: CurvedSubstrate::Sphere(radius),
        layers,
        samples_per_decade: 10,
    };
    let deposit = deposit_curved(&params, seed, 0, budget, progress)?;
    let points = deposit.points();
    let mut facts = Measurements::new();
    facts.set("particles", points.len() - deposit.seeds);
    facts.set("thickness", deposit.thickness);
    Ok(Grown {
        points,
        facts,
        warnings: Vec::new(),
    })
}
