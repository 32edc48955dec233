//! `asperity ca run|rule|gallery`, `asperity facet`, `asperity interpolate`:
//! peridier's cellular-automaton surfaces from the command line.

use std::path::Path;

use anyhow::{Context as _, bail};
use asperity_ca::facets::{circle, drape, facet_mesh, interpolate_many};
use asperity_ca::{
    Boundary, CaParams, Family, Init, Rule, Weights, evolve_and_accumulate, initial_grid,
};
use asperity_core::{Diagonal, Grid2, HeightField, RgbaImage};
use asperity_io::WriteOptions;
use asperity_render::font::draw_text;
use asperity_render::{Polyline, RenderOptions, Shader, render_mesh};

use crate::cli::{
    CaCommand, CaGalleryArgs, CaRuleArgs, CaRunArgs, Context, FacetArgs, InterpolateArgs, RuleArgs,
};
use crate::progress::Bar;
use crate::report::Report;

pub fn run(ctx: &Context, c: CaCommand) -> anyhow::Result<()> {
    match c {
        CaCommand::Run(a) => ca_run(ctx, &a),
        CaCommand::Rule(a) => ca_rule(ctx, &a),
        CaCommand::Gallery(a) => ca_gallery(ctx, &a),
    }
}

fn rule(args: &RuleArgs, text: &str) -> anyhow::Result<Rule> {
    let family = Family::from_name(&args.family).context("unknown family")?;
    Ok(Rule::parse(family, args.states, text)?)
}

/// `seed`, `random:DENSITY[@SEED]`, or a file: `.npy` states or an image thresholded at 0.5.
fn parse_init(ctx: &Context, text: &str, k: u8) -> anyhow::Result<Init> {
    if text == "seed" {
        return Ok(Init::Seed);
    }
    if let Some(r) = text.strip_prefix("random:") {
        let (d, s) = r.split_once('@').map_or((r, None), |(d, s)| (d, Some(s)));
        let density: f64 = d
            .parse()
            .with_context(|| format!("{d:?} is not a density in [0, 1]"))?;
        let seed = match s {
            Some(s) => s.parse().with_context(|| format!("{s:?} is not a seed"))?,
            None => ctx.seed,
        };
        return Ok(Init::Random { density, seed });
    }
    let path = Path::new(text);
    let h = asperity_io::read_height(path).with_context(|| {
        format!("initial grid {text:?} (use seed, random:DENSITY or a .npy/.png file)")
    })?;
    let is_image = path
        .extension()
        .is_some_and(|e| !e.eq_ignore_ascii_case("npy") && !e.eq_ignore_ascii_case("csv"));
    let mut states = Vec::with_capacity(h.len());
    for (n, &v) in h.data().iter().enumerate() {
        let s = if is_image {
            (v >= 0.5) as u8
        } else {
            if v.fract() != 0.0 || v < 0.0 || v >= k as f64 {
                bail!("{text}: value {v} at index {n} is not a state 0..{}", k - 1);
            }
            v as u8
        };
        states.push(s);
    }
    Ok(Init::Grid(Grid2::from_vec(h.dims(), states)?))
}

fn ca_run(ctx: &Context, a: &CaRunArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output file: give -o heights.npy")?;
    let rule = rule(&a.rule_args, &a.rule)?;
    let k = rule.states();
    let init = parse_init(ctx, &a.init, k)?;
    let size = a.size.map(|(w, h)| [w as usize, h as usize]);
    let boundary = match a.boundary.as_deref() {
        Some("infinite") => Boundary::Infinite,
        Some(_) => Boundary::Cyclic,
        None if matches!(init, Init::Seed) && size.is_none() => Boundary::Infinite,
        None => Boundary::Cyclic,
    };
    if boundary == Boundary::Infinite && size.is_some() && matches!(init, Init::Seed) {
        bail!(
            "--boundary infinite takes its region from the pattern; drop --size (or use --boundary cyclic)"
        );
    }
    let grid = initial_grid(&init, size, k, &ctx.budget)?;
    let params = CaParams {
        boundary,
        include_step0: !a.no_step0,
        weights: match (&a.weights, a.decay) {
            (Some(w), _) => Weights::Explicit(w.clone()),
            (None, Some(r)) => Weights::Geometric(r),
            (None, None) => Weights::Uniform,
        },
        values: a.values.clone(),
        keep_states: a.states_out.is_some() || a.steps_png.is_some(),
        ..CaParams::new(rule.clone(), a.steps)
    };
    let bar = Bar::new(ctx.quiet || ctx.json);
    let t = std::time::Instant::now();
    let result = evolve_and_accumulate(&grid, &params, &ctx.budget, &bar)?;
    let seconds = t.elapsed().as_secs_f64();
    let h = &result.heights;
    asperity_io::write_height(
        &out,
        h,
        &WriteOptions {
            title: format!("CA rule {}", rule.code()),
            ..WriteOptions::default()
        },
    )?;
    let mut report = Report::new("ca run", ctx);
    report.output(&out);
    let [nx, ny] = h.dims();
    if let (Some(st), Some(path)) = (&result.states, &a.states_out) {
        asperity_io::write_npy_u8(path, &[a.steps + 1, ny, nx], st)?;
        report.output(path);
    }
    if let (Some(st), Some(dir)) = (&result.states, &a.steps_png) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        for (t, step) in st.chunks(nx * ny).enumerate() {
            let path = dir.join(format!("step_{t:03}.png"));
            asperity_io::write_png(&path, &step_image(step, nx, ny, k))?;
            report.output(&path);
        }
    }
    let (lo, hi) = h.min_max();
    report.measure("rule", rule.code().to_string());
    report.measure("family", rule.family().name());
    report.measure("states", k);
    report.measure("table", rule.table());
    report.measure(
        "boundary",
        if boundary == Boundary::Cyclic {
            "cyclic"
        } else {
            "infinite"
        },
    );
    report.measure("size", [nx, ny]);
    report.measure("steps", a.steps);
    report.measure("height_range", [lo, hi]);
    report.measure("seconds", seconds);
    report.measure(
        "cell_updates_per_second",
        (nx * ny * a.steps) as f64 / seconds.max(1e-12),
    );
    ctx.note(format!(
        "wrote {} ({nx}×{ny}, heights {lo}…{hi}) in {seconds:.3} s",
        out.display()
    ));
    report.finish(ctx)
}

