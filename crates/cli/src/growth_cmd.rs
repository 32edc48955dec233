//! `asperity growth rd|rdsr|bd|dla`: the growth simulators of asperity-growth,
//! with the measurements of asperity-analysis.

use std::path::Path;

use anyhow::Context as _;
use asperity_analysis::scaling::{
    self, GrowthFit, density_dimension, density_profile, growth_exponent,
    growth_exponent_intrinsic, gyration_dimension, mass_radius_dimension, radius_of_gyration,
};
use asperity_core::{PointSet, TriMesh, voxelize::voxelize};
use asperity_growth::curved::{self, CurvedParams, CurvedSubstrate, deposit_curved};
use asperity_growth::deposition::deposit_on_schedule;
use asperity_growth::dla::{DlaParams, SeedShape, auto_size, dla};
use asperity_growth::interface_width::uniform_schedule;
use asperity_growth::{DepositionParams, Lattice, Model, WidthSeries, deposit_ensemble};
use asperity_io::{Format, WriteOptions};
use asperity_render::plot::{Plot, Series, Style, plot_png, plot_svg};
use rayon::prelude::*;
use serde_json::json;

use crate::cli::{Context, DepositArgs, DlaArgs, GrowthCommand, SeedShapeArg, SubstrateArg};
use crate::progress::Bar;
use crate::report::Report;

pub fn run(ctx: &Context, c: GrowthCommand) -> anyhow::Result<()> {
    match c {
        GrowthCommand::Rd(a) => deposit_cmd(ctx, Model::Rd, &a),
        GrowthCommand::Rdsr(a) => deposit_cmd(ctx, Model::Rdsr { radius: a.relax }, &a),
        GrowthCommand::Bd(a) => deposit_cmd(ctx, Model::Bd, &a),
        GrowthCommand::Dla(a) => dla_cmd(ctx, &a),
    }
}

fn output(ctx: &Context) -> anyhow::Result<std::path::PathBuf> {
    ctx.output
        .clone()
        .context("no output file: give -o FILE (e.g. -o h.npy or -o points.ply)")
}

/// Whether `path` names a point-set format rather than a height field.
fn is_points_path(path: &Path) -> anyhow::Result<bool> {
    let f = Format::from_path(path)?;
    Ok(matches!(f, Format::Ply | Format::Xyz | Format::Csv))
}

fn fit_json(f: &Result<GrowthFit, asperity_analysis::AnalysisError>) -> serde_json::Value {
    match f {
        Ok(f) => json!({
            "exponent": f.exponent,
            "intrinsic_width": f.intrinsic_width,
            "fit_window": f.fit.range,
            "r2": f.fit.r2,
            "points": f.fit.points,
        }),
        Err(e) => json!({"error": e.to_string()}),
    }
}

pub(crate) fn write_points(path: &Path, pts: Vec<[f64; 3]>, title: &str) -> anyhow::Result<()> {
    anyhow::ensure!(!pts.is_empty(), "no particle to write");
    asperity_io::write_points(
        path,
        &PointSet::new(pts),
        &WriteOptions {
            title: title.into(),
            ..WriteOptions::default()
        },
    )?;
    Ok(())
}

fn width_csv(path: &Path, s: &WidthSeries) -> anyhow::Result<()> {
    let mut text = String::from("t,w,w_binned,w2_stderr,mean_height\n");
    for k in 0..s.t.len() {
        let wb = s
            .w2_binned
            .get(k)
            .map_or(String::new(), |v| v.sqrt().to_string());
        text += &format!(
            "{},{},{},{},{}\n",
            s.t[k],
            s.w2[k].sqrt(),
            wb,
            s.w2_stderr[k],
            s.mean_height[k]
        );
    }
    asperity_io::write_text(path, &text)?;
    Ok(())
}

/// Writes `plot` as `name` (SVG, scalable) and as the same name with `.png`.
fn write_svg(dir: &Path, name: &str, plot: &Plot, report: &mut Report) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let path = dir.join(name);
    asperity_io::write_text(&path, &plot_svg(plot, 800, 560)?)?;
    report.output(&path);
    let png = path.with_extension("png");
    asperity_io::write_png(&png, &plot_png(plot, 800, 560)?)?;
    report.output(&png);
    Ok(())
}

