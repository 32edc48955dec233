//! `asperity surface-ca`: cellular automata on a triangle mesh (gobron-chiba;
//! library: `asperity-surfca`).

use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use asperity_core::{PointSet, Progress, TriMesh, shapes};
use asperity_io::{Format, Surface, WriteOptions};
use asperity_render::plot::{Plot, Series, Style, plot_png};
use asperity_surfca::engine::RunStats;
use asperity_surfca::voronoi::{PAPER_P, UNLABELLED, VoronoiRule, random_sites, voronoi};
use asperity_surfca::{CellSize, Cells, build};
use serde_json::json;

use crate::cli::{Context, SurfaceApp, SurfaceCaArgs};
use crate::progress::Bar;
use crate::report::Report;

/// A mesh from a file or `builtin:NAME`.
pub fn load_mesh(ctx: &Context, spec: &str) -> anyhow::Result<TriMesh> {
    if let Some(name) = spec.strip_prefix("builtin:") {
        return Ok(match name {
            "sphere" => shapes::icosphere(3, 1.0),
            "cube" => shapes::cube(4),
            "cup" => shapes::cup(48),
            "cylinder" => shapes::revolve(
                &[
                    [0.0, 0.0],
                    [0.5, 0.0],
                    [0.5, 0.5],
                    [0.5, 1.0],
                    [0.5, 1.5],
                    [0.5, 2.0],
                    [0.0, 2.0],
                ],
                48,
            ),
            _ => {
                anyhow::bail!("unknown built-in mesh {name:?}; known: sphere, cube, cylinder, cup")
            }
        });
    }
    match crate::convert::load(ctx, Path::new(spec))? {
        Surface::Mesh(m) => Ok(m),
        _ => anyhow::bail!("{spec} is not a triangle mesh (a surface CA lives on triangles)"),
    }
}

/// Distinct colours for labels (golden-ratio hues, fixed saturation and value).
pub fn label_color(label: u32) -> [u8; 4] {
    if label == UNLABELLED {
        return [200, 200, 200, 255];
    }
    let h = (label as f64 * 0.618_033_988_749_895).fract() * 6.0;
    let (s, v) = (0.55, 0.92);
    let c = v * s;
    let x = c * (1.0 - ((h % 2.0) - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    let to = |u: f64| ((u + m) * 255.0).round() as u8;
    [to(r), to(g), to(b), 255]
}

/// The cells as a mesh with vertex colours (see `asperity_surfca::atlas::cell_mesh`).
pub fn cell_mesh(
    mesh: &TriMesh,
    cells: &Cells,
    color: impl Fn(usize) -> [u8; 4],
) -> anyhow::Result<TriMesh> {
    Ok(asperity_surfca::atlas::cell_mesh(mesh, cells, color, None)?)
}

/// `dir/stem_stepNNNN.ext` next to `out`.
fn frame_path(out: &Path, step: u64) -> std::path::PathBuf {
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
    let ext = out.extension().and_then(|s| s.to_str()).unwrap_or("ply");
    out.with_file_name(format!("{stem}_step{step:04}.{ext}"))
}

/// Writes an animation frame when `--frames K` asks for this step; the first
/// error is kept and reported after the run.
struct Frames<'a> {
    every: Option<u64>,
    out: &'a Path,
    written: Vec<std::path::PathBuf>,
    error: Option<anyhow::Error>,
}

impl Frames<'_> {
    fn maybe(&mut self, step: u64, mesh: impl FnOnce() -> anyhow::Result<TriMesh>) {
        let Some(k) = self.every else { return };
        if self.error.is_some() || !step.is_multiple_of(k) {
            return;
        }
        let path = frame_path(self.out, step);
        match mesh().and_then(|m| {
            asperity_io::write_mesh(&path, &m, &WriteOptions::default())
                .with_context(|| format!("writing {}", path.display()))
        }) {
            Ok(()) => self.written.push(path),
            Err(e) => self.error = Some(e),
        }
    }

    fn finish(self, report: &mut Report) -> anyhow::Result<()> {
        if let Some(e) = self.error {
            return Err(e);
        }
        for p in &self.written {
            report.output(p);
        }
        Ok(())
    }
}

