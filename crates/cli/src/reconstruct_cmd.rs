//! `asperity reconstruct` and the two-pass pipelines `asperity generate dla-terrain`
//! and `asperity generate rdsr-sphere` (kim-machiraju-thompson, Fig. 2: growth, then
//! level-set reconstruction).

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use asperity_core::TriMesh;
use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_growth::deposition::Model;
use asperity_growth::dla::{DlaParams, SeedShape, dla};
use asperity_io::{Format, WriteOptions};
use asperity_levelset::{
    Band, DistanceMethod, ExtractOptions, ReconstructParams, Reconstruction, Scheme, Sizing,
    TagRule, extract, reconstruct,
};
use serde_json::json;

use crate::cli::{
    Context, DistanceArg, DlaTerrainArgs, FlowArg, LevelSetArgs, RdsrSphereArgs, ReconstructArgs,
    SchemeArg, TagRuleArg,
};
use crate::growth_cmd::write_points;
use crate::progress::Bar;
use crate::report::Report;

/// What a command uses when the user gives no sizing, offset or step count.
struct Defaults {
    sizing: Sizing,
    offset: Option<f64>,
    iterations: usize,
}

fn params(a: &LevelSetArgs, d: &Defaults) -> ReconstructParams {
    let sizing = match (a.resolution, a.spacing) {
        (Some(n), _) => Sizing::Resolution(n),
        (None, Some(h)) => Sizing::Spacing(h),
        (None, None) => d.sizing,
    };
    ReconstructParams {
        sizing,
        offset: a.offset.or(d.offset),
        tube_cells: a.tube,
        beta_cells: a.beta,
        distance: match a.distance {
            DistanceArg::ClosestPoint => DistanceMethod::ClosestPoint,
            DistanceArg::Godunov => DistanceMethod::GODUNOV,
        },
        tag_rule: match a.tagging {
            TagRuleArg::Paper => TagRule::Paper,
            TagRuleArg::Threshold => TagRule::Threshold,
        },
        iterations: a.iterations.unwrap_or(d.iterations),
        scheme: match a.scheme {
            SchemeArg::Eno2 => Scheme::Eno2,
            SchemeArg::Upwind => Scheme::Upwind,
        },
        curvature_weight: match a.flow {
            FlowArg::Convection => None,
            FlowArg::Regularized => Some(a.curvature_weight),
        },
        cfl: a.cfl,
        redistance_iterations: a.redistance,
        tolerance: a.tolerance,
        band: if a.full_grid {
            Band::Full
        } else {
            Band::Narrow
        },
        point_radius: a.point_radius,
        extract: ExtractOptions {
            curvature: a.curvature,
            min_shell_triangles: a.min_shell,
        },
        snapshot_every: a.save_every,
    }
}

fn mesh_output(ctx: &Context) -> anyhow::Result<PathBuf> {
    let out = ctx
        .output
        .clone()
        .context("no output file: give -o MESH (e.g. -o surface.ply or -o surface.glb)")?;
    let f = Format::from_path(&out)?;
    anyhow::ensure!(
        f.info().mesh.can_write(),
        "{} cannot hold a triangle mesh; use .ply, .obj, .stl or .glb",
        out.display()
    );
    Ok(out)
}

/// `dir/stem_stepNNNN.ext` next to `out`.
fn step_path(out: &Path, step: usize) -> PathBuf {
    let stem = out
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("surface");
    let ext = out.extension().and_then(|s| s.to_str()).unwrap_or("ply");
    out.with_file_name(format!("{stem}_step{step:04}.{ext}"))
}

fn write_mesh(path: &Path, mesh: &TriMesh) -> anyhow::Result<()> {
    asperity_io::write_mesh(path, mesh, &WriteOptions::default())
        .with_context(|| format!("writing {}", path.display()))
}

