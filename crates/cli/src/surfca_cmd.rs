//! `asperity surface-ca`: cellular automata on a triangle mesh (gobron-chiba;
//! `asperity_engine::surfca`).

use std::path::{Path, PathBuf};

use asperity_core::Progress;
use asperity_engine::files::{numbered, require_mesh_format};
use asperity_engine::surfca::{
    App, AppRequest, AppRun, Covered, OutputShape, check_time, cover, run_app, start_progress,
};
use asperity_io::Format;
use asperity_surfca::CellSize;
use asperity_surfca::corrosion::CorrosionParams;

use crate::cli::{SurfaceApp, SurfaceCaArgs};
use crate::context::{Context, Run};

fn request(ctx: &Context, a: &SurfaceCaArgs) -> anyhow::Result<AppRequest> {
    let at = match &a.site_points {
        Some(path) => Some((ctx.load_points(path)?, path.display().to_string())),
        None => None,
    };
    Ok(match a.app {
        SurfaceApp::Voronoi => AppRequest::Voronoi {
            sites: a.sites,
            at,
            diagonal_p: a.diagonal_p,
            max_steps: a.max_steps,
        },
        SurfaceApp::Corrosion => AppRequest::Corrosion {
            params: CorrosionParams {
                k1: a.k1,
                k2: a.k2,
                k3: a.k3,
                seed_rate: a.seed_rate,
                max_seeds: a.max_seeds,
                strong_fraction: a.strong_fraction,
                strong_noise_scale: a.strong_noise,
                max_attacked: a.max_attacked,
                attack: a.attack,
                maturity: a.maturity,
                ..CorrosionParams::default()
            },
            steps: a.steps,
            at,
        },
        SurfaceApp::GrayScott => AppRequest::GrayScott {
            feed: a.feed,
            kill: a.kill,
            patches: a.patches,
            steps: a.steps,
        },
    })
}

/// Runs the application, writing an animation frame every `--frames` steps.
fn run_with_frames(
    ctx: &Context,
    a: &SurfaceCaArgs,
    cov: &Covered,
    app: App,
    out: &Path,
) -> anyhow::Result<(AppRun, Vec<PathBuf>)> {
    if let Some(k) = a.frames {
        asperity_engine::estimate::check_file_count(app.steps() / k + 1, "--frames")?;
    }
    let bar = ctx.bar();
    start_progress(&bar, &app);
    let (mut written, mut failed) = (Vec::new(), None);
    let r = run_app(cov, app, ctx.seed, &ctx.time, |step, color| {
        bar.advance(1);
        let Some(k) = a.frames else { return };
        if failed.is_some() || !step.is_multiple_of(k) {
            return;
        }
        let path = numbered(out, "step", step, 4);
        let m = cov.cell_mesh(color);
        match m.map_err(anyhow::Error::from).and_then(|m| {
            asperity_io::write_mesh(&path, &m, &ctx.write_options()).map_err(Into::into)
        }) {
            Ok(()) => written.push(path),
            Err(e) => failed = Some(e),
        }
    })?;
    bar.finish();
    match failed {
        Some(e) => Err(e),
        None => Ok((r, written)),
    }
}

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
        let img = asperity_render::plot::plot_png(&r.stats_plot(n), 900, 600)?;
        run.png(path, &img)?;
    }
    Ok(())
}

pub fn run(ctx: &Context, a: &SurfaceCaArgs) -> anyhow::Result<()> {
    let out = ctx.output("FILE (e.g. -o voronoi.glb)")?;
    require_mesh_format(&out, ".glb, .ply or .obj")?;
    let mut run = Run::new(ctx, "surface-ca");
    let size = match a.cell_size {
        Some(h) => CellSize::Size(h),
        None => CellSize::Count(a.cells),
    };
    let mesh = ctx.load_mesh(&a.mesh)?;
    let request = request(ctx, a)?;
    // Refuse a run no machine could finish before building its cells.
    if let Ok(cells) = asperity_surfca::cells::estimated_count(&mesh, size) {
        check_time(cells, &request.kind(), &ctx.time)?;
    }
    let cov = cover(mesh, &a.mesh, a.repair, size, &ctx.budget)?;
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
    let app = request.build(&cov, ctx.seed)?;
    let (r, frames) = run_with_frames(ctx, a, &cov, app, &out)?;
    for p in &frames {
        run.report.output(p);
    }
    for w in r.warnings() {
        run.warn("warning", w);
    }
    let shape = OutputShape {
        textured: matches!(Format::from_path(&out)?, Format::Glb | Format::Obj),
        cell_mesh: a.cell_mesh,
        displace: a.displace,
    };
    run.mesh(&out, &r.mesh(&cov, shape, &ctx.budget)?)?;
    if let Some(path) = &a.labels_out {
        run.point_set(path, &r.labels(&cov)?)?;
    }
    statistics(&mut run, a, &r, cov.cells.len())?;
    run.measure(r.measurements(&cov));
    run.note(format!("{}; written to {}", r.summary(&cov), out.display()));
    run.finish()
}
