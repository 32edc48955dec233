//! `asperity ifs …`: projected-IFS curves and surfaces, their DCFs/SDCFs and
//! pseudo-curvature ranges (poull-gentil; `asperity_engine::ifs`).

use std::path::Path;
use std::time::Instant;

use asperity_core::TriMesh;
use asperity_engine::files::{extension, require_mesh_format};
use asperity_engine::ifs::{
    CurvatureReport, Loaded, ModelSpec, control_net, curvature_doc, curvature_report, dcf_for,
    figure, load, pair, sdcf_for, surface_mesh,
};
use asperity_ifs::sdcf::Start;
use asperity_ifs::{DirectionAnalysis, FamilyOptions, PresetParams, preset, preset_names};

use crate::cli::{
    BoundArg, IfsCommand, IfsCurvatureArgs, IfsCurveArgs, IfsDcfArgs, IfsModelArgs, IfsPresetArgs,
    IfsPresetParams, IfsSdcfArgs, IfsSurfaceArgs,
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

fn params(p: &IfsPresetParams) -> PresetParams {
    PresetParams {
        w: p.w,
        degree: p.degree,
        height: p.height,
    }
}

fn model(a: &IfsModelArgs) -> anyhow::Result<Loaded> {
    Ok(load(&ModelSpec {
        preset: a.preset.clone(),
        file: a.ifs.clone(),
        json: None,
        params: params(&a.params),
        control: a.control.clone(),
        moves: a.moves.clone(),
        family: FamilyOptions {
            dyadic_depth: a.family_depth,
            period: a.family_period,
        },
    })?)
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
    let text = preset(&a.name, &params(&a.params))?.to_json();
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
    asperity_io::write_mesh_with_polylines(path, &empty, lines, &run.ctx.write_options())?;
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
    let (name, c, opts) = model(&a.model)?.curve()?;
    let out = ctx.output("FILE (e.g. -o curve.obj, curve.csv or curve.svg)")?;
    let mut run = Run::new(ctx, "ifs curve");
    let t = Instant::now();
    let pts = c.attractor(a.depth)?;
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
    run.report.measure("depth", a.depth);
    run.note(format!(
        "{name}: {} attractor points written to {}",
        pts.len(),
        out.display()
    ));
    run.finish()
}

fn surface(ctx: &Context, a: &IfsSurfaceArgs) -> anyhow::Result<()> {
    let (name, s, opts) = model(&a.model)?.surface(a.model.params.height)?;
    let out = ctx.output("FILE (e.g. -o attractor.ply)")?;
    require_mesh_format(&out, ".ply, .obj, .stl or .glb")?;
    let mut run = Run::new(ctx, "ifs surface");
    let t = Instant::now();
    let (mesh, note) = surface_mesh(&s, &opts, a.depth, !a.no_curvature, &ctx.budget)?;
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
    run.report.measure("depth", a.depth);
    run.report.measure("attributes", attributes);
    run.note(format!(
        "{name}: {} vertices, {} triangles written to {}",
        mesh.n_vertices(),
        mesh.n_faces(),
        out.display()
    ));
    run.finish()
}

fn start(bound: Option<BoundArg>, param: f64) -> Start {
    match bound {
        Some(BoundArg::Lower) => Start::Lower,
        Some(BoundArg::Upper) => Start::Upper,
        None => Start::Parameter(param),
    }
}

fn dcf(ctx: &Context, a: &IfsDcfArgs) -> anyhow::Result<()> {
    let (name, c, opts) = model(&a.model)?.curve()?;
    let out = ctx.output("FILE (e.g. -o dcf.svg, dcf.csv or dcf.obj)")?;
    let i = a.operator as usize;
    let first = start(a.bound, a.start.unwrap_or(1.0 - i as f64));
    let d = dcf_for(&c, &opts, i, Some(first), a.samples)?;
    let (pts, class) = (d.points, d.class);
    let mut run = Run::new(ctx, "ifs dcf");
    match extension(&out).as_str() {
        "csv" => run.text(&out, &csv("t,x,y,z", &pts, 3, a.samples as f64))?,
        "svg" => {
            let an = DirectionAnalysis::new(&c.pifs, &opts);
            run.text(&out, &figure(&c, &an, &name, a.family, Some((i, &pts)))?)?
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
    run.report.measure("samples", a.samples);
    run.note(format!(
        "DCF of T{i} ({class}) written to {}",
        out.display()
    ));
    run.finish()
}

fn sdcf(ctx: &Context, a: &IfsSdcfArgs) -> anyhow::Result<()> {
    let (name, s, opts) = model(&a.model)?.surface(a.model.params.height)?;
    let out = ctx.output("FILE (e.g. -o sdcf.ply)")?;
    let (i, j): (usize, usize) = pair(&a.operator, "--operator")?;
    anyhow::ensure!(
        i < 2 && j < 2,
        "--operator {}: I and J are 0 or 1",
        a.operator
    );
    let st = match &a.start {
        Some(v) => pair(v, "--start")?,
        None => (1.0 - i as f64, 1.0 - j as f64),
    };
    let starts = (start(a.bound, st.0), start(a.bound, st.1));
    let mut mesh = sdcf_for(&s, &opts, (i, j), starts, a.resolution, &ctx.budget)?;
    if let Some(d) = a.with_attractor {
        let att = s.attractor_mesh(d, &ctx.budget)?;
        mesh =
            TriMesh::merge_colored(&[(&att, [190, 190, 190, 255]), (&mesh, [40, 90, 220, 255])])?;
    }
    let mut run = Run::new(ctx, "ifs sdcf");
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

fn curvature(ctx: &Context, a: &IfsCurvatureArgs) -> anyhow::Result<()> {
    let l = model(&a.model)?;
    let t = Instant::now();
    let report = curvature_report(&l, &a.at)?;
    let mut doc = curvature_doc(&l, &report)?;
    doc["seconds"] = serde_json::json!(t.elapsed().as_secs_f64());
    if ctx.json {
        outln!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    print_curvature(&l, &report)
}

fn print_curvature(l: &Loaded, report: &CurvatureReport) -> anyhow::Result<()> {
    match (report, &l.model) {
        (CurvatureReport::Curve(ops, at), asperity_ifs::Model::Curve(c)) => {
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
        (CurvatureReport::Surface(ops, at), asperity_ifs::Model::Surface(s)) => {
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
