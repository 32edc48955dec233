//! `asperity surface-ca`: cellular automata on a triangle mesh (gobron-chiba;
//! `asperity_engine::surfca`).

use std::path::PathBuf;

use asperity_engine::files::{numbered, require_mesh_format};
use asperity_engine::io::Format;
use asperity_engine::surfca::{AppRun, SurfaceCaInputs, run_job};

use crate::cli::SurfaceCaArgs;
use crate::context::{Context, Run};

/// The statistics file (`.json` or CSV) and plot, when asked for.
fn statistics(run: &mut Run, a: &SurfaceCaArgs, r: &AppRun, n: usize) -> anyhow::Result<()> {
    if let Some(path) = &a.stats_out {
        let text = if path.extension().and_then(|e| e.to_str()) == Some("json") {
            r.stats_json(n)
        } else {
            r.stats_csv(n)
        };
        run.text(path, &text)?;
    }
    if let Some(path) = &a.plot {
        let img = asperity_engine::methods::render::plot::plot_png(&r.stats_plot(n), 900, 600)?;
        run.png(path, &img)?;
    }
    Ok(())
}

pub fn run(ctx: &Context, a: &SurfaceCaArgs) -> anyhow::Result<()> {
    // The parameters first, as every command checks them.
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let out = ctx.output("FILE (e.g. -o voronoi.glb)")?;
    require_mesh_format(&out, ".glb, .ply or .obj")?;
    let p = &job.params;
    let mut run = Run::new(ctx, "surface-ca");
    run.params(p, job.seed, job.overridden.clone());
    let inputs = SurfaceCaInputs {
        mesh: ctx.load_mesh(&a.mesh)?,
        name: a.mesh.clone(),
        at: match &a.site_points {
            Some(path) => Some((ctx.load_points(path)?, path.display().to_string())),
            None => None,
        },
    };
    let steps = match p.app {
        asperity_engine::surfca::AppName::Voronoi => p.max_steps,
        _ => p.steps,
    };
    if let Some(k) = a.frames {
        asperity_engine::estimate::check_file_count(steps / k + 1, "⟨frames⟩")?;
    }
    // Animation frames are written as the run goes.
    let (mut frames, mut failed): (Vec<PathBuf>, _) = (Vec::new(), None);
    let frame_options = run.write_options();
    let (cov, r) = run_job(
        p,
        inputs,
        job.seed,
        (&ctx.budget, &ctx.time),
        &ctx.bar(),
        |cov, step, color| {
            let Some(k) = a.frames else { return };
            if failed.is_some() || !step.is_multiple_of(k) {
                return;
            }
            let path = numbered(&out, "step", step, 4);
            let written = cov
                .cell_mesh(color)
                .map_err(anyhow::Error::from)
                .and_then(|m| {
                    asperity_engine::io::write_mesh(&path, &m, &frame_options).map_err(Into::into)
                });
            match written {
                Ok(()) => frames.push(path),
                Err(e) => failed = Some(e),
            }
        },
    )?;
    if let Some(e) = failed {
        return Err(e);
    }
    if let Some(r) = &cov.repair {
        if r.dropped_degenerate > 0 || r.flipped > 0 || r.split_vertices > 0 {
            run.note(format!(
                "repaired: {} degenerate triangles dropped, {} flipped, {} vertices split",
                r.dropped_degenerate, r.flipped, r.split_vertices
            ));
        }
        run.report.measure("repair", r);
    }
    run.report.measure("cells_s", cov.cells_s);
    for w in &cov.cells.stats.warnings {
        run.warn("warning", w.clone());
    }
    run.note(cov.summary());
    for path in &frames {
        run.report.output(path);
    }
    for w in r.warnings() {
        run.warn("warning", w);
    }
    let textured = matches!(Format::from_path(&out)?, Format::Glb | Format::Obj);
    run.mesh(&out, &r.mesh(&cov, p.shape(textured), &ctx.budget)?)?;
    if let Some(path) = &a.labels_out {
        run.point_set(path, &r.labels(&cov)?)?;
    }
    statistics(&mut run, a, &r, cov.cells.len())?;
    run.measure(r.measurements(&cov));
    run.note(format!("{}; written to {}", r.summary(&cov), out.display()));
    run.finish()
}