/// A fit line y = e^c x^slope over the fit window, for plots.
fn fit_line(name: String, f: &asperity_analysis::psd::LogFit) -> Series {
    let (range, intercept, slope) = (f.range, f.intercept, f.slope);
    let pts = (0..=20)
        .map(|k| {
            let x = range[0] * (range[1] / range[0]).powf(k as f64 / 20.0);
            (x, (intercept + slope * x.ln()).exp())
        })
        .collect();
    Series {
        name,
        points: pts,
        style: Style::Fit,
    }
}

fn width_plot(
    title: &str,
    s: &WidthSeries,
    fit: &Option<GrowthFit>,
    binned: &Option<GrowthFit>,
) -> Plot {
    let mut series = vec![Series {
        name: "W(t)".into(),
        points: s.t.iter().copied().zip(s.width()).collect(),
        style: Style::Points,
    }];
    if let Some(f) = fit {
        series.push(fit_line(format!("β = {:.3}", f.exponent), &f.fit));
    }
    if !s.w2_binned.is_empty() {
        series.push(Series {
            name: "W binned".into(),
            points: s.t.iter().copied().zip(s.width_binned()).collect(),
            style: Style::Points,
        });
        if let Some(f) = binned {
            series.push(fit_line(format!("binned β = {:.3}", f.exponent), &f.fit));
        }
    }
    Plot {
        title: title.into(),
        x_label: "t (monolayers)".into(),
        y_label: "interface width W".into(),
        log_x: true,
        log_y: true,
        series,
    }
}

fn deposit_cmd(ctx: &Context, model: Model, a: &DepositArgs) -> anyhow::Result<()> {
    let out = output(ctx)?;
    let mut report = Report::new("growth", ctx);
    report.measure("model", model.name());
    let bar = Bar::new(ctx.quiet || ctx.json);
    anyhow::ensure!(a.runs >= 1, "--runs must be at least 1");
    if a.substrate != SubstrateArg::Flat {
        return curved_cmd(ctx, model, a, &out, report, &bar);
    }
    let lattice = Lattice::new(a.size, a.dim as usize)?;
    let mut p = DepositionParams::new(model, lattice, a.layers);
    p.bin = a.bin;
    p.samples_per_decade = a.samples_per_decade.max(1);
    let wants_points = a.points.is_some() || is_points_path(&out)?;
    p.keep_particles = wants_points && model == Model::Bd;
    if wants_points {
        // Positions (24 bytes) plus the writer's buffer, per particle.
        ctx.budget.check_elements(
            p.depositions() as u128,
            48,
            "the point set of every deposited particle",
        )?;
    }
    let (d, series) = deposit_ensemble(&p, ctx.seed, a.runs, &ctx.budget, &bar)?;
    let window = match &a.fit_window {
        Some(w) => {
            anyhow::ensure!(
                w.len() == 2 && w[0] > 0.0 && w[1] > w[0],
                "--fit-window takes TMIN,TMAX with 0 < TMIN < TMAX, got {w:?}"
            );
            [w[0], w[1]]
        }
        None if a.layers >= 100.0 => [10.0, a.layers],
        None => [1.0, a.layers],
    };
    let plain = growth_exponent(&series.t, &series.width(), window);
    let intrinsic = growth_exponent_intrinsic(&series.t, &series.width(), window);
    let binned = (!series.w2_binned.is_empty())
        .then(|| growth_exponent(&series.t, &series.width_binned(), window));
    // Outputs.
    if is_points_path(&out)? {
        write_points(&out, d.point_set().positions().to_vec(), model.name())?;
    } else if a.dim == 1 && Format::from_path(&out)? == Format::Npy {
        let h: Vec<f64> = d.heights.iter().map(|&v| v as f64).collect();
        asperity_io::write_npy_f64(&out, &[a.size], &h)?;
    } else {
        asperity_io::write_height(
            &out,
            &d.height_field(),
            &WriteOptions {
                title: format!("{} L={} T={}", model.name(), a.size, a.layers),
                ..WriteOptions::default()
            },
        )?;
    }
    report.output(&out);
    if let Some(pp) = &a.points {
        write_points(pp, d.point_set().positions().to_vec(), model.name())?;
        report.output(pp);
    }
    if let Some(c) = &a.width_csv {
        width_csv(c, &series)?;
        report.output(c);
    }
    let alpha = match &a.alpha_sizes {
        Some(sizes) => Some(alpha_study(ctx, model, a, sizes)?),
        None => None,
    };
    if let Some(dir) = &a.plot {
        let plot = width_plot(
            &format!(
                "{} {}+1D, L = {}, {} runs",
                model.name().to_uppercase(),
                a.dim,
                a.size,
                a.runs
            ),
            &series,
            &plain.as_ref().ok().copied(),
            &binned.as_ref().and_then(|b| b.as_ref().ok().copied()),
        );
        write_svg(dir, "width.svg", &plot, &mut report)?;
        if let Some((sizes, wsat, fit)) = &alpha {
            let plot = Plot {
                title: format!("saturated width, α = {:.3}", fit.slope),
                x_label: "L".into(),
                y_label: "W_sat".into(),
                log_x: true,
                log_y: true,
                series: vec![
                    Series {
                        name: "W_sat(L)".into(),
                        points: sizes
                            .iter()
                            .map(|&l| l as f64)
                            .zip(wsat.iter().copied())
                            .collect(),
                        style: Style::Points,
                    },
                    fit_line(format!("α = {:.3}", fit.slope), fit),
                ],
            };
            write_svg(dir, "saturation.svg", &plot, &mut report)?;
        }
    }
    let beta_plain = plain.as_ref().ok().map(|f| f.exponent);
    report.measure("lattice", json!({"L": a.size, "d": a.dim}));
    report.measure("layers", a.layers);
    report.measure("runs", a.runs);
    report.measure("depositions_per_run", d.depositions);
    report.measure("mean_height", series.mean_height.last());
    report.measure("width", series.w2.last().map(|v| v.sqrt()));
    report.measure(
        "width_series",
        series
            .t
            .iter()
            .zip(series.width())
            .map(|(t, w)| json!({"t": t, "w": w}))
            .collect::<Vec<_>>(),
    );
    if !series.w2_binned.is_empty() {
        report.measure("width_binned_series", series.width_binned());
    }
    report.measure("beta", beta_plain);
    report.measure(
        "fits",
        json!({
            "plain": fit_json(&plain),
            "intrinsic_width": fit_json(&intrinsic),
            "binned": binned.as_ref().map(fit_json),
        }),
    );
    if let Some((sizes, wsat, fit)) = &alpha {
        report.measure(
            "alpha",
            json!({"exponent": fit.slope, "r2": fit.r2, "sizes": sizes, "saturated_width": wsat}),
        );
    }
    ctx.note(format!(
        "{}: L = {} ({}+1D), T = {} monolayers, {} run(s): W = {:.4}, β = {}{}",
        model.name(),
        a.size,
        a.dim,
        a.layers,
        a.runs,
        series.w2.last().map_or(0.0, |v| v.sqrt()),
        beta_plain.map_or("n/a".into(), |b| format!("{b:.4}")),
        alpha
            .as_ref()
            .map_or(String::new(), |x| format!(", α = {:.4}", x.2.slope)),
    ));
    report.finish(ctx)
}

