//! `asperity reconstruct` and the two-pass pipelines `asperity generate
//! dla-terrain` and `asperity generate rdsr-sphere` (kim-machiraju-thompson,
//! Fig. 2: growth, then level-set reconstruction).

use std::path::{Path, PathBuf};

use asperity_engine::files::{numbered, require_mesh_format};
use asperity_engine::reconstruct::{self, Grown, Job, LevelSetParams};

use crate::cli::{DlaTerrainArgs, RdsrSphereArgs, ReconstructArgs};
use crate::context::{Context, Run};

fn mesh_output(ctx: &Context) -> anyhow::Result<PathBuf> {
    let out = ctx.output("MESH (e.g. -o surface.ply or -o surface.glb)")?;
    require_mesh_format(&out, ".ply, .obj, .stl or .glb")?;
    Ok(out)
}

/// Reconstructs, writes the mesh and the saved steps, and records it all.
fn surface(
    run: &mut Run,
    cloud: reconstruct::Cloud,
    a: &LevelSetParams,
    job: Job,
    out: &Path,
) -> anyhow::Result<()> {
    let _purge = crate::memory::PurgeDelay::prompt();
    // Saved steps are written as they come (a long run holds none in memory).
    let mut saved = Vec::new();
    let mut failed = None;
    let surf = reconstruct::reconstruct_job(
        cloud,
        (a, job),
        (&run.ctx.budget, &run.ctx.time),
        &run.ctx.bar(),
        &mut |step, mesh| {
            let path = numbered(out, "step", step as u64, 4);
            if failed.is_none() {
                match asperity_engine::io::write_mesh(&path, &mesh, &run.write_options()) {
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
        let topology = s.spawn(|| surf.rec.mesh.topology());
        let written = run.mesh(out, &surf.rec.mesh);
        let topology = topology
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (written, topology)
    });
    written?;
    for path in &saved {
        run.report.output(path);
    }
    run.measure(reconstruct::measurements(
        &surf,
        cloud.points.len(),
        &topology,
    ));
    run.note(reconstruct::summary(&surf, &topology));
    Ok(())
}

/// `asperity reconstruct POINTS -o MESH`
pub fn run(ctx: &Context, a: &ReconstructArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    asperity_engine::params::validate(&job.params)?;
    // From the reading on: the reader's buffers go back before the stages
    // allocate theirs.
    let _purge = crate::memory::PurgeDelay::prompt();
    let points = ctx.load_points(&a.input)?;
    let mut run = Run::new(ctx, "reconstruct");
    run.params(
        &job.params.resolved(Job::Reconstruct),
        job.seed,
        job.overridden,
    );
    let cloud = reconstruct::Cloud {
        points: points.positions(),
        normals: points.normals(),
    };
    surface(&mut run, cloud, &job.params, Job::Reconstruct, &out)?;
    run.finish()
}

/// Writes what a pipeline grew, then reconstructs it.
fn pipeline(
    mut run: Run,
    grown: Grown,
    points_out: Option<&Path>,
    a: &LevelSetParams,
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
    surface(&mut run, grown.points.as_slice().into(), a, job, out)?;
    run.finish()
}

/// `asperity generate dla-terrain`
pub fn dla_terrain(ctx: &Context, a: &DlaTerrainArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let mut run = Run::new(ctx, "generate dla-terrain");
    let grown =
        reconstruct::dla_terrain(&job.params, (job.seed, &ctx.budget, &ctx.time, &ctx.bar()))?;
    run.params(&job.params.resolved()?, job.seed, job.overridden);
    pipeline(
        run,
        grown,
        a.points.as_deref(),
        &job.params.level_set,
        &out,
        Job::DlaTerrain,
    )
}

/// `asperity generate rdsr-sphere`
pub fn rdsr_sphere(ctx: &Context, a: &RdsrSphereArgs) -> anyhow::Result<()> {
    let out = mesh_output(ctx)?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let mut run = Run::new(ctx, "generate rdsr-sphere");
    let grown = reconstruct::rdsr_sphere(&job.params, (job.seed, &ctx.budget, &ctx.bar()))?;
    run.params(&job.params.resolved(), job.seed, job.overridden);
    pipeline(
        run,
        grown,
        a.points.as_deref(),
        &job.params.level_set,
        &out,
        Job::RdsrSphere,
    )
}
