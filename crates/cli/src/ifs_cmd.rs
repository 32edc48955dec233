//! `asperity ifs …`: projected-IFS curves and surfaces, their DCFs/SDCFs and
//! pseudo-curvature ranges (poull-gentil; `asperity_engine::ifs`).

use std::path::Path;
use std::time::Instant;

use asperity_engine::core::TriMesh;
use asperity_engine::files::{extension, require_mesh_format};
use asperity_engine::ifs::{CurvatureReport, Loaded, control_net, figure};
use asperity_engine::methods::ifs::{DirectionAnalysis, SpectrumEntry, preset_names};

use crate::cli::{
    IfsCommand, IfsCurvatureArgs, IfsCurveArgs, IfsDcfArgs, IfsPresetArgs, IfsSdcfArgs,
    IfsSurfaceArgs,
};
use crate::context::{Context, Run};

pub fn run(ctx: &Context, c: IfsCommand) -> anyhow::Result<()> {
    match c {
        IfsCommand::Presets => presets(ctx),
        IfsCommand::Preset(a) => write_preset(ctx, &a),
        IfsCommand::Curve(a) => curve(ctx, &a),
        IfsCommand::Surface(a) => surface(ctx, &a),
        IfsCommand::Dcf(a) => dcf(ctx, &a),
        IfsCommand::Sdcf(a) => sdcf(ctx, &a),
        IfsCommand::Curvature(a) => curvature(ctx, &a),
    }
}