/// Saturated widths for several sizes: each run to 2·L^z monolayers and W²
/// averaged over the last three quarters, over --runs runs.
fn alpha_study(
    ctx: &Context,
    model: Model,
    a: &DepositArgs,
    sizes: &[usize],
) -> anyhow::Result<(Vec<usize>, Vec<f64>, asperity_analysis::psd::LogFit)> {
    anyhow::ensure!(
        model != Model::Rd,
        "random deposition never saturates: α is undefined for rd"
    );
    anyhow::ensure!(sizes.len() >= 3, "--alpha-sizes needs at least 3 sizes");
    let z = match (model, a.dim) {
        (Model::Bd, 1) => 1.5,
        (Model::Bd, _) => 1.62,
        _ => 2.0,
    };
    let jobs: Vec<(usize, u64)> = sizes
        .iter()
        .flat_map(|&l| (0..a.runs as u64).map(move |r| (l, r)))
        .collect();
    for &l in sizes {
        Lattice::new(l, a.dim as usize)?;
    }
    let w2: Vec<f64> = jobs
        .par_iter()
        .map(|&(l, r)| {
            let lat = Lattice::new(l, a.dim as usize).expect("checked");
            let layers = (2.0 * (l as f64).powf(z)).ceil();
            let p = DepositionParams::new(model, lat, layers);
            let n = lat.columns() as u64;
            let total = p.depositions();
            let sched = uniform_schedule(total / 4 / n * n, total, 64);
            let d = deposit_on_schedule(&p, ctx.seed, 1000 + r, &sched, &asperity_core::NoProgress);
            d.series.w2.iter().sum::<f64>() / d.series.w2.len() as f64
        })
        .collect();
    let wsat: Vec<f64> = sizes
        .iter()
        .enumerate()
        .map(|(k, _)| (w2[k * a.runs..(k + 1) * a.runs].iter().sum::<f64>() / a.runs as f64).sqrt())
        .collect();
    let fit =
        scaling::roughness_exponent(&sizes.iter().map(|&l| l as f64).collect::<Vec<_>>(), &wsat)?;
    Ok((sizes.to_vec(), wsat, fit))
}

