//! Level-set reconstruction (kim-machiraju-thompson §5) and the paper's
//! two-pass pipelines (Fig. 2: growth, then reconstruction): a DLA terrain
//! (Figs. 9–11) and an RDSR-grown sphere (Fig. 8).

use asperity_core::{MemoryBudget, Progress, TimeBudget, Topology, TriMesh};
use asperity_growth::Model;
use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_growth::dla::{DlaParams, SeedShape, dla};
use asperity_levelset::{
    CloudChoice, DistanceMethod, Length, Neighbourhood, ReconstructParams, Reconstruction, Sizing,
    reconstruct_cloud,
};
use serde_json::json;

mod params;
pub mod quality;

pub use params::{
    CloudName, DistanceName, DlaTerrainParams, FlowName, LevelSetParams, Offset, RdsrSphereParams,
    SchemeChoice, Tagging, TubeN,
};

use crate::error::{Result, invalid};
use crate::growth::dla::Sides;
use crate::report::Measurements;

/// The settings a command uses for what the user does not give.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Defaults {
    /// Grid sizing.
    pub sizing: Sizing,
    /// ε; `None` is 3h.
    pub offset: Option<Length>,
    /// Time steps.
    pub iterations: usize,
    /// Time steps for a sampled surface.
    pub surface_iterations: usize,
    /// The unsigned-distance method.
    pub distance: DistanceMethod,
    /// How the flow tube T grows into the redistancing tube N.
    pub neighbourhood: Neighbourhood,
    /// The arrest distance δ; `None` sets it from the sample spacing.
    pub point_radius: Option<f64>,
    /// What the points are taken to be.
    pub cloud: CloudChoice,
}

/// `asperity reconstruct`: 128 cells along the longest axis, ε = 3h, 30 steps
/// (200 for a sampled surface: Zhao's front carves a scan's concavities
/// slowly; the bunny scan's area comes within 0.3 % of the scan's own at 200
/// steps and is 12 % above it at 30); what the points are is measured (a
/// sampled surface or a deposit, see `asperity_levelset::cloud`).
pub const RECONSTRUCT: Defaults = Defaults {
    sizing: Sizing::Resolution(128),
    offset: None,
    iterations: 30,
    surface_iterations: 200,
    distance: DistanceMethod::ClosestPoint,
    neighbourhood: Neighbourhood::Axes,
    point_radius: None,
    cloud: CloudChoice::Auto,
};

/// The pipelines: the paper's ε = 3 lattice units, h = 0.7 (a 64-cell lattice
/// gives about the paper's 115-node grid with its padding), 60 steps.
pub const PIPELINE: Defaults = Defaults {
    sizing: Sizing::Spacing(0.7),
    offset: Some(Length::World(3.0)),
    iterations: 60,
    surface_iterations: 200,
    distance: DistanceMethod::ClosestPoint,
    neighbourhood: Neighbourhood::Axes,
    point_radius: None,
    cloud: CloudChoice::Deposit,
};