/// The result mesh: for glTF and OBJ the original mesh with the cells as a
/// texture atlas (unless `--cell-mesh`); otherwise the cell mesh with per-vertex
/// colours and the per-cell `scalar`.
fn output_mesh(
    a: &SurfaceCaArgs,
    out: &Path,
    (mesh, cells): (&TriMesh, &Cells),
    color: impl Fn(usize) -> [u8; 4],
    scalar: Option<(&str, &[f64])>,
    budget: &asperity_core::MemoryBudget,
) -> anyhow::Result<TriMesh> {
    let textured = matches!(Format::from_path(out)?, Format::Glb | Format::Obj);
    if let Some(k) = a.displace {
        let (_, values) = scalar.with_context(
            || "--displace needs a per-cell thickness (corrosion: oxide; gray-scott: activator)",
        )?;
        anyhow::ensure!(k.is_finite(), "--displace must be finite");
        return Ok(asperity_surfca::atlas::cell_mesh(
            mesh,
            cells,
            color,
            Some((values, k)),
        )?);
    }
    if textured && !a.cell_mesh {
        return Ok(asperity_surfca::atlas::atlas_mesh(
            mesh, cells, color, budget,
        )?);
    }
    let mut m = cell_mesh(mesh, cells, color)?;
    if let Some((name, values)) = scalar {
        m = m.with_scalar(
            name,
            (0..cells.len())
                .flat_map(|c| std::iter::repeat_n(values[c], cells.polygon(c).len()))
                .collect(),
        )?;
    }
    Ok(m)
}

fn stats_csv(s: &RunStats, n: usize, classes: &[&str]) -> String {
    let mut t = String::from("step,changed,changed_fraction");
    for c in classes {
        t += &format!(",{c}");
    }
    t.push('\n');
    for p in &s.per_step {
        t += &format!("{},{},{}", p.step, p.changed, p.changed as f64 / n as f64);
        for f in &p.class_fraction {
            t += &format!(",{f}");
        }
        t.push('\n');
    }
    t
}

