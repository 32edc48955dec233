//! `asperity reconstruct` and the two-pass pipelines `asperity generate
//! dla-terrain` and `asperity generate rdsr-sphere` (kim-machiraju-thompson,
//! Fig. 2: growth, then level-set reconstruction).

use std::path::{Path, PathBuf};

use asperity_engine::files::{numbered, require_mesh_format};
use asperity_engine::reconstruct::{self, Grown, Job, LevelSetOptions};
use asperity_levelset::{
    DistanceMethod, FlowChoice, Neighbourhood, ReconstructParams, Scheme, TagRule,
};

use crate::cli::{
    DistanceArg, DlaTerrainArgs, FlowArg, LevelSetArgs, RdsrSphereArgs, ReconstructArgs, SchemeArg,
    TagRuleArg, TubeNArg,
};
use crate::context::{Context, Run};

fn params(a: &LevelSetArgs, job: Job) -> ReconstructParams {
    LevelSetOptions {
        paper: a.paper,
        resolution: a.resolution,
        spacing: a.spacing,
        offset: a.offset,
        iterations: a.iterations,
        tolerance: a.tolerance,
        point_radius: a.point_radius,
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
        distance: a.distance.map(|d| match d {
            DistanceArg::ClosestPoint => DistanceMethod::ClosestPoint,
            DistanceArg::Godunov => DistanceMethod::GODUNOV,
        }),
        neighbourhood: a.tube_n.map(|n| match n {
            TubeNArg::Axes => Neighbourhood::Axes,
            TubeNArg::Cube => Neighbourhood::Cube,
        }),
        tag_rule: match a.tagging {
            TagRuleArg::Paper => TagRule::Paper,
            TagRuleArg::Threshold => TagRule::Threshold,
        },
        tube_cells: a.tube,
        beta_cells: a.beta,
        cfl: a.cfl,
        redistance_iterations: a.redistance,
        full_grid: a.full_grid,
        curvature: a.curvature,
        min_shell_triangles: a.min_shell,
        save_every: a.save_every,
    }
    .params(job)
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
    let _purge = crate::memory::PromptPurge::new();
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
                match asperity_io::write_mesh(&path, &mesh, &run.ctx.write_options()) {
                    Ok(()) => saved.push(path),
                    Err(e) => failed = Some(e),
                }
            }
        },
    )?;
    if let Some(e) = failed {
        return Err(e.into());
    }
    // The topology (for the report) is read while the file is written: the
    // writer waits on the kernel much of the time, the topology keeps the
    // cores busy meanwhile.
    let (written, topology) = std::thread::scope(|s| {
        let topology = s.spawn(|| rec.mesh.topology());
        let written = run.mesh(out, &rec.mesh);
        let topology = topology
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (written, topology)
    });
    written?;
    for path in &saved {
        run.report.output(path);
    }
    run.measure(reconstruct::measurements(&rec, points.len(), &topology));
    run.note(reconstruct::summary(&rec, &topology));
    Ok(())
}

/// `asperity reconstruct POINTS -o MESH`
pub fn run(ctx: &Context, a: &ReconstructArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    // From the reading on: the reader's buffers go back before the stages
    // allocate theirs.
    let _purge = crate::memory::PromptPurge::new();
    let points = ctx.load_points(&a.input)?;
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
