//! `asperity growth rd|rdsr|bd|dla`: the growth jobs of `asperity_engine::growth`.

use std::path::Path;

use asperity_engine::files::{is_points_path, load_height};
use asperity_engine::growth::curved::{self, CurvedJob, Substrate};
use asperity_engine::growth::deposition::{self, DepositionJob, width_csv};
use asperity_engine::growth::dla::{self, SeedInputs, SeedShape};
use asperity_growth::Model;
use asperity_io::Format;

use crate::cli::{DepositArgs, DlaArgs, GrowthCommand, SubstrateArg};
use crate::context::{Context, Run};

pub fn run(ctx: &Context, c: GrowthCommand) -> anyhow::Result<()> {
    match c {
        GrowthCommand::Rd(a) => deposit(ctx, Model::Rd, &a),
        GrowthCommand::Rdsr(a) => deposit(ctx, Model::Rdsr { radius: a.relax }, &a),
        GrowthCommand::Bd(a) => deposit(ctx, Model::Bd, &a),
        GrowthCommand::Dla(a) => grow_dla(ctx, &a),
    }
}

const OUTPUT: &str = "FILE (e.g. -o h.npy or -o points.ply)";

fn deposit(ctx: &Context, model: Model, a: &DepositArgs) -> anyhow::Result<()> {
    let out = ctx.output(OUTPUT)?;
    anyhow::ensure!(a.runs >= 1, "--runs must be at least 1");
    if a.substrate != SubstrateArg::Flat {
        return deposit_curved(ctx, model, a, &out);
    }
    let job = DepositionJob {
        model,
        size: a.size,
        dim: a.dim as usize,
        layers: a.layers,
        runs: a.runs,
        bin: a.bin,
        samples_per_decade: a.samples_per_decade,
        fit_window: fit_window(&a.fit_window)?,
        alpha_sizes: a.alpha_sizes.clone(),
        keep_points: a.points.is_some() || is_points_path(&out)?,
    };
    let mut run = Run::new(ctx, "growth");
    let r = deposition::deposit(&job, ctx.seed, &ctx.budget, &ctx.time, &ctx.bar())?;
    let name = model.name();
    if is_points_path(&out)? {
        run.points(&out, r.deposit.point_set().positions().to_vec(), name)?;
    } else if a.dim == 1 && Format::from_path(&out)? == Format::Npy {
        let h: Vec<f64> = r.deposit.heights.iter().map(|&v| v as f64).collect();
        asperity_io::write_npy_f64(&out, &[a.size], &h)?;
        run.report.output(&out);
    } else {
        run.height(&out, &r.deposit.height_field(), job.title())?;
    }
    if let Some(pp) = &a.points {
        run.points(pp, r.deposit.point_set().positions().to_vec(), name)?;
    }
    if let Some(c) = &a.width_csv {
        run.text(c, &width_csv(&r.series))?;
    }
    if let Some(dir) = &a.plot {
        run.plots(dir, &r.plots(&job), (800, 560))?;
    }
    run.measure(r.measurements(&job));
    run.note(r.summary(&job));
    run.finish()
}

fn fit_window(w: &Option<Vec<f64>>) -> anyhow::Result<Option<[f64; 2]>> {
    match w.as_deref() {
        None => Ok(None),
        Some([a, b]) => Ok(Some([*a, *b])),
        Some(w) => anyhow::bail!("--fit-window takes TMIN,TMAX with 0 < TMIN < TMAX, got {w:?}"),
    }
}

fn deposit_curved(ctx: &Context, model: Model, a: &DepositArgs, out: &Path) -> anyhow::Result<()> {
    anyhow::ensure!(
        is_points_path(out)?,
        "a curved deposit is a point set: give -o with .ply, .xyz or .csv"
    );
    let substrate = match a.substrate {
        SubstrateArg::Mesh => {
            let path = a
                .mesh
                .as_ref()
                .ok_or_else(|| anyhow::anyhow!("--substrate mesh needs --mesh FILE"))?;
            Substrate::Mesh {
                mesh: ctx.load_triangles(path)?,
                resolution: a.resolution,
            }
        }
        _ => Substrate::Sphere(a.radius),
    };
    let job = CurvedJob {
        model,
        substrate,
        layers: a.layers,
        samples_per_decade: a.samples_per_decade,
    };
    let mut run = Run::new(ctx, "growth");
    let r = curved::deposit(&job, ctx.seed, &ctx.budget, &ctx.bar())?;
    run.points(out, r.world_points(), model.name())?;
    if let Some(c) = &a.width_csv {
        run.text(c, &width_csv(&r.deposit.series))?;
    }
    if let Some(dir) = &a.plot {
        run.plots(dir, &r.plots(&job), (800, 560))?;
    }
    run.measure(r.measurements(&job));
    run.note(r.summary(&job));
    run.finish()
}

/// Parses NXxNYxNZ (or NXxNZ in 2-D) into a lattice size.
pub fn parse_size(text: &str, dim: usize) -> anyhow::Result<[usize; 3]> {
    let parts: Vec<usize> = text
        .split(['x', 'X', '×'])
        .map(|s| s.trim().parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| anyhow::anyhow!("--size {text:?}: expected NXxNYxNZ (or NXxNZ in 2-D)"))?;
    match (dim, parts.as_slice()) {
        (3, [x, y, z]) => Ok([*x, *y, *z]),
        (3, [n]) => Ok([*n; 3]),
        (2, [x, z]) => Ok([*x, 1, *z]),
        (2, [n]) => Ok([*n, 1, *n]),
        _ => anyhow::bail!("--size {text:?}: expected {} numbers separated by x", dim),
    }
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