pub fn run(ctx: &Context, a: &SurfaceCaArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output file: give -o FILE (e.g. -o voronoi.glb)")?;
    let f = Format::from_path(&out)?;
    anyhow::ensure!(
        f.info().mesh.can_write(),
        "{} cannot hold a mesh; use .glb, .ply or .obj",
        out.display()
    );
    let mut report = Report::new("surface-ca", ctx);
    let mut mesh = load_mesh(ctx, &a.mesh)?;
    if a.repair {
        let (m, r) = asperity_surfca::repair::repair(&mesh)?;
        if r.dropped_degenerate > 0 || r.flipped > 0 {
            ctx.note(format!(
                "repaired: {} degenerate triangles dropped, {} flipped",
                r.dropped_degenerate, r.flipped
            ));
        }
        report.measure("repair", &r);
        mesh = m;
    }
    asperity_surfca::repair::check(&mesh).with_context(|| a.mesh.clone())?;
    let t = Instant::now();
    let size = match a.cell_size {
        Some(h) => CellSize::Size(h),
        None => CellSize::Count(a.cells),
    };
    let cells = build(&mesh, size, &ctx.budget)?;
    report.measure("cells_s", t.elapsed().as_secs_f64());
    for w in &cells.stats.warnings {
        ctx.note(format!("warning: {w}"));
        report.warnings.push(w.clone());
    }
    ctx.note(format!(
        "{} cells of side {:.4} on {} triangles ({} COMP-IN, {} PART-IN; pairing redundancy {:.1} %)",
        cells.len(),
        cells.h,
        mesh.n_faces(),
        cells.stats.comp_in,
        cells.stats.part_in,
        100.0 * cells.stats.pairing_redundancy
    ));
    match a.app {
        SurfaceApp::Corrosion => corrosion(ctx, a, &mesh, &cells, &out, &mut report)?,
        SurfaceApp::GrayScott => gray_scott(ctx, a, &mesh, &cells, &out, &mut report)?,
        SurfaceApp::Voronoi => {
            anyhow::ensure!(
                a.sites >= 1 || a.site_points.is_some(),
                "--sites must be at least 1"
            );
            anyhow::ensure!(
                a.sites <= cells.len(),
                "--sites {} exceeds the {} cells; use more cells",
                a.sites,
                cells.len()
            );
            let p = a.diagonal_p.unwrap_or(PAPER_P);
            anyhow::ensure!(
                (0.0..=1.0).contains(&p),
                "--diagonal-p must be in [0, 1], got {p}"
            );
            let sites = match &a.site_points {
                Some(path) => {
                    let pts = asperity_io::read_points(path)
                        .with_context(|| format!("reading sites from {}", path.display()))?;
                    anyhow::ensure!(!pts.is_empty(), "{}: no site points", path.display());
                    asperity_surfca::voronoi::sites_at(&cells, pts.positions())
                }
                None => random_sites(&cells, a.sites, ctx.seed),
            };
            let bar = Bar::new(ctx.quiet || ctx.json);
            bar.start(0, "surface Voronoi");
            let t = Instant::now();
            let mut frames = Frames {
                every: a.frames,
                out: &out,
                written: Vec::new(),
                error: None,
            };
            let (labels, stats) = voronoi(
                &cells,
                &sites,
                &VoronoiRule { diagonal_p: p },
                ctx.seed,
                a.max_steps,
                |step, labels| {
                    bar.advance(1);
                    frames.maybe(step, || {
                        cell_mesh(&mesh, &cells, |c| label_color(labels[c]))
                    });
                    true
                },
            );
            bar.finish();
            frames.finish(&mut report)?;
            let secs = t.elapsed().as_secs_f64();
            report.measure("run_s", secs);
            report.measure(
                "cell_updates_per_s",
                cells.len() as f64 * stats.steps as f64 / secs.max(1e-9),
            );
            let unreached = labels.iter().filter(|&&l| l == UNLABELLED).count();
            if unreached > 0 {
                let w = format!(
                    "{unreached} cells were not reached (separate components, or the step limit)"
                );
                ctx.note(format!("warning: {w}"));
                report.warnings.push(w);
            }
            let m = output_mesh(
                a,
                &out,
                (&mesh, &cells),
                |c| label_color(labels[c]),
                None,
                &ctx.budget,
            )?;
            asperity_io::write_mesh(&out, &m, &WriteOptions::default())
                .with_context(|| format!("writing {}", out.display()))?;
            report.output(&out);
            if let Some(path) = &a.labels_out {
                let mut ps = PointSet::new(cells.centre.clone());
                ps.add_attribute(
                    "label",
                    labels
                        .iter()
                        .map(|&l| if l == UNLABELLED { -1.0 } else { l as f64 })
                        .collect(),
                )?;
                ps.add_attribute("area", cells.area.clone())?;
                ps.set_colors(labels.iter().map(|&l| label_color(l)).collect())?;
                asperity_io::write_points(path, &ps, &WriteOptions::default())
                    .with_context(|| format!("writing {}", path.display()))?;
                report.output(path);
            }
            let rule = VoronoiRule { diagonal_p: p };
            let classes = asperity_surfca::Rule::classes(&rule);
            write_stats(a, &stats, cells.len(), classes, &mut report)?;
            report.measure("app", "voronoi");
            report.measure("cells", cells.len());
            report.measure("cell_structure", &cells.stats);
            report.measure("steps", stats.steps);
            report.measure("diagonal_p", p);
            report.measure(
                "changed_fraction",
                stats
                    .per_step
                    .iter()
                    .map(|s| s.changed as f64 / cells.len() as f64)
                    .collect::<Vec<_>>(),
            );
            report.measure(
                "sites",
                sites.iter().map(|&c| cells.centre[c]).collect::<Vec<_>>(),
            );
            ctx.note(format!(
                "{} sites grew over {} cells in {} steps ({secs:.2} s); written to {}",
                sites.len(),
                cells.len(),
                stats.steps,
                out.display()
            ));
        }
    }
    report.finish(ctx)
}