/// Maps lattice cells back to the input's coordinates.
type ToWorld = Box<dyn Fn([i32; 3]) -> [f64; 3]>;

fn curved_cmd(
    ctx: &Context,
    model: Model,
    a: &DepositArgs,
    out: &Path,
    mut report: Report,
    bar: &Bar,
) -> anyhow::Result<()> {
    anyhow::ensure!(
        is_points_path(out)?,
        "a curved deposit is a point set: give -o with .ply, .xyz or .csv"
    );
    // Mesh substrates come back in the mesh's own coordinates.
    let (substrate, to_world): (CurvedSubstrate, ToWorld) = match a.substrate {
        SubstrateArg::Sphere => (
            CurvedSubstrate::Sphere(a.radius),
            Box::new(|c| c.map(f64::from)),
        ),
        SubstrateArg::Mesh => {
            let path = a
                .mesh
                .as_ref()
                .context("--substrate mesh needs --mesh FILE")?;
            let mesh = asperity_io::read_mesh(path)?;
            let m = curved::margin(model, a.layers);
            let vox = voxelize(&mesh, a.resolution, m, &ctx.budget)
                .with_context(|| format!("voxelising {}", path.display()))?;
            let (o, h) = (vox.origin, vox.spacing);
            let lattice_mesh = TriMesh::new(
                mesh.positions()
                    .iter()
                    .map(|p| [0, 1, 2].map(|k| (p[k] - o[k]) / h))
                    .collect(),
                mesh.triangles().to_vec(),
            )?;
            let cells = vox.cells();
            (
                CurvedSubstrate::Mesh {
                    mesh: lattice_mesh,
                    size: vox.dims,
                    cells,
                },
                Box::new(move |c: [i32; 3]| [0, 1, 2].map(|k| o[k] + c[k] as f64 * h)),
            )
        }
        SubstrateArg::Flat => unreachable!("handled by the caller"),
    };
    let params = CurvedParams {
        model,
        substrate,
        layers: a.layers,
        samples_per_decade: a.samples_per_decade.max(1),
    };
    let d = deposit_curved(&params, ctx.seed, 0, &ctx.budget, bar)?;
    write_points(
        out,
        d.cells.iter().map(|&c| to_world(c)).collect(),
        model.name(),
    )?;
    report.output(out);
    if let Some(c) = &a.width_csv {
        width_csv(c, &d.series)?;
        report.output(c);
    }
    let window = [1.0, a.layers.max(1.0)];
    let plain = growth_exponent(&d.series.t, &d.series.width(), window);
    if let Some(dir) = &a.plot {
        let plot = width_plot(
            &format!(
                "{} on a {:?} substrate",
                model.name().to_uppercase(),
                a.substrate
            )
            .to_lowercase(),
            &d.series,
            &plain.as_ref().ok().copied(),
            &None,
        );
        write_svg(dir, "width.svg", &plot, &mut report)?;
    }
    report.measure("substrate", format!("{:?}", a.substrate).to_lowercase());
    report.measure("lattice", d.size);
    report.measure("substrate_cells", d.seeds);
    report.measure("particles", d.cells.len() - d.seeds);
    report.measure("thickness", d.thickness);
    report.measure(
        "width_series",
        d.series
            .t
            .iter()
            .zip(d.series.width())
            .map(|(t, w)| json!({"t": t, "w": w}))
            .collect::<Vec<_>>(),
    );
    report.measure("beta", plain.as_ref().ok().map(|f| f.exponent));
    ctx.note(format!(
        "{} on a {:?} substrate: {} particles on {} surface cells, thickness {:.1} cells, W = {:.3}",
        model.name(),
        a.substrate,
        d.cells.len() - d.seeds,
        d.seeds,
        d.thickness,
        d.series.w2.last().map_or(0.0, |v| v.sqrt())
    ));
    report.finish(ctx)
}

