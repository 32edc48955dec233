//! `asperity ca run|rule|gallery`, `asperity facet`, `asperity interpolate`:
//! peridier's cellular-automaton surfaces (`asperity_engine::ca`).

use std::time::Instant;

use asperity_engine::ca::{
    facets, gallery_image, render_with_curves, rule_measurements, run_job, step_image,
};
use asperity_engine::files::{load_height, load_xy};
use asperity_engine::methods::ca::facets::interpolate_many;
use asperity_engine::params::require;

use crate::cli::{CaCommand, CaGalleryArgs, CaRuleArgs, CaRunArgs, FacetArgs, InterpolateArgs};
use crate::context::{Context, Run};

pub fn run(ctx: &Context, c: CaCommand) -> anyhow::Result<()> {
    match c {
        CaCommand::Run(a) => ca_run(ctx, &a),
        CaCommand::Rule(a) => ca_rule(ctx, &a),
        CaCommand::Gallery(a) => ca_gallery(ctx, &a),
    }
}

fn ca_run(ctx: &Context, a: &CaRunArgs) -> anyhow::Result<()> {
    let out = ctx.output("heights.npy")?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let keep_states = a.states_out.is_some() || a.steps_png.is_some();
    let t = Instant::now();
    let r = run_job(
        &job.params,
        keep_states,
        job.seed,
        (&ctx.budget, &ctx.time),
        &ctx.bar(),
    )?;
    let seconds = t.elapsed().as_secs_f64();
    let (h, steps, k) = (&r.output.heights, r.job.steps, r.job.rule.states());
    let mut run = Run::new(ctx, "ca run");
    run.params(&job.params, job.seed, job.overridden);
    run.height(&out, h, r.title())?;
    let [nx, ny] = h.dims();
    if let (Some(st), Some(path)) = (&r.output.states, &a.states_out) {
        asperity_engine::io::write_npy_u8(path, &[steps + 1, ny, nx], st)?;
        run.report.output(path);
    }
    if let (Some(st), Some(dir)) = (&r.output.states, &a.steps_png) {
        asperity_engine::io::create_output_dir(dir)?;
        for (t, step) in st.chunks(nx * ny).enumerate() {
            run.png(
                &dir.join(format!("step_{t:03}.png")),
                &step_image(step, nx, ny, k),
            )?;
        }
    }
    run.measure(r.measurements());
    run.report.measure("seconds", seconds);
    run.report.measure(
        "cell_updates_per_second",
        (nx * ny * steps) as f64 / seconds.max(1e-12),
    );
    let (lo, hi) = h.min_max();
    run.note(format!(
        "wrote {} ({nx}×{ny}, heights {lo}…{hi}) in {seconds:.3} s",
        out.display()
    ));
    run.finish()
}

fn ca_rule(ctx: &Context, a: &CaRuleArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    asperity_engine::params::validate(&job.params)?;
    let r = job
        .params
        .family
        .rule(&require(&job.params.rule, "rule")?)?;
    if ctx.json {
        let mut run = Run::new(ctx, "ca rule");
        run.params(&job.params, job.seed, job.overridden);
        run.measure(rule_measurements(&r));
        return run.finish();
    }
    out!("{}", r.describe());
    Ok(())
}

fn ca_gallery(ctx: &Context, a: &CaGalleryArgs) -> anyhow::Result<()> {
    let out = ctx.output("grid.png")?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let p = &job.params;
    let img = gallery_image(p, job.seed, &ctx.budget, &ctx.time)?;
    let mut run = Run::new(ctx, "ca gallery");
    run.params(p, job.seed, job.overridden.clone());
    run.png(&out, &img)?;
    run.report.measure("rules", &p.rules);
    run.report.measure("inits", &p.inits);
    run.note(format!(
        "wrote {} ({} rules × {} initial conditions)",
        out.display(),
        p.rules.len(),
        p.inits.len()
    ));
    run.finish()
}

pub fn facet(ctx: &Context, a: &FacetArgs) -> anyhow::Result<()> {
    let out = ctx.output("mesh.ply")?;
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let h = load_height(&a.input, &ctx.budget)?;
    let polyline = a
        .polyline
        .as_deref()
        .map(|p| load_xy(p, &ctx.budget))
        .transpose()?;
    let (mesh, curves) = facets(&h, &job.params, polyline.as_deref())?;
    let mut run = Run::new(ctx, "facet");
    run.params(&job.params, job.seed, job.overridden.clone());
    if curves.is_empty() {
        run.mesh(&out, &mesh)?;
    } else {
        asperity_engine::io::write_mesh_with_polylines(&out, &mesh, &curves, &run.write_options())?;
        run.report.output(&out);
    }
    if let Some(png) = &a.render {
        run.png(
            png,
            &render_with_curves(&mesh, &curves, &job.params, &ctx.budget)?,
        )?;
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
        run.params(
            &asperity_engine::ca::InterpolateParams {},
            ctx.seed,
            Vec::new(),
        );
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