/// Colour of a corrosion cell: patina over copper by the two-layer model
/// (gobron-chiba "light through two layers"); holes are dark.
pub fn patina_color(s: &asperity_surfca::corrosion::CorrosionCell) -> [u8; 4] {
    use asperity_surfca::corrosion::Behaviour;
    const PATINA: [f64; 3] = [0.27, 0.62, 0.50];
    const COPPER: [f64; 3] = [0.74, 0.43, 0.25];
    let c = match s.behaviour {
        Behaviour::NonExistent => [0.12, 0.09, 0.07],
        _ => asperity_render::light::two_layer(
            PATINA,
            s.oxide as f64,
            0.6,
            COPPER,
            s.metal.max(0.05) as f64,
            0.95,
        ),
    };
    let to = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [to(c[0]), to(c[1]), to(c[2]), 255]
}

fn corrosion(
    ctx: &Context,
    a: &SurfaceCaArgs,
    mesh: &TriMesh,
    cells: &Cells,
    out: &Path,
    report: &mut Report,
) -> anyhow::Result<()> {
    use asperity_surfca::corrosion::{Behaviour, CorrosionParams, CorrosionRule, corrode, initial};
    let params = CorrosionParams {
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
    };
    params
        .validate()
        .map_err(|e| anyhow::anyhow!("corrosion: {e}"))?;
    let mut states = initial(cells, &params, ctx.seed);
    let bar = Bar::new(ctx.quiet || ctx.json);
    bar.start(a.steps, "corrosion");
    let t = Instant::now();
    let mut frames = Frames {
        every: a.frames,
        out,
        written: Vec::new(),
        error: None,
    };
    let stats = corrode(
        cells,
        &params,
        &mut states,
        ctx.seed,
        a.steps,
        |step, st| {
            bar.advance(1);
            frames.maybe(step, || cell_mesh(mesh, cells, |c| patina_color(&st[c])));
            true
        },
    );
    bar.finish();
    frames.finish(report)?;
    let secs = t.elapsed().as_secs_f64();
    report.measure("run_s", secs);
    report.measure(
        "cell_updates_per_s",
        cells.len() as f64 * stats.steps as f64 / secs.max(1e-9),
    );
    let oxide: Vec<f64> = states.iter().map(|s| s.oxide as f64).collect();
    let m = output_mesh(
        a,
        out,
        (mesh, cells),
        |c| patina_color(&states[c]),
        Some(("oxide", &oxide)),
        &ctx.budget,
    )?;
    asperity_io::write_mesh(out, &m, &WriteOptions::default())
        .with_context(|| format!("writing {}", out.display()))?;
    report.output(out);
    let rule = CorrosionRule { params };
    write_stats(
        a,
        &stats,
        cells.len(),
        asperity_surfca::Rule::classes(&rule),
        report,
    )?;
    let count = |b: Behaviour| states.iter().filter(|s| s.behaviour == b).count();
    report.measure("app", "corrosion");
    report.measure("cells", cells.len());
    report.measure("cell_structure", &cells.stats);
    report.measure("steps", stats.steps);
    report.measure("corroded", count(Behaviour::Corroded));
    report.measure("non_existent", count(Behaviour::NonExistent));
    report.measure(
        "changed_fraction",
        stats
            .per_step
            .iter()
            .map(|s| s.changed as f64 / cells.len() as f64)
            .collect::<Vec<_>>(),
    );
    ctx.note(format!(
        "{} steps over {} cells in {secs:.2} s: {:.1} % corroded, {:.1} % eaten through; written to {}",
        stats.steps,
        cells.len(),
        100.0 * count(Behaviour::Corroded) as f64 / cells.len() as f64,
        100.0 * count(Behaviour::NonExistent) as f64 / cells.len() as f64,
        out.display()
    ));
    Ok(())
}

/// Colour of a Gray–Scott cell: v through viridis.
fn rd_color(s: &asperity_surfca::reaction_diffusion::Chemicals) -> [u8; 4] {
    let c = asperity_render::ColorMap::Viridis.map((s.v as f64 / 0.45).clamp(0.0, 1.0));
    [c[0], c[1], c[2], 255]
}