fn presets(ctx: &Context) -> anyhow::Result<()> {
    if ctx.json {
        let v = asperity_engine::ifs::presets();
        outln!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    for (n, d) in preset_names() {
        outln!("{n:<26} {d}");
    }
    Ok(())
}

fn write_preset(ctx: &Context, a: &IfsPresetArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let mut p = job.params;
    if let Some(name) = &a.name {
        p.model.preset = Some(name.clone());
    }
    asperity_engine::params::validate(&p)?;
    let text = p.model.load()?.file().to_json();
    match &ctx.output {
        Some(path) => {
            let mut run = Run::new(ctx, "ifs preset");
            run.text(path, &text)?;
            run.note(format!("wrote {}", path.display()));
            run.finish()
        }
        None => {
            out!("{text}");
            Ok(())
        }
    }
}

/// Writes polylines alone as OBJ `l` / PLY `edge` elements.
fn write_lines(run: &mut Run, path: &Path, lines: &[Vec<[f64; 3]>]) -> anyhow::Result<()> {
    let empty = TriMesh::new(Vec::new(), Vec::new())?;
    asperity_engine::io::write_mesh_with_polylines(path, &empty, lines, &run.write_options())?;
    run.report.output(path);
    Ok(())
}

/// Points as CSV: a parameter column, then x, y (and z).
fn csv(header: &str, pts: &[[f64; 3]], dims: usize, count: f64) -> String {
    let mut text = format!("{header}\n");
    for (k, p) in pts.iter().enumerate() {
        let s = k as f64 / count;
        text += &match dims {
            2 => format!("{s},{},{}\n", p[0], p[1]),
            _ => format!("{s},{},{},{}\n", p[0], p[1], p[2]),
        };
    }
    text
}

fn curve(ctx: &Context, a: &IfsCurveArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let out = ctx.output("FILE (e.g. -o curve.obj, curve.csv or curve.svg)")?;
    let mut run = Run::new(ctx, "ifs curve");
    let t = Instant::now();
    let (name, c, opts, pts) = job.params.attractor()?;
    run.params(&job.params, job.seed, job.overridden.clone());
    run.report.measure("build_s", t.elapsed().as_secs_f64());
    match extension(&out).as_str() {
        "csv" => {
            let header = if c.dim() == 2 { "s,x,y" } else { "s,x,y,z" };
            let text = csv(header, &pts, c.dim(), (pts.len() - 1) as f64);
            run.text(&out, &text)?;
        }
        "svg" => {
            let an = DirectionAnalysis::new(&c.pifs, &opts);
            run.text(&out, &figure(&c, &an, &name, 12, None)?)?;
        }
        "obj" | "ply" => write_lines(&mut run, &out, std::slice::from_ref(&pts))?,
        e => anyhow::bail!(
            "{}: curves are written as .obj/.ply (lines), .csv or .svg, not .{e}",
            out.display()
        ),
    }
    run.report.measure("points", pts.len());
    run.report.measure("depth", job.params.depth);
    run.note(format!(
        "{name}: {} attractor points written to {}",
        pts.len(),
        out.display()
    ));
    run.finish()
}

fn surface(ctx: &Context, a: &IfsSurfaceArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let out = ctx.output("FILE (e.g. -o attractor.ply)")?;
    require_mesh_format(&out, ".ply, .obj, .stl or .glb")?;
    let mut run = Run::new(ctx, "ifs surface");
    let t = Instant::now();
    let (name, s, mesh, note) = job.params.mesh(&ctx.budget)?;
    run.params(&job.params, job.seed, job.overridden.clone());
    run.report.measure("build_s", t.elapsed().as_secs_f64());
    if let Some(n) = note {
        run.note(&n);
        run.report.warn(n);
    }
    let t = Instant::now();
    run.mesh(&out, &mesh)?;
    run.report.measure("write_s", t.elapsed().as_secs_f64());
    if let Some(net) = &a.control_net {
        write_lines(&mut run, net, &control_net(&s))?;
    }
    let attributes: Vec<String> = mesh.scalars().iter().map(|s| s.name.clone()).collect();
    run.report.measure("vertices", mesh.n_vertices());
    run.report.measure("triangles", mesh.n_faces());
    run.report.measure("depth", job.params.depth);
    run.report.measure("attributes", attributes);
    run.note(format!(
        "{name}: {} vertices, {} triangles written to {}",
        mesh.n_vertices(),
        mesh.n_faces(),
        out.display()
    ));
    run.finish()
}

fn dcf(ctx: &Context, a: &IfsDcfArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let p = &job.params;
    let out = ctx.output("FILE (e.g. -o dcf.svg, dcf.csv or dcf.obj)")?;
    let (name, c, opts, d) = p.dcf()?;
    let i = p.operator;
    let (pts, class) = (d.points, d.class);
    let mut run = Run::new(ctx, "ifs dcf");
    run.params(p, job.seed, job.overridden.clone());
    match extension(&out).as_str() {
        "csv" => run.text(&out, &csv("t,x,y,z", &pts, 3, p.samples as f64))?,
        "svg" => {
            let an = DirectionAnalysis::new(&c.pifs, &opts);
            run.text(&out, &figure(&c, &an, &name, p.family, Some((i, &pts)))?)?
        }
        "obj" | "ply" => write_lines(&mut run, &out, std::slice::from_ref(&pts))?,
        e => anyhow::bail!(
            "{}: a DCF is written as .svg, .csv or .obj/.ply (a polyline), not .{e}",
            out.display()
        ),
    }
    run.report.measure("operator", i);
    run.report.measure("class", class);
    run.report.measure("alpha", d.alpha);
    run.report.measure("samples", p.samples);
    run.note(format!(
        "DCF of T{i} ({class}) written to {}",
        out.display()
    ));
    run.finish()
}

fn sdcf(ctx: &Context, a: &IfsSdcfArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let out = ctx.output("FILE (e.g. -o sdcf.ply)")?;
    let (name, mesh) = job.params.mesh(&ctx.budget)?;
    let (i, j) = job.params.indices()?;
    let mut run = Run::new(ctx, "ifs sdcf");
    run.params(&job.params, job.seed, job.overridden.clone());
    run.mesh(&out, &mesh)?;
    run.report.measure("operator", [i, j]);
    run.report.measure("vertices", mesh.n_vertices());
    run.note(format!(
        "{name}: SDCF of T{i}⊗T'{j} written to {}",
        out.display()
    ));
    run.finish()
}

fn fmt_range(r: Option<[f64; 2]>) -> String {
    match r {
        Some([a, b]) if (a - b).abs() <= 1e-12 * a.abs().max(1.0) => format!("{a:.10}"),
        Some([a, b]) => format!("[{a:.10}, {b:.10}]"),
        None => "—".to_owned(),
    }
}

/// A tensor operator's spectrum as "1, 0.5 ×4 (Jordan: 2 eigenvectors), 0.25 ×4 (…)",
/// values to 6 decimals with trailing zeros dropped (exact down to 2⁻⁶, a
/// bicubic patch's smallest eigenvalue; `--json` has them in full).
fn fmt_spectrum(spectrum: Option<&[SpectrumEntry]>) -> String {
    let Some(parts) = spectrum else {
        return "— (not real)".to_owned();
    };
    parts
        .iter()
        .map(|p| {
            let mut s = format!("{:.6}", p.value)
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_owned();
            if p.multiplicity > 1 {
                s += &format!(" ×{}", p.multiplicity);
            }
            if p.eigenvectors < p.multiplicity {
                s += &format!(
                    " (Jordan: {} eigenvector{})",
                    p.eigenvectors,
                    if p.eigenvectors == 1 { "" } else { "s" }
                );
            }
            s
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn curvature(ctx: &Context, a: &IfsCurvatureArgs) -> anyhow::Result<()> {
    let job = ctx.job_params(a.params.clone(), &a.params_file)?;
    let t = Instant::now();
    let (l, report, mut doc) = job.params.report()?;
    doc["seconds"] = serde_json::json!(t.elapsed().as_secs_f64());
    doc["params"] = asperity_engine::params::record(&job.params, job.seed);
    if ctx.json {
        outln!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    print_curvature(&l, &report)
}

fn print_curvature(l: &Loaded, report: &CurvatureReport) -> anyhow::Result<()> {
    match (report, &l.model) {
        (CurvatureReport::Curve(ops, at), asperity_engine::methods::ifs::Model::Curve(c)) => {
            outln!("{} (curve, N = {})", l.name, c.pifs.size());
            outln!(
                "{:<4} {:<8} {:<20} {:<28} curvature",
                "op",
                "s",
                "class",
                "alpha"
            );
            for o in ops {
                let alpha: Vec<String> = o
                    .alpha
                    .iter()
                    .map(|x| x.map_or("∞".into(), |v| format!("{v:.4}")))
                    .collect();
                outln!(
                    "T{:<3} {:<8} {:<20} {:<28} {}",
                    o.index,
                    o.parameter,
                    o.class,
                    alpha.join(" "),
                    fmt_range(o.curvature)
                );
                if let Some(r) = &o.reason {
                    outln!("     {r}");
                }
            }
            for p in at {
                for sd in &p.sides {
                    let word = if sd.word.is_empty() { "—" } else { &sd.word };
                    outln!(
                        "at s = {} ({}, T{} via {word}): {} {}",
                        p.at,
                        sd.side,
                        sd.operator,
                        sd.class,
                        fmt_range(sd.curvature)
                    );
                }
            }
        }
        (CurvatureReport::Surface(ops, at), asperity_engine::methods::ifs::Model::Surface(s)) => {
            let (n, m) = s.grid_size();
            outln!("{} (tensor-product surface, {n}×{m} control grid)", l.name);
            outln!(
                "{:<8} {:<10} {:<12} {:<36} mean",
                "op",
                "(s,t)",
                "class",
                "gaussian"
            );
            for o in ops {
                outln!(
                    "T{}⊗T'{}  ({},{})      {:<12} {:<36} {}",
                    o.index[0],
                    o.index[1],
                    o.parameter[0],
                    o.parameter[1],
                    o.class,
                    fmt_range(o.gaussian),
                    fmt_range(o.mean)
                );
                outln!(
                    "         spectrum {}",
                    fmt_spectrum(o.tensor_spectrum.as_deref())
                );
            }
            for p in at {
                for q in &p.quadrants {
                    outln!(
                        "at ({}, {}) {}/{} (T{}⊗T'{}): {} K {} H {}",
                        p.at[0],
                        p.at[1],
                        q.side[0],
                        q.side[1],
                        q.operator[0],
                        q.operator[1],
                        q.class,
                        fmt_range(q.gaussian),
                        fmt_range(q.mean)
                    );
                }
            }
        }
        _ => anyhow::bail!("the report does not match the model"),
    }
    Ok(())
}
