//! `asperity reconstruct` and the two-pass pipelines `asperity generate
//! dla-terrain` and `asperity generate rdsr-sphere` (kim-machiraju-thompson,
//! Fig. 2: growth, then level-set reconstruction).

use std::path::{Path, PathBuf};

use asperity_engine::files::{load_points, numbered, require_mesh_format};
use asperity_engine::reconstruct::{self, Grown, Job};
use asperity_levelset::{
    Band, DistanceMethod, ExtractOptions, FlowChoice, Neighbourhood, ReconstructParams, Scheme,
    Sizing, TagRule,
};

use crate::cli::{
    DistanceArg, DlaTerrainArgs, FlowArg, LevelSetArgs, RdsrSphereArgs, ReconstructArgs, SchemeArg,
    TagRuleArg, TubeNArg,
};
use crate::context::{Context, Run};

fn params(a: &LevelSetArgs, job: Job) -> ReconstructParams {
    let d = &job.defaults(a.paper);
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
            None => d.distance,
            Some(DistanceArg::ClosestPoint) => DistanceMethod::ClosestPoint,
            Some(DistanceArg::Godunov) => DistanceMethod::GODUNOV,
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
        flow: match a.flow {
            FlowArg::Convection => FlowChoice::Convection,
            FlowArg::Regularized => FlowChoice::Regularized {
                weight_cells: a.curvature_weight,
            },
            FlowArg::Zhao => FlowChoice::Zhao,
        },
        cfl: a.cfl,
        redistance_iterations: a.redistance,
        tolerance: a.tolerance,
        band: if a.full_grid {
            Band::Full
        } else {
            Band::Narrow
        },
        point_radius: a.point_radius.or(d.point_radius),
        extract: ExtractOptions {
            curvature: a.curvature,
            min_shell_triangles: a.min_shell,
        },
        snapshot_every: a.save_every,
        neighbourhood: match a.tube_n {
            None => d.neighbourhood,
            Some(TubeNArg::Axes) => Neighbourhood::Axes,
            Some(TubeNArg::Cube) => Neighbourhood::Cube,
        },
    }
}

fn mesh_output(ctx: &Context) -> anyhow::Result<PathBuf> {
    let out = ctx.output("MESH (e.g. -o surface.ply or -o surface.glb)")?;
    require_mesh_format(&out, ".ply, .obj, .stl or .glb")?;
    Ok(out)
}

/// Reconstructs, writes the mesh and the saved steps, and records it all.
fn surface(
    run: &mut Run,
    points: &[[f64; 3]],
    a: &LevelSetArgs,
    job: Job,
    out: &Path,
) -> anyhow::Result<()> {
    let p = params(a, job);
    // Saved steps are written as they come (a long run holds none in memory).
    let mut saved = Vec::new();
    let mut failed = None;
    let rec = reconstruct::surface(
        points,
        &p,
        a.save_every,
        (&run.ctx.budget, &run.ctx.time),
        &run.ctx.bar(),
        &mut |step, mesh| {
            let path = numbered(out, "step", step as u64, 4);
            if failed.is_none() {
                match asperity_io::write_mesh(&path, &mesh, &Default::default()) {
                    Ok(()) => saved.push(path),
                    Err(e) => failed = Some(e),
                }
            }
        },
    )?;
    if let Some(e) = failed {
        return Err(e.into());
    }
    run.mesh(out, &rec.mesh)?;
    for path in &saved {
        run.report.output(path);
    }
    run.measure(reconstruct::measurements(&rec, points.len()));
    run.note(reconstruct::summary(&rec));
    Ok(())
}

/// `asperity reconstruct POINTS -o MESH`
pub fn run(ctx: &Context, a: &ReconstructArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let points = load_points(&a.input, &ctx.budget)?;
    let mut run = Run::new(ctx, "reconstruct");
    surface(
        &mut run,
        points.positions(),
        &a.level_set,
        Job::Reconstruct,
        &out,
    )?;
    run.finish()
}

/// Writes what a pipeline grew, then reconstructs it.
fn pipeline(
    mut run: Run,
    grown: Grown,
    points_out: Option<&Path>,
    a: &LevelSetArgs,
    out: &Path,
    job: Job,
) -> anyhow::Result<()> {
    let title = match job {
        Job::DlaTerrain => "dla",
        _ => "rdsr",
    };
    for w in grown.warnings {
        run.warn("warning", w);
    }
    run.measure(grown.facts);
    if let Some(pp) = points_out {
        run.points(pp, grown.points.clone(), title)?;
    }
    surface(&mut run, &grown.points, a, job, out)?;
    run.finish()
}

/// `asperity generate dla-terrain`
pub fn dla_terrain(ctx: &Context, a: &DlaTerrainArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let size = crate::growth_cmd::parse_size(&a.size, 3)?;
    let run = Run::new(ctx, "generate dla-terrain");
    let grown = reconstruct::dla_terrain(
        size,
        a.particles
            .unwrap_or(reconstruct::terrain_particles(a.level_set.paper)),
        (a.stick, a.sides.into()),
        (ctx.seed, &ctx.budget, &ctx.time, &ctx.bar()),
    )?;
    pipeline(
        run,
        grown,
        a.points.as_deref(),
        &a.level_set,
        &out,
        Job::DlaTerrain,
    )
}

/// `asperity generate rdsr-sphere`
pub fn rdsr_sphere(ctx: &Context, a: &RdsrSphereArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let run = Run::new(ctx, "generate rdsr-sphere");
    let grown = reconstruct::rdsr_sphere(
        a.radius,
        a.layers,
        a.relax,
        (ctx.seed, &ctx.budget, &ctx.bar()),
    )?;
    pipeline(
        run,
        grown,
        a.points.as_deref(),
        &a.level_set,
        &out,
        Job::RdsrSphere,
    )
}