fn gray_scott(
    ctx: &Context,
    a: &SurfaceCaArgs,
    mesh: &TriMesh,
    cells: &Cells,
    out: &Path,
    report: &mut Report,
) -> anyhow::Result<()> {
    use asperity_surfca::engine::{RunOptions, run};
    use asperity_surfca::reaction_diffusion::{GrayScott, seeded_state};
    let rule = GrayScott {
        feed: a.feed,
        kill: a.kill,
        ..GrayScott::default()
    };
    rule.validate()
        .map_err(|e| anyhow::anyhow!("gray-scott: {e}"))?;
    anyhow::ensure!(a.patches >= 1, "--patches must be at least 1");
    let mut states = seeded_state(cells, a.patches.min(cells.len()), ctx.seed);
    let bar = Bar::new(ctx.quiet || ctx.json);
    bar.start(a.steps, "reaction-diffusion");
    let mut frames = Frames {
        every: a.frames,
        out,
        written: Vec::new(),
        error: None,
    };
    let t = Instant::now();
    let stats = run(
        cells,
        &rule,
        &mut states,
        &RunOptions {
            seed: ctx.seed,
            max_steps: a.steps,
            stop_when_stable: false,
        },
        |step, st| {
            bar.advance(1);
            frames.maybe(step, || cell_mesh(mesh, cells, |c| rd_color(&st[c])));
            true
        },
    );
    bar.finish();
    frames.finish(report)?;
    let secs = t.elapsed().as_secs_f64();
    let v: Vec<f64> = states.iter().map(|s| s.v as f64).collect();
    let m = output_mesh(
        a,
        out,
        (mesh, cells),
        |c| rd_color(&states[c]),
        Some(("activator", &v)),
        &ctx.budget,
    )?;
    asperity_io::write_mesh(out, &m, &WriteOptions::default())
        .with_context(|| format!("writing {}", out.display()))?;
    report.output(out);
    write_stats(
        a,
        &stats,
        cells.len(),
        asperity_surfca::Rule::classes(&rule),
        report,
    )?;
    report.measure("app", "gray-scott");
    report.measure("cells", cells.len());
    report.measure("steps", stats.steps);
    report.measure("run_s", secs);
    report.measure(
        "activator_fraction",
        stats.per_step.last().map_or(0.0, |s| s.class_fraction[1]),
    );
    ctx.note(format!(
        "{} Gray–Scott steps over {} cells in {secs:.2} s; written to {}",
        stats.steps,
        cells.len(),
        out.display()
    ));
    Ok(())
}

fn write_stats(
    a: &SurfaceCaArgs,
    stats: &RunStats,
    n: usize,
    classes: &[&str],
    report: &mut Report,
) -> anyhow::Result<()> {
    if let Some(path) = &a.stats_out {
        let text = if path.extension().and_then(|e| e.to_str()) == Some("json") {
            serde_json::to_string_pretty(&json!({"classes": classes, "cells": n, "run": stats}))?
        } else {
            stats_csv(stats, n, classes)
        };
        asperity_io::write_text(path, &text)?;
        report.output(path);
    }
    if let Some(path) = &a.plot {
        let mut series = vec![Series {
            name: "changed cells (fraction)".into(),
            points: stats
                .per_step
                .iter()
                .map(|s| (s.step as f64, s.changed as f64 / n as f64))
                .collect(),
            style: Style::Line,
        }];
        for (k, c) in classes.iter().enumerate() {
            series.push(Series {
                name: format!("{c} (area fraction)"),
                points: stats
                    .per_step
                    .iter()
                    .map(|s| {
                        (
                            s.step as f64,
                            s.class_fraction.get(k).copied().unwrap_or(0.0),
                        )
                    })
                    .collect(),
                style: Style::Line,
            });
        }
        let plot = Plot {
            title: "Surface CA: per-step statistics".into(),
            x_label: "step".into(),
            y_label: "fraction".into(),
            log_x: false,
            log_y: false,
            series,
        };
        asperity_io::write_png(path, &plot_png(&plot, 900, 600)?)?;
        report.output(path);
    }
    Ok(())
}
