//! `asperity ca run|rule|gallery`, `asperity facet`, `asperity interpolate`:
//! peridier's cellular-automaton surfaces (`asperity_engine::ca`).

use std::time::Instant;

use asperity_ca::facets::interpolate_many;
use asperity_ca::{Boundary, Weights};
use asperity_engine::ca::{
    FacetJob, GalleryGrid, RunJob, facets, gallery_image, parse_init, render_with_curves, rule,
    rule_measurements, run_measurements, step_image,
};
use asperity_engine::files::{load_height, load_xy};

use crate::cli::{
    CaCommand, CaGalleryArgs, CaRuleArgs, CaRunArgs, FacetArgs, InterpolateArgs, RuleArgs,
};
use crate::context::{Context, Run};

pub fn run(ctx: &Context, c: CaCommand) -> anyhow::Result<()> {
    match c {
        CaCommand::Run(a) => ca_run(ctx, &a),
        CaCommand::Rule(a) => ca_rule(ctx, &a),
        CaCommand::Gallery(a) => ca_gallery(ctx, &a),
    }
}

fn rule_of(a: &RuleArgs, text: &str) -> anyhow::Result<asperity_ca::Rule> {
    Ok(rule(&a.family, a.states, text)?)
}

fn ca_run(ctx: &Context, a: &CaRunArgs) -> anyhow::Result<()> {
    let out = ctx.output("heights.npy")?;
    let rule = rule_of(&a.rule_args, &a.rule)?;
    let k = rule.states();
    let job = RunJob {
        init: parse_init(&a.init, k, ctx.seed, &ctx.budget)?,
        rule,
        steps: a.steps,
        size: a.size.map(|(w, h)| [w as usize, h as usize]),
        boundary: a.boundary.as_deref().map(|b| match b {
            "infinite" => Boundary::Infinite,
            _ => Boundary::Cyclic,
        }),
        no_step0: a.no_step0,
        weights: match (&a.weights, a.decay) {
            (Some(w), _) => Weights::Explicit(w.clone()),
            (None, Some(r)) => Weights::Geometric(r),
            (None, None) => Weights::Uniform,
        },
        values: a.values.clone(),
        keep_states: a.states_out.is_some() || a.steps_png.is_some(),
    };
    let t = Instant::now();
    let (result, boundary) = asperity_engine::ca::run(&job, &ctx.budget, &ctx.time, &ctx.bar())?;
    let seconds = t.elapsed().as_secs_f64();
    let h = &result.heights;
    let mut run = Run::new(ctx, "ca run");
    run.height(&out, h, format!("CA rule {}", job.rule.code()))?;
    let [nx, ny] = h.dims();
    if let (Some(st), Some(path)) = (&result.states, &a.states_out) {
        asperity_io::write_npy_u8(path, &[a.steps + 1, ny, nx], st)?;
        run.report.output(path);
    }
    if let (Some(st), Some(dir)) = (&result.states, &a.steps_png) {
        asperity_io::create_output_dir(dir)?;
        for (t, step) in st.chunks(nx * ny).enumerate() {
            run.png(
                &dir.join(format!("step_{t:03}.png")),
                &step_image(step, nx, ny, k),
            )?;
        }
    }
    run.measure(run_measurements(&job, h, boundary));
    run.report.measure("seconds", seconds);
    run.report.measure(
        "cell_updates_per_second",
        (nx * ny * a.steps) as f64 / seconds.max(1e-12),
    );
    let (lo, hi) = h.min_max();
    run.note(format!(
        "wrote {} ({nx}×{ny}, heights {lo}…{hi}) in {seconds:.3} s",
        out.display()
    ));
    run.finish()
}

fn ca_rule(ctx: &Context, a: &CaRuleArgs) -> anyhow::Result<()> {
    let r = rule_of(&a.rule_args, &a.rule)?;
    if ctx.json {
        let mut run = Run::new(ctx, "ca rule");
        run.measure(rule_measurements(&r));
        return run.finish();
    }
    out!("{}", r.describe());
    Ok(())
}

fn ca_gallery(ctx: &Context, a: &CaGalleryArgs) -> anyhow::Result<()> {
    let out = ctx.output("grid.png")?;
    let grid = GalleryGrid {
        rules: a.rules.clone(),
        family: a.rule_args.family.clone(),
        states: a.rule_args.states,
        inits: a.inits.clone(),
        steps: a.steps,
        size: [a.size.0 as usize, a.size.1 as usize],
        tile: a.tile,
    };
    let img = gallery_image(&grid, ctx.seed, &ctx.budget, &ctx.time)?;
    let mut run = Run::new(ctx, "ca gallery");
    run.png(&out, &img)?;
    run.report.measure("rules", &a.rules);
    run.report.measure("inits", &a.inits);
    run.note(format!(
        "wrote {} ({} rules × {} initial conditions)",
        out.display(),
        a.rules.len(),
        a.inits.len()
    ));
    run.finish()
}

pub fn facet(ctx: &Context, a: &FacetArgs) -> anyhow::Result<()> {
    let out = ctx.output("mesh.ply")?;
    let h = load_height(&a.input, &ctx.budget)?;
    let circle = match a.circle.as_deref() {
        None => None,
        Some([x, y, r]) => Some([*x, *y, *r]),
        Some(c) => anyhow::bail!("--circle takes CX,CY,R, got {c:?}"),
    };
    let job = FacetJob {
        smooth: a.smooth,
        shared: a.shared,
        circle,
        polyline: a
            .polyline
            .as_deref()
            .map(|p| load_xy(p, &ctx.budget))
            .transpose()?,
    };
    let (mesh, curves) = facets(&h, &job)?;
    let mut run = Run::new(ctx, "facet");
    if curves.is_empty() {
        run.mesh(&out, &mesh)?;
    } else {
        asperity_io::write_mesh_with_polylines(&out, &mesh, &curves, &ctx.write_options())?;
        run.report.output(&out);
    }
    if let Some(png) = &a.render {
        run.png(png, &render_with_curves(&mesh, &curves, &job, &ctx.budget)?)?;
    }
    run.report.measure("triangles", mesh.n_faces());
    run.report
        .measure("curve_points", curves.iter().map(Vec::len).sum::<usize>());
    run.note(format!(
        "wrote {} ({} facets)",
        out.display(),
        mesh.n_faces()
    ));
    run.finish()
}

pub fn interpolate(ctx: &Context, a: &InterpolateArgs) -> anyhow::Result<()> {
    let h = load_height(&a.input, &ctx.budget)?;
    let pts = load_xy(&a.points, &ctx.budget)?;
    let z = interpolate_many(&h, &pts);
    let outside = z.iter().filter(|v| v.is_none()).count();
    if ctx.json {
        let mut run = Run::new(ctx, "interpolate");
        let rows: Vec<[f64; 3]> = pts
            .iter()
            .zip(&z)
            .map(|(p, z)| [p[0], p[1], z.unwrap_or(f64::NAN)])
            .collect();
        run.report.measure("points", rows);
        run.report.measure("outside", outside);
        return run.finish();
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