/// `--paper` for `asperity reconstruct`: the paper's own settings and
/// algorithms (kim-machiraju-thompson §5.2, §6) — ε = 3 grid cells, 30 steps,
/// Godunov fast sweeping (Eqs. 8–9), the 3 × 3 × 3 tube N, the redistancing of
/// Eq. 11 — with one deviation: the arrest distance δ stays
/// (`--point-radius 0` gives the pure flow of Eq. 6). Measured:
/// - Eq. 6 alone (δ = 0, no redistancing) keeps a densely sampled sphere (10⁵
///   samples, R = 10, h = 0.156) within 0.08 (0.5h) for 200 steps: the flow
///   itself stops on the data.
/// - With Eq. 11's redistancing (Sussman's first-order scheme, two iterations
///   per step, as the paper does), the zero level drifts where the front sits
///   between samples, and at 30 steps the front has crept through every kind
///   of data measured: the dense sphere (within 0.14 at step 10, then 0.46
///   inside at step 20 and 1.16 = 7.4h at step 30); the RDSR sphere of Fig. 8
///   (lattice cells 1 apart, h = 0.6: eaten down to the substrate, mean radius
///   19.9 against 26.0 with δ); the DLA terrain of Fig. 9 (43 pieces against
///   one with δ). Pinning the nodes next to the front during redistancing does
///   not stop it, and neither does a subcell redistancing that does not move
///   the zero level (Russo & Smereka 2000: the nodes next to the front relax to
///   φ/|∇φ|; measured 2026-11-29 on the same sphere, δ = 0, worst/mean distance
///   at step 30: 13.4h/−5.6h against 13.0h/−7.4h with Sussman's scheme), nor
///   that plus the front's own speed (d − |φ| ≥ 0, the 1-Lipschitz bound of d at
///   the front, the time step still from c·d): it reaches 0.35h at step 20 and
///   is 3.5h inside at step 30. The cause is the model, not the redistancing:
///   with the unsigned d of Eq. 6 a front that crosses the data anywhere, by
///   any O(h) error of the scheme at the kink of d, meets a speed that grows
///   with its depth (a front at depth x moves to x/(1 − Δt)), and nothing
///   brings it back. δ is therefore kept.
/// - Without redistancing the front stalls where it must travel far (Fig. 7's
///   ε = 17 cells: after 200 steps the synthetic bunny's ears are still not
///   carved out), so dropping Eq. 11 is no cure either.
/// - Sampled data have no rest for the front but the samples. A 2-D model
///   (`docs/experiments/eq6_front_speed.py`, exact redistancing) separates the
///   two causes: with the front moving at its own exact d (an extension
///   velocity) and the nodes next to it left alone by the redistancing, a
///   continuous circle (d = 0 on all of it) holds within 0.012h for 200 steps,
///   where either fix alone is 4.5–8.3h inside by step 100–200; but the same
///   circle sampled 0.5h, 1h or 2h apart is 3.7h, 7.9h or 11.5h inside at step
///   100: between samples d > 0 and the front goes on. Every input here is
///   sampled, so no scheme faithful to Eq. 6 can drop δ; it could go only for
///   data whose distance vanishes on a whole surface.
///
/// δ (0.75 × the sample spacing up to 60 steps, growing to one spacing at 200
/// steps, at least 0.6h: `asperity_levelset::default_arrest_spacings`) stops
/// the front before the drift can carry it through, and keeps Eq. 11.
pub const RECONSTRUCT_PAPER: Defaults = Defaults {
    sizing: Sizing::Resolution(128),
    offset: Some(Length::Cells(3.0)),
    iterations: 30,
    surface_iterations: 30,
    distance: DistanceMethod::GODUNOV,
    neighbourhood: Neighbourhood::Cube,
    point_radius: None,
    cloud: CloudChoice::Deposit,
};

/// `--paper` for the pipelines (Figs. 8, 9, 11): as [`RECONSTRUCT_PAPER`] on
/// 96 cells along the lattice (ε = 3h and γ = 3h of padding give the paper's
/// 115-node grid on a 64³ lattice).
pub const PIPELINE_PAPER: Defaults = Defaults {
    sizing: Sizing::Resolution(96),
    ..RECONSTRUCT_PAPER
};

/// Pieces with fewer triangles are dropped from the mesh (single-node voids the
/// flow opens inside a deposit have 8).
pub const MIN_SHELL_TRIANGLES: usize = 32;

impl Defaults {
    /// The reconstruction settings with these defaults, shells below
    /// [`MIN_SHELL_TRIANGLES`] dropped (the rest as [`ReconstructParams::default`]).
    pub fn params(&self) -> ReconstructParams {
        ReconstructParams {
            extract: asperity_levelset::ExtractOptions {
                curvature: false,
                min_shell_triangles: MIN_SHELL_TRIANGLES,
            },
            sizing: self.sizing,
            offset: self.offset,
            iterations: self.iterations,
            surface_iterations: Some(self.surface_iterations),
            distance: self.distance,
            neighbourhood: self.neighbourhood,
            point_radius: self.point_radius,
            cloud: self.cloud,
            ..ReconstructParams::default()
        }
    }
}

/// Which command's defaults.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Job {
    /// `asperity reconstruct` of a given point set.
    Reconstruct,
    /// `asperity generate dla-terrain`.
    DlaTerrain,
    /// `asperity generate rdsr-sphere`.
    RdsrSphere,
}

impl Job {
    /// The job's defaults, or the paper's when `paper`.
    pub fn defaults(self, paper: bool) -> Defaults {
        match (self, paper) {
            (Job::Reconstruct, false) => RECONSTRUCT,
            (Job::Reconstruct, true) => RECONSTRUCT_PAPER,
            (Job::DlaTerrain | Job::RdsrSphere, false) => PIPELINE,
            (Job::DlaTerrain | Job::RdsrSphere, true) => PIPELINE_PAPER,
        }
    }
}

/// The paper's particle count for a DLA terrain on a 64³ lattice: a deposit
/// about 20 cells high, which the paper's 49-node grid height implies.
pub const PAPER_TERRAIN_PARTICLES: usize = 2_500;