/// Runs the reconstruction, writes the mesh (and the intermediate surfaces), and
/// records everything in the report.
#[allow(clippy::too_many_arguments)] // one call site per command; the arguments are its whole state
fn reconstruct_and_write(
    ctx: &Context,
    points: &[[f64; 3]],
    a: &LevelSetArgs,
    p: &ReconstructParams,
    out: &Path,
    report: &mut Report,
    bar: &Bar,
) -> anyhow::Result<Reconstruction> {
    if let Some(k) = a.save_every {
        anyhow::ensure!(k > 0, "--save-every needs K ≥ 1");
    }
    let mut saved: Vec<PathBuf> = Vec::new();
    let mut save_error: Option<anyhow::Error> = None;
    let rec = reconstruct(points, p, &ctx.budget, bar, &mut |step, ls| {
        let Some(k) = a.save_every else { return };
        if save_error.is_some() || !step.step.is_multiple_of(k) {
            return;
        }
        let (mesh, _) = extract(&ls.phi, &ls.grid, &p.extract);
        if mesh.n_faces() == 0 {
            return;
        }
        let path = step_path(out, step.step);
        match write_mesh(&path, &mesh) {
            Ok(()) => saved.push(path),
            Err(e) => save_error = Some(e),
        }
    })?;
    if let Some(e) = save_error {
        return Err(e);
    }
    anyhow::ensure!(
        rec.mesh.n_faces() > 0,
        "the reconstruction is empty: the offset surface vanished (try a smaller --offset or more points)"
    );
    write_mesh(out, &rec.mesh)?;
    report.output(out);
    for s in &saved {
        report.output(s);
    }
    let m = &rec.mesh;
    let t = &rec.timings;
    report.measure("grid", rec.grid.dims);
    report.measure("spacing", rec.grid.spacing);
    report.measure("origin", rec.grid.origin);
    report.measure("offset", rec.offset);
    report.measure("point_radius", rec.point_radius);
    report.measure("sample_spacing", rec.sample_spacing);
    report.measure(
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
    report.measure("points", points.len());
    report.measure("vertices", m.n_vertices());
    report.measure("triangles", m.n_faces());
    report.measure("euler_characteristic", m.euler_characteristic());
    report.measure("genus", m.genus());
    report.measure("watertight", m.is_watertight());
    report.measure("manifold", m.is_manifold());
    report.measure("components", rec.extraction.components);
    report.measure("shells_removed", rec.extraction.shells_removed);
    report.measure("area", m.area());
    if m.is_watertight() {
        report.measure("volume", m.signed_volume());
    }
    report.measure("iterations", rec.evolution.steps.len());
    report.measure("converged", rec.evolution.converged);
    report.measure(
        "front_movement",
        rec.evolution
            .steps
            .iter()
            .map(|s| s.front_movement)
            .collect::<Vec<_>>(),
    );
    report.measure("tagged_exterior", rec.tagged.0);
    report.measure("tagging_refused", rec.tagged.1);
    report.measure("distance_sweeps", rec.distance_sweeps);
    ctx.note(format!(
        "grid {}×{}×{} (h = {:.4}), ε = {:.3}, δ = {:.3}: {} vertices, {} triangles, χ = {}, {} piece(s), {}watertight; {:.2} s (distance {:.2}, tagging {:.2}, flow {:.2} for {} steps, marching cubes {:.2})",
        rec.grid.dims[0],
        rec.grid.dims[1],
        rec.grid.dims[2],
        rec.grid.spacing,
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
    ));
    Ok(rec)
}

/// `asperity reconstruct POINTS -o MESH`
pub fn run(ctx: &Context, a: &ReconstructArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let points = asperity_io::read_points(&a.input)
        .with_context(|| format!("reading points from {}", a.input.display()))?;
    let mut report = Report::new("reconstruct", ctx);
    let bar = Bar::new(ctx.quiet || ctx.json);
    let p = params(
        &a.level_set,
        &Defaults {
            sizing: Sizing::Resolution(128),
            offset: None,
            iterations: 30,
        },
    );
    reconstruct_and_write(
        ctx,
        points.positions(),
        &a.level_set,
        &p,
        &out,
        &mut report,
        &bar,
    )?;
    report.finish(ctx)
}

/// The pipelines' defaults: the paper's ε = 3 lattice units, h = 0.7 (a 64-cell
/// lattice gives about the paper's 115-node grid with its padding), 60 steps.
const PIPELINE: Defaults = Defaults {
    sizing: Sizing::Spacing(0.7),
    offset: Some(3.0),
    iterations: 60,
};

/// `asperity generate dla-terrain`
pub fn dla_terrain(ctx: &Context, a: &DlaTerrainArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let size = crate::growth_cmd::parse_size(&a.size, 3)?;
    let mut report = Report::new("generate dla-terrain", ctx);
    let bar = Bar::new(ctx.quiet || ctx.json);
    let params_dla = DlaParams {
        dim: 3,
        size,
        particles: a.particles,
        stick: a.stick,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
    };
    let cluster = dla(&params_dla, ctx.seed, 0, &ctx.budget, &bar)?;
    if let Some(why) = &cluster.stopped {
        ctx.note(format!("warning: {why}"));
        report.warnings.push(why.clone());
    }
    let pts = cluster.points();
    report.measure("particles", cluster.particles().len());
    report.measure("lattice", size);
    if let Some(pp) = &a.points {
        write_points(pp, pts.clone(), "dla")?;
        report.output(pp);
    }
    let p = params(&a.level_set, &PIPELINE);
    reconstruct_and_write(ctx, &pts, &a.level_set, &p, &out, &mut report, &bar)?;
    report.finish(ctx)
}

/// `asperity generate rdsr-sphere`
pub fn rdsr_sphere(ctx: &Context, a: &RdsrSphereArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let mut report = Report::new("generate rdsr-sphere", ctx);
    let bar = Bar::new(ctx.quiet || ctx.json);
    let params_growth = CurvedParams {
        model: Model::Rdsr { radius: a.relax },
        substrate: CurvedSubstrate::Sphere(a.radius),
        layers: a.layers,
        samples_per_decade: 10,
    };
    let deposit = deposit_curved(&params_growth, ctx.seed, 0, &ctx.budget, &bar)?;
    let pts = deposit.points();
    report.measure("particles", pts.len() - deposit.seeds);
    report.measure("thickness", deposit.thickness);
    if let Some(pp) = &a.points {
        write_points(pp, pts.clone(), "rdsr")?;
        report.output(pp);
    }
    let p = params(&a.level_set, &PIPELINE);
    reconstruct_and_write(ctx, &pts, &a.level_set, &p, &out, &mut report, &bar)?;
    report.finish(ctx)
}