/// One step as a picture: state 1 black on white (the paper's Figure 3), k > 2 in
/// grey levels; small grids are enlarged so cells stay visible.
fn step_image(states: &[u8], nx: usize, ny: usize, k: u8) -> RgbaImage {
    let scale = (256 / nx.max(ny)).max(1) as u32;
    let mut img = RgbaImage::filled(nx as u32 * scale, ny as u32 * scale, [255, 255, 255, 255]);
    for (n, &s) in states.iter().enumerate() {
        let g = 255 - (s as u32 * 255 / (k as u32 - 1)) as u8;
        let (x, y) = ((n % nx) as u32 * scale, (n / nx) as u32 * scale);
        for dy in 0..scale {
            for dx in 0..scale {
                img.put(x + dx, y + dy, [g, g, g, 255]);
            }
        }
    }
    img
}

fn ca_rule(ctx: &Context, a: &CaRuleArgs) -> anyhow::Result<()> {
    let r = rule(&a.rule_args, &a.rule)?;
    if ctx.json {
        let mut report = Report::new("ca rule", ctx);
        report.measure("rule", r.code().to_string());
        report.measure("family", r.family().name());
        report.measure("states", r.states());
        report.measure("table", r.table());
        return report.finish(ctx);
    }
    out!("{}", r.describe());
    Ok(())
}

/// Facet mesh of a CA height field, rendered flat for the gallery. CA heights
/// count steps on a grid of unit spacing, so the view scales them to 15 % of the
/// grid's extent (the data are not changed).
pub fn render_facets(h: &HeightField, opts: &RenderOptions) -> anyhow::Result<RgbaImage> {
    let (lo, hi) = h.min_max();
    let e = h.extent();
    let f = if hi > lo {
        0.15 * e[0].max(e[1]) / (hi - lo)
    } else {
        1.0
    };
    let m = facet_mesh(&h.map(|z| z * f), true)?;
    Ok(render_mesh(
        &m,
        &RenderOptions {
            shader: Shader::Flat,
            ..opts.clone()
        },
    )?)
}

/// The Figure 4 grid: one row per rule, one column per initial condition.
pub fn gallery_image(ctx: &Context, a: &CaGalleryArgs) -> anyhow::Result<RgbaImage> {
    let (tw, th) = a.tile;
    let (rows, cols) = (a.rules.len() as u32, a.inits.len() as u32);
    anyhow::ensure!(
        rows > 0 && cols > 0,
        "need at least one rule and one initial condition"
    );
    let mut img = RgbaImage::filled(cols * tw, rows * th, [255, 255, 255, 255]);
    let size = [a.size.0 as usize, a.size.1 as usize];
    for (r, text) in a.rules.iter().enumerate() {
        let rule = rule(&a.rule_args, text)?;
        for (c, init) in a.inits.iter().enumerate() {
            let init = parse_init(ctx, init, rule.states())?;
            let grid = initial_grid(&init, Some(size), rule.states(), &ctx.budget)?;
            let out =
                asperity_ca::accumulate(&grid, &CaParams::new(rule.clone(), a.steps), &ctx.budget)?;
            let tile = render_facets(
                &out.heights,
                &RenderOptions {
                    width: tw,
                    height: th,
                    budget: ctx.budget,
                    ..RenderOptions::default()
                },
            )?;
            for y in 0..th {
                for x in 0..tw {
                    img.put(c as u32 * tw + x, r as u32 * th + y, tile.get(x, y));
                }
            }
            draw_text(
                &mut img,
                c as u32 * tw + 6,
                r as u32 * th + 6,
                &rule.code().to_string(),
                2,
                [30, 30, 30, 255],
            );
        }
    }
    Ok(img)
}