/// The points to reconstruct, with their unit normals when the file had them.
#[derive(Clone, Copy, Debug)]
pub struct Cloud<'a> {
    /// Positions.
    pub points: &'a [[f64; 3]],
    /// Normals, one per point.
    pub normals: Option<&'a [[f64; 3]]>,
}

impl<'a> From<&'a [[f64; 3]]> for Cloud<'a> {
    fn from(points: &'a [[f64; 3]]) -> Self {
        Self {
            points,
            normals: None,
        }
    }
}

/// A reconstruction and what it is worth against its points.
#[derive(Clone, Debug)]
pub struct Surface {
    /// The level set's result (its mesh trimmed with `open`, with the
    /// curvatures asked for).
    pub rec: Reconstruction,
    /// Distances to the points, holes, curvature scale.
    pub quality: quality::Quality,
}

/// Reconstructs a watertight surface from `points` with `params`; every
/// `save_every` steps (and at step 0) the current surface is handed to
/// `on_snapshot` with its step. (The jobs run [`reconstruct_job`], which also
/// measures the result against the points.)
///
/// # Errors
/// The pipeline's (parameters, memory budget); [`crate::EngineError::Invalid`]
/// for `save_every` = 0 or when the offset surface vanished.
pub fn surface(
    points: &[[f64; 3]],
    params: &ReconstructParams,
    save_every: Option<usize>,
    budgets: (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
    on_snapshot: &mut dyn FnMut(usize, TriMesh),
) -> Result<Reconstruction> {
    surface_of(
        points.into(),
        params,
        save_every,
        budgets,
        progress,
        on_snapshot,
    )
}

/// [`surface`] of a cloud with its normals.
fn surface_of(
    cloud: Cloud,
    params: &ReconstructParams,
    save_every: Option<usize>,
    (budget, time): (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
    on_snapshot: &mut dyn FnMut(usize, TriMesh),
) -> Result<Reconstruction> {
    if save_every == Some(0) {
        return Err(invalid("⟨save_every⟩ needs K ≥ 1"));
    }
    params.validate()?;
    let params = &ReconstructParams {
        snapshot_every: save_every.or(params.snapshot_every),
        ..*params
    };
    let points = cloud.points;
    let grid = asperity_levelset::pipeline::grid_for(points, params, budget)?;
    let iterations = params
        .iterations
        .max(params.surface_iterations.unwrap_or(0)) as f64;
    crate::estimate::check(
        time,
        &crate::estimate::level_set(grid.len() as f64, iterations),
    )?;
    if let Some(k) = save_every {
        crate::estimate::check_file_count(iterations as u64 / k as u64 + 1, "⟨save_every⟩")?;
    }
    let rec = reconstruct_cloud(
        points,
        cloud.normals,
        params,
        budget,
        progress,
        &mut |step, ls| {
            let Some(k) = save_every else { return };
            if !step.step.is_multiple_of(k) {
                return;
            }
            let (mesh, _) = ls.extract(&params.extract);
            if mesh.n_faces() > 0 {
                on_snapshot(step.step, mesh);
            }
        },
    )?;
    if rec.mesh.n_faces() == 0 {
        return Err(invalid(
            "the reconstruction is empty: the offset surface vanished (try a smaller ⟨offset⟩ or more points)",
        ));
    }
    Ok(rec)
}

/// The job: reconstructs `cloud` with the settings of `a` for `job`, then
/// measures it against the points and, as `a` asks, opens it and stores its
/// curvatures ([`quality::finish`]); every `a.save_every` steps (and at step
/// 0) the current surface is handed to `on_snapshot` with its step.
///
/// # Errors
/// As [`surface`].
pub fn reconstruct_job(
    cloud: Cloud,
    (a, job): (&LevelSetParams, Job),
    budgets: (&MemoryBudget, &TimeBudget),
    progress: &dyn Progress,
    on_snapshot: &mut dyn FnMut(usize, TriMesh),
) -> Result<Surface> {
    let params = a.settings(job);
    let mut rec = surface_of(cloud, &params, a.save_every, budgets, progress, on_snapshot)?;
    let h = rec.grid.spacing;
    let scale = a.curvature_scale.map(|s| s.0.world(h));
    if let Some(r) = scale.filter(|&r| a.curvature && r > quality::MAX_CURVATURE_CELLS * h) {
        return Err(invalid(format!(
            "⟨curvature_scale⟩ {r} is more than {} cells (h = {h}): each vertex's fit would take some {} of its neighbours",
            quality::MAX_CURVATURE_CELLS,
            (std::f64::consts::PI * (r / h).powi(2)).round()
        )));
    }
    let curvature = a.curvature.then_some(scale);
    // A deposit is closed by nature: `open` is for sampled surfaces.
    let open = a.open && rec.cloud.surface;
    let quality = quality::finish(&mut rec, (cloud.points, cloud.normals), open, curvature)?;
    if rec.mesh.n_faces() == 0 {
        return Err(invalid(
            "⟨open⟩ removed every triangle: no part of the surface lies within two sample spacings of the points",
        ));
    }
    Ok(Surface { rec, quality })
}

/// The mesh's counts and topology.
fn mesh_facts(r: &mut Measurements, rec: &Reconstruction, topology: &Topology) {
    let m = &rec.mesh;
    r.set("vertices", m.n_vertices());
    r.set("triangles", m.n_faces());
    r.set("euler_characteristic", topology.euler_characteristic);
    r.set("genus", topology.genus);
    r.set("watertight", topology.is_watertight());
    r.set("manifold", topology.is_manifold());
    r.set("components", rec.extraction.components);
    r.set("shells_removed", rec.extraction.shells_removed);
    r.set("pieces", pieces(rec));
    r.set("area", m.area());
    if topology.is_watertight() {
        r.set("volume", m.signed_volume());
    }
}

/// The measurements `asperity reconstruct --json` reports for `s` of `points`
/// points; `topology` is `s.rec.mesh.topology()`, computed once for these and
/// for [`summary`].
pub fn measurements(s: &Surface, points: usize, topology: &Topology) -> Measurements {
    let rec = &s.rec;
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
            "cloud": t.cloud,
            "distance": t.distance,
            "voids": t.voids,
            "tagging": t.tagging,
            "initial_surface": t.initial,
            "evolution": t.evolution,
            "marching_cubes": t.extraction,
            "total": t.total,
        }),
    );
    r.set("points", points);
    mesh_facts(&mut r, rec, topology);
    let steps = &rec.evolution.steps;
    r.set("iterations", steps.len());
    r.set("converged", rec.evolution.converged);
    let movement: Vec<f64> = steps.iter().map(|s| s.front_movement).collect();
    r.set("front_movement", movement);
    r.set("tagged_exterior", rec.tagged.0);
    r.set("tagging_refused", rec.tagged.1);
    r.set("distance_sweeps", rec.distance_sweeps);
    r.set("active_bricks", rec.bricks.0);
    r.set("grid_bricks", rec.bricks.1);
    r.set("flow", flow_name(rec.flow));
    let c = &rec.cloud;
    r.set(
        "cloud",
        json!({
            "kind": if c.surface { "surface" } else { "deposit" },
            "why": cloud_reason(c),
            "spacing": c.spacing,
            "flatness": c.flatness,
            "outliers_removed": c.outliers,
            "points_reconstructed": c.points,
            "denoise_moved": {"median": c.moved.0, "max": c.moved.1},
        }),
    );
    if let Some(v) = &rec.voids {
        r.set(
            "voids",
            json!({
                "count": v.count,
                "depth": v.depth,
                "widest_gap": v.widest_gap,
                "distance_cap": v.cap,
                "distance_tries": v.tries,
                "undecided": v.undecided,
                "thin_nodes_held": v.thin_nodes,
            }),
        );
    }
    r.set("quality", s.quality);
    if let Some(p) = &rec.projection {
        r.set(
            "projection",
            json!({"vertices_moved": p.moved, "median": p.shift.0, "max": p.shift.1}),
        );
    }
    r
}