/// Parses NXxNYxNZ (or NXxNZ in 2-D) into a lattice size.
pub(crate) fn parse_size(text: &str, dim: usize) -> anyhow::Result<[usize; 3]> {
    let parts: Vec<usize> = text
        .split(['x', 'X', '×'])
        .map(|s| s.trim().parse::<usize>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--size {text:?}: expected NXxNYxNZ (or NXxNZ in 2-D)"))?;
    match (dim, parts.as_slice()) {
        (3, [x, y, z]) => Ok([*x, *y, *z]),
        (3, [n]) => Ok([*n; 3]),
        (2, [x, z]) => Ok([*x, 1, *z]),
        (2, [n]) => Ok([*n, 1, *n]),
        _ => anyhow::bail!("--size {text:?}: expected {} numbers separated by x", dim),
    }
}

fn dla_cmd(ctx: &Context, a: &DlaArgs) -> anyhow::Result<()> {
    let out = output(ctx)?;
    anyhow::ensure!(
        is_points_path(&out)?,
        "a DLA cluster is a point set: give -o with .ply, .xyz or .csv"
    );
    let dim = a.dim as usize;
    let plane = matches!(a.seed_shape, SeedShapeArg::Plane | SeedShapeArg::Image);
    let size = match &a.size {
        Some(s) => parse_size(s, dim)?,
        None if plane => {
            if dim == 3 {
                [128, 128, 128]
            } else {
                [512, 1, 512]
            }
        }
        None => {
            let mut s = auto_size(dim, a.particles, a.stick);
            if a.seed_shape == SeedShapeArg::Sphere {
                let extra = (2.0 * a.seed_radius).ceil() as usize / 4 * 4 + 4;
                s = s.map(|v| if v > 1 { v + extra } else { v });
            }
            if a.seed_shape == SeedShapeArg::Mesh {
                s = s.map(|v| {
                    if v > 1 {
                        v + a.resolution / 4 * 4 + 4
                    } else {
                        v
                    }
                });
            }
            s
        }
    };
    let mut world: Option<([f64; 3], f64)> = None;
    let seed_shape = match a.seed_shape {
        SeedShapeArg::Point => SeedShape::Point,
        SeedShapeArg::Plane => SeedShape::Plane,
        SeedShapeArg::Sphere => SeedShape::Sphere(a.seed_radius),
        SeedShapeArg::Mesh => {
            anyhow::ensure!(dim == 3, "a mesh seed needs --dim 3");
            let path = a
                .mesh
                .as_ref()
                .context("--seed-shape mesh needs --mesh FILE")?;
            let mesh = asperity_io::read_mesh(path)?;
            let vox = voxelize(&mesh, a.resolution, 0, &ctx.budget)
                .with_context(|| format!("voxelising {}", path.display()))?;
            // Centre the solid in the lattice.
            let shift = [0, 1, 2].map(|k| ((size[k] as i64 - vox.dims[k] as i64) / 2) as i32);
            anyhow::ensure!(
                shift.iter().all(|&s| s >= 2),
                "the voxelised mesh ({:?} cells) does not fit the {}x{}x{} lattice; raise --size or lower --resolution",
                vox.dims,
                size[0],
                size[1],
                size[2]
            );
            world = Some((
                [0, 1, 2].map(|k| vox.origin[k] - shift[k] as f64 * vox.spacing),
                vox.spacing,
            ));
            SeedShape::Cells(
                vox.cells()
                    .into_iter()
                    .map(|c| [c[0] + shift[0], c[1] + shift[1], c[2] + shift[2]])
                    .collect(),
            )
        }
        SeedShapeArg::Image => {
            let path = a
                .image
                .as_ref()
                .context("--seed-shape image needs --image FILE")?;
            anyhow::ensure!(
                a.seed_density > 0.0 && a.seed_density <= 1.0,
                "--seed-density must be in (0, 1], got {}",
                a.seed_density
            );
            let img = asperity_io::read_height(path)?;
            let (lo, hi) = img.min_max();
            let [iw, ih] = img.dims();
            let mut d = Vec::with_capacity(size[0] * size[1]);
            for y in 0..size[1] {
                for x in 0..size[0] {
                    // Nearest pixel; image row 0 is the top, lattice y = 0 the bottom.
                    let i = (x * iw / size[0]).min(iw - 1);
                    let j = ih - 1 - (y * ih / size[1]).min(ih - 1);
                    let v = *img.get(i, j);
                    let g = if hi > lo { (v - lo) / (hi - lo) } else { 1.0 };
                    d.push(a.seed_density * g);
                }
            }
            SeedShape::Density(d)
        }
    };
    let params = DlaParams {
        dim,
        size,
        particles: a.particles,
        stick: a.stick,
        seed_shape,
        launch_gap: a.launch_gap,
    };
    let mut report = Report::new("growth dla", ctx);
    let bar = Bar::new(ctx.quiet || ctx.json);
    let c = dla(&params, ctx.seed, 0, &ctx.budget, &bar)?;
    if let Some(k) = c.capped_at {
        let why = format!(
            "the deposit reached the lattice top after {k} particles; later particles were released from the top layer"
        );
        ctx.note(format!("note: {why}"));
        report.warnings.push(why);
    }
    if let Some(why) = &c.stopped {
        ctx.note(format!("warning: {why}"));
        report.warnings.push(why.clone());
    }
    let to_world = |p: &[i32; 3]| match world {
        Some((o, h)) => [0, 1, 2].map(|k| o[k] + p[k] as f64 * h),
        None => p.map(f64::from),
    };
    write_points(&out, c.cells.iter().map(to_world).collect(), "dla")?;
    report.output(&out);
    let parts: Vec<[f64; 3]> = c.particles().iter().map(|p| p.map(f64::from)).collect();
    let all = c.points();
    let rg = if parts.is_empty() {
        0.0
    } else {
        radius_of_gyration(&parts)
    };
    let (dimension, method, extra) = if plane {
        let area = (size[0] * size[1]) as f64;
        let rho = density_profile(&parts, area);
        let dd = density_dimension(&rho, dim);
        (
            dd.as_ref().ok().map(|d| d.d),
            "density profile rho(z) ~ z^(D-d)",
            json!({"density_profile": rho, "fit": dd.as_ref().ok().map(|d| d.fit)}),
        )
    } else {
        // A point seed starts the deposition order; solid seeds are left out.
        let cluster = if c.seeds == 1 { &all } else { &parts };
        let g = gyration_dimension(cluster);
        let m = mass_radius_dimension(cluster, 2.0);
        (
            g.as_ref().ok().map(|d| d.d),
            "radius of gyration R_g(n) ~ n^(1/D)",
            json!({
                "gyration_fit": g.as_ref().ok().map(|d| d.fit),
                "mass_radius": m.as_ref().ok().map(|d| json!({"D": d.d, "fit": d.fit})),
            }),
        )
    };
    if let Some(dir) = &a.plot {
        let ns: Vec<usize> = (6..)
            .map(|k| 1usize << k)
            .take_while(|&n| n <= all.len())
            .collect();
        let plot = Plot {
            title: format!(
                "DLA radius of gyration, D = {}",
                dimension.map_or("n/a".into(), |d| format!("{d:.3}"))
            ),
            x_label: "particles n".into(),
            y_label: "R_g".into(),
            log_x: true,
            log_y: true,
            series: vec![Series {
                name: "R_g(n)".into(),
                points: ns
                    .iter()
                    .map(|&n| (n as f64, radius_of_gyration(&all[..n])))
                    .collect(),
                style: Style::Points,
            }],
        };
        write_svg(dir, "gyration.svg", &plot, &mut report)?;
        if plane {
            let rho = density_profile(&parts, (size[0] * size[1]) as f64);
            let plot = Plot {
                title: "DLA deposit density profile".into(),
                x_label: "height z".into(),
                y_label: "density".into(),
                log_x: true,
                log_y: true,
                series: vec![Series {
                    name: "ρ(z)".into(),
                    points: rho
                        .iter()
                        .enumerate()
                        .map(|(z, r)| (z as f64, *r))
                        .collect(),
                    style: Style::Points,
                }],
            };
            write_svg(dir, "density.svg", &plot, &mut report)?;
        }
    }
    report.measure("seed_shape", params.seed_shape.name());
    report.measure("dim", dim);
    report.measure("lattice", size);
    report.measure("stick", a.stick);
    report.measure("particles", c.particles().len());
    report.measure("seeds", c.seeds);
    report.measure("radius_of_gyration", rg);
    report.measure("fractal_dimension", dimension);
    report.measure("fractal_dimension_method", method);
    report.measure("dimension_details", extra);
    report.measure("walk", c.stats);
    report.measure("stopped_early", &c.stopped);
    ctx.note(format!(
        "DLA ({}D, {} seed, p = {}): {} particles, R_g = {:.2}, D = {}",
        dim,
        params.seed_shape.name(),
        a.stick,
        c.particles().len(),
        rg,
        dimension.map_or("n/a".into(), |d| format!("{d:.3}"))
    ));
    report.finish(ctx)
}