fn ca_gallery(ctx: &Context, a: &CaGalleryArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output image: give -o grid.png")?;
    let img = gallery_image(ctx, a)?;
    asperity_io::write_png(&out, &img)?;
    let mut report = Report::new("ca gallery", ctx);
    report.output(&out);
    report.measure("rules", &a.rules);
    report.measure("inits", &a.inits);
    ctx.note(format!(
        "wrote {} ({} rules × {} initial conditions)",
        out.display(),
        a.rules.len(),
        a.inits.len()
    ));
    report.finish(ctx)
}

/// x,y rows from a CSV (comma, semicolon or whitespace separated; `#` comments).
fn read_xy(path: &Path) -> anyhow::Result<Vec<[f64; 2]>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let mut pts = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let v: Vec<&str> = line
            .split([',', ';', ' ', '\t'])
            .filter(|s| !s.is_empty())
            .collect();
        let num = |k: usize| -> anyhow::Result<f64> {
            let s = v
                .get(k)
                .with_context(|| format!("{}:{}: need x,y", path.display(), n + 1))?;
            let x: f64 = s
                .parse()
                .with_context(|| format!("{}:{}: {s:?} is not a number", path.display(), n + 1))?;
            anyhow::ensure!(
                x.is_finite(),
                "{}:{}: {s:?} is not finite",
                path.display(),
                n + 1
            );
            Ok(x)
        };
        pts.push([num(0)?, num(1)?]);
    }
    Ok(pts)
}

pub fn facet(ctx: &Context, a: &FacetArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output mesh: give -o mesh.ply")?;
    let h = asperity_io::read_height(&a.input)?;
    let mesh = if a.smooth {
        h.to_trimesh(Diagonal::Forward)?
            .with_scalar("height", h.data().to_vec())?
    } else {
        facet_mesh(&h, !a.shared)?
    };
    let mut curves = Vec::new();
    if let Some(c) = &a.circle {
        anyhow::ensure!(
            c.len() == 3 && c.iter().all(|v| v.is_finite()),
            "--circle takes CX,CY,R, got {c:?}"
        );
        anyhow::ensure!(c[2] > 0.0, "circle radius must be positive");
        curves.push(drape(&h, &circle(c[0], c[1], c[2], 180))?);
    }
    if let Some(p) = &a.polyline {
        curves.push(drape(&h, &read_xy(p)?)?);
    }
    let mut report = Report::new("facet", ctx);
    if curves.is_empty() {
        asperity_io::write_mesh(&out, &mesh, &WriteOptions::default())?;
    } else {
        asperity_io::write_mesh_with_polylines(&out, &mesh, &curves, &WriteOptions::default())?;
    }
    report.output(&out);
    if let Some(png) = &a.render {
        let lines = curves
            .iter()
            .map(|c| Polyline {
                points: c.clone(),
                color: [220, 30, 30, 255],
                closed: false,
            })
            .collect();
        let img = render_mesh(
            &mesh,
            &RenderOptions {
                shader: if a.smooth || a.shared {
                    Shader::Phong
                } else {
                    Shader::Flat
                },
                polylines: lines,
                budget: ctx.budget,
                ..RenderOptions::default()
            },
        )?;
        asperity_io::write_png(png, &img)?;
        report.output(png);
    }
    report.measure("triangles", mesh.n_faces());
    report.measure("curve_points", curves.iter().map(Vec::len).sum::<usize>());
    ctx.note(format!(
        "wrote {} ({} facets)",
        out.display(),
        mesh.n_faces()
    ));
    report.finish(ctx)
}

pub fn interpolate(ctx: &Context, a: &InterpolateArgs) -> anyhow::Result<()> {
    let h = asperity_io::read_height(&a.input)?;
    let pts = read_xy(&a.points)?;
    let z = interpolate_many(&h, &pts);
    let outside = z.iter().filter(|v| v.is_none()).count();
    if ctx.json {
        let mut r = Report::new("interpolate", ctx);
        r.measure(
            "points",
            pts.iter()
                .zip(&z)
                .map(|(p, z)| [p[0], p[1], z.unwrap_or(f64::NAN)])
                .collect::<Vec<_>>(),
        );
        r.measure("outside", outside);
        return r.finish(ctx);
    }
    use std::io::Write;
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    for (p, z) in pts.iter().zip(&z) {
        match z {
            Some(z) => writeln!(w, "{},{},{}", p[0], p[1], z)?,
            None => writeln!(w, "{},{},nan", p[0], p[1])?,
        }
    }
    w.flush()?;
    if outside > 0 {
        ctx.note(format!(
            "warning: {outside} point(s) outside the height field (z = nan)"
        ));
    }
    Ok(())
}