/// The flow's CLI name.
pub fn flow_name(f: asperity_levelset::FlowChoice) -> &'static str {
    use asperity_levelset::FlowChoice as F;
    match f {
        F::Convection | F::Auto => "convection",
        F::Regularized { .. } => "regularized",
        F::Zhao => "zhao",
    }
}

/// Why the points were taken for what they were.
fn cloud_reason(c: &asperity_levelset::CloudFacts) -> String {
    match (c.measured, c.flatness) {
        (true, Some(f)) => format!(
            "measured: median surface variation {f:.3} of {} neighbours is {} {}",
            asperity_levelset::cloud::NEIGHBOURS,
            if c.surface { "below" } else { "at or above" },
            asperity_levelset::cloud::SURFACE_FLATNESS
        ),
        _ => "given".into(),
    }
}

/// Connected pieces of the mesh written (components less the shells removed).
/// (With `--open`, the holes' removal may split pieces; the topology reports them.)
pub fn pieces(rec: &Reconstruction) -> usize {
    rec.extraction.components - rec.extraction.shells_removed
}

/// One line: the cloud, grid, ε, δ, counts, topology (`s.rec.mesh.topology()`),
/// the distance to the points and stage times.
pub fn summary(s: &Surface, topology: &Topology) -> String {
    let rec = &s.rec;
    let (m, t, g) = (&rec.mesh, &rec.timings, &rec.grid);
    let q = &s.quality;
    let cloud = match (rec.cloud.surface, &rec.voids) {
        (true, Some(v)) => format!(
            "a sampled surface ({} outliers dropped; {} void(s), widest gap {:.3}; {} hole(s) closed, the largest {:.3} across), ",
            rec.cloud.outliers,
            v.count,
            2.0 * v.widest_gap,
            q.holes.count,
            2.0 * q.holes.largest_radius
        ),
        _ => "a deposit, ".into(),
    };
    format!(
        "{cloud}{} flow, vertices within {:.3} (mean {:.4}, {:.2}h) of the points; grid {}×{}×{} (h = {:.4}), ε = {:.3}, δ = {:.3}: {} vertices, {} triangles, χ = {}, {} piece(s), {}watertight; {:.2} s (distance {:.2}, tagging {:.2}, flow {:.2} for {} steps, marching cubes {:.2})",
        flow_name(rec.flow),
        q.distance_to_points.max,
        q.distance_to_points.mean,
        q.distance_to_points.in_h[0],
        g.dims[0],
        g.dims[1],
        g.dims[2],
        g.spacing,
        rec.offset,
        rec.point_radius,
        m.n_vertices(),
        m.n_faces(),
        topology.euler_characteristic,
        pieces(rec),
        if topology.is_watertight() { "" } else { "not " },
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

/// A DLA terrain's deposit (`generate dla-terrain`): a plane deposit of the
/// job's particles on its lattice (kim-machiraju-thompson Figs. 9–11). With
/// [`Sides::Walls`] the deposit is one connected set and its reconstruction one
/// piece; with periodic sides it is connected only across the wrap, which a
/// bounded reconstruction cuts (a warning says so).
///
/// # Errors
/// The parameters' and the simulator's (lattice, memory budget).
pub fn dla_terrain(
    p: &DlaTerrainParams,
    (seed, budget, time, progress): (u64, &MemoryBudget, &TimeBudget, &dyn Progress),
) -> Result<Grown> {
    crate::params::validate(p)?;
    let size = p.size.resolve(3)?;
    let particles = p.particle_count();
    let sides = p.sides;
    crate::estimate::check(time, &crate::estimate::dla(particles as f64))?;
    let params = DlaParams {
        dim: 3,
        size,
        particles,
        stick: p.stick,
        seed_shape: SeedShape::Plane,
        launch_gap: DlaParams::DEFAULT_LAUNCH_GAP,
        sides: sides.into(),
    };
    let cluster = dla(&params, seed, 0, budget, progress)?;
    let mut facts = Measurements::new();
    facts.set("particles", cluster.particles().len());
    facts.set("lattice", size);
    facts.set("reached_top_after", cluster.capped_at);
    // The same words as `growth dla` (#22: only that command said it).
    let capped = cluster.capped_at.map(|k| {
        format!(
            "the deposit reached the lattice top after {k} particles; later particles were released from the top layer (a taller ⟨size⟩ keeps the growth free)"
        )
    });
    let cut = (sides == Sides::Periodic).then(|| {
        "the deposit grew with periodic sides and is one cluster only across the wrap; the reconstruction is bounded, so the terrain falls into pieces at the sides (⟨sides=walls⟩ keeps it in one piece)".to_string()
    });
    facts.set("sides", sides);
    Ok(Grown {
        points: cluster.points(),
        facts,
        warnings: capped
            .into_iter()
            .chain(cluster.stopped)
            .chain(cut)
            .collect(),
    })
}

/// An RDSR sphere's deposit (`generate rdsr-sphere`): the job's monolayers
/// (with its relaxation radius) on a ball of its radius in cells
/// (kim-machiraju-thompson Fig. 8).
///
/// # Errors
/// The parameters' and the simulator's (memory budget).
pub fn rdsr_sphere(
    p: &RdsrSphereParams,
    (seed, budget, progress): (u64, &MemoryBudget, &dyn Progress),
) -> Result<Grown> {
    crate::params::validate(p)?;
    let params = CurvedParams {
        model: Model::Rdsr { radius: p.relax },
        substrate: CurvedSubstrate::Sphere(p.radius),
        layers: p.layers,
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
