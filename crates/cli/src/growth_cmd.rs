//! `asperity growth rd|rdsr|bd|dla`: the growth jobs of `asperity_engine::growth`.

use asperity_engine::files::{is_points_path, load_height};
use asperity_engine::growth::deposition::width_csv;
use asperity_engine::growth::dla::{self, SeedInputs, SeedShape};
use asperity_engine::growth::{self, DepositJob, Deposited, SubstrateShape};
use asperity_engine::io::Format;

use crate::cli::{DepositArgs, DlaArgs, GrowthCommand};
use crate::context::{Context, Run};

pub fn run(ctx: &Context, c: GrowthCommand) -> anyhow::Result<()> {
    match c {
        GrowthCommand::Rd(a) => deposit(ctx, &a),
        GrowthCommand::Rdsr(a) => deposit(ctx, &a),
        GrowthCommand::Bd(a) => deposit(ctx, &a),
        GrowthCommand::Dla(a) => grow_dla(ctx, &a),
    }
}

const OUTPUT: &str = "FILE (e.g. -o h.npy or -o points.ply)";

fn deposit<P: DepositJob + clap::Args>(ctx: &Context, a: &DepositArgs<P>) -> anyhow::Result<()> {
    let out = ctx.output(OUTPUT)?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let d = job.params.deposit();
    let points_out = is_points_path(&out)?;
    anyhow::ensure!(
        d.substrate == SubstrateShape::Flat || points_out,
        "a curved deposit is a point set: give -o with .ply, .xyz or .csv"
    );
    let mesh = match (&a.mesh, d.substrate) {
        (Some(path), SubstrateShape::Mesh) => Some(ctx.load_triangles(path)?),
        _ => None,
    };
    let keep_points = a.points.is_some() || points_out;
    let mut run = Run::new(ctx, "growth");
    let r = growth::deposit(
        &job.params,
        mesh,
        keep_points,
        job.seed,
        (&ctx.budget, &ctx.time),
        &ctx.bar(),
    )?;
    run.params(&job.params, job.seed, job.overridden);
    let name = job.params.model().name();
    match &r {
        Deposited::Curved(..) => run.points(&out, r.points().positions().to_vec(), name)?,
        Deposited::Flat(..) if points_out => {
            run.points(&out, r.points().positions().to_vec(), name)?
        }
        Deposited::Flat(_, flat) if d.dim == 1 && Format::from_path(&out)? == Format::Npy => {
            let h: Vec<f64> = flat.deposit.heights.iter().map(|&v| v as f64).collect();
            asperity_engine::io::write_npy_f64(&out, &[d.size], &h)?;
            run.report.output(&out);
        }
        Deposited::Flat(_, flat) => run.height(&out, &flat.deposit.height_field(), r.title())?,
    }
    if let (Some(pp), Deposited::Flat(..)) = (&a.points, &r) {
        run.points(pp, r.points().positions().to_vec(), name)?;
    }
    if let Some(c) = &a.width_csv {
        run.text(c, &width_csv(r.series()))?;
    }
    if let Some(dir) = &a.plot {
        run.plots(dir, &r.plots(), (800, 560))?;
    }
    run.measure(r.measurements());
    run.note(r.summary());
    run.finish()
}

fn grow_dla(ctx: &Context, a: &DlaArgs) -> anyhow::Result<()> {
    let out = ctx.output(OUTPUT)?;
    anyhow::ensure!(
        is_points_path(&out)?,
        "a DLA cluster is a point set: give -o with .ply, .xyz or .csv"
    );
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let p = &job.params;
    let inputs = SeedInputs {
        mesh: match (&a.mesh, p.seed_shape) {
            (Some(path), SeedShape::Mesh) => Some(ctx.load_triangles(path)?),
            _ => None,
        },
        image: match (&a.image, p.seed_shape) {
            (Some(path), SeedShape::Image) => Some(load_height(path, &ctx.budget)?),
            _ => None,
        },
        walkers: a.walkers,
    };
    let mut run = Run::new(ctx, "growth dla");
    let r = dla::grow(p, inputs, job.seed, &ctx.budget, &ctx.time, &ctx.bar())?;
    run.params(&r.resolved, job.seed, job.overridden);
    for (kind, msg) in r.warnings() {
        run.warn(kind, msg);
    }
    run.points(&out, r.world_points(), "dla")?;
    if let Some(dir) = &a.plot {
        run.plots(dir, &r.plots(), (800, 560))?;
    }
    run.measure(r.measurements());
    run.note(r.summary());
    run.finish()
}
