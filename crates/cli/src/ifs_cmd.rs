//! `asperity ifs …`: projected-IFS curves and surfaces, their DCFs/SDCFs and
//! pseudo-curvature ranges (poull-gentil; library: `asperity-ifs`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context as _;
use asperity_core::TriMesh;
use asperity_ifs::curvature::{
    curve_at, curve_report, surface_at, surface_report, vertex_curvature,
};
use asperity_ifs::model::{TAKAGI_SHEAR, tensor_square};
use asperity_ifs::sdcf::{Start, dcf_polyline, sdcf_mesh, start_point};
use asperity_ifs::{
    CurveIfs, DirectionAnalysis, FamilyOptions, Model, ModelFile, PresetParams, SurfaceIfs, preset,
    preset_names,
};
use asperity_io::{Format, WriteOptions};
use asperity_render::plot::{Drawing, Stroke, drawing_svg};
use serde_json::{Value, json};

use crate::cli::{
    BoundArg, Context, IfsCommand, IfsCurvatureArgs, IfsCurveArgs, IfsDcfArgs, IfsModelArgs,
    IfsPresetArgs, IfsPresetParams, IfsSdcfArgs, IfsSurfaceArgs,
};
use crate::report::Report;

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

/// A model as used: built, with its control points edited.
pub struct Loaded {
    pub name: String,
    pub model: Model,
    pub opts: FamilyOptions,
}

impl Loaded {
    fn file(&self) -> ModelFile {
        self.model.to_file(&self.name, "")
    }
}

fn parse_numbers(s: &str, what: &str) -> anyhow::Result<Vec<f64>> {
    s.split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .with_context(|| format!("{what}: {x:?} is not a finite number"))
        })
        .collect()
}

fn read_control(path: &Path) -> anyhow::Result<Value> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    if path.extension().and_then(|e| e.to_str()) == Some("json") {
        return serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()));
    }
    // CSV: x,y[,z] per line; a header line and `#` comments are skipped.
    let mut pts = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        match parse_numbers(line, "control point") {
            Ok(v) => pts.push(json!(v)),
            Err(e) if pts.is_empty() && i == 0 => {
                let _ = e; // header
            }
            Err(e) => return Err(e.context(format!("{} line {}", path.display(), i + 1))),
        }
    }
    Ok(Value::Array(pts))
}

fn points(v: &Value, what: &str) -> anyhow::Result<Vec<Vec<f64>>> {
    v.as_array()
        .with_context(|| format!("{what}: expected a list of points"))?
        .iter()
        .map(|p| {
            p.as_array()
                .with_context(|| format!("{what}: a point is a list of 2 or 3 numbers"))?
                .iter()
                .map(|x| {
                    x.as_f64()
                        .with_context(|| format!("{what}: {x} is not a number"))
                })
                .collect()
        })
        .collect()
}

fn apply_control(model: Model, v: &Value, path: &Path) -> anyhow::Result<Model> {
    let what = path.display().to_string();
    Ok(match model {
        Model::Curve(c) => Model::Curve(CurveIfs::new(c.pifs.clone(), &points(v, &what)?)?),
        Model::Surface(s) => {
            let (_, m) = s.grid_size();
            let nested = v
                .as_array()
                .and_then(|a| a.first())
                .and_then(|r| r.as_array())
                .and_then(|r| r.first())
                .is_some_and(Value::is_array);
            let rows: Vec<Vec<Vec<f64>>> = if nested {
                v.as_array()
                    .into_iter()
                    .flatten()
                    .map(|r| points(r, &what))
                    .collect::<anyhow::Result<_>>()?
            } else {
                let flat = points(v, &what)?;
                anyhow::ensure!(
                    flat.len().is_multiple_of(m),
                    "{what}: {} points do not fill rows of {m} (the grid is N×{m}, row-major)",
                    flat.len()
                );
                flat.chunks(m).map(<[Vec<f64>]>::to_vec).collect()
            };
            Model::Surface(SurfaceIfs::new(s.s.clone(), s.t.clone(), &rows)?)
        }
    })
}

fn apply_move(model: &mut Model, spec: &str) -> anyhow::Result<()> {
    let (idx, to) = spec
        .split_once('=')
        .with_context(|| format!("--move {spec:?}: expected I=x,y[,z] or I,J=x,y,z"))?;
    let idx: Vec<usize> = idx
        .split(',')
        .map(|x| {
            x.trim()
                .parse()
                .with_context(|| format!("--move {spec:?}: {x:?} is not an index"))
        })
        .collect::<anyhow::Result<_>>()?;
    let v = parse_numbers(to, &format!("--move {spec:?}"))?;
    anyhow::ensure!(
        (2..=3).contains(&v.len()),
        "--move {spec:?}: a point has 2 or 3 coordinates"
    );
    let p = [v[0], v[1], v.get(2).copied().unwrap_or(0.0)];
    match (model, idx.as_slice()) {
        (Model::Curve(c), [i]) => c.move_point(*i, p)?,
        (Model::Surface(s), [a, b]) => {
            anyhow::ensure!(v.len() == 3, "--move {spec:?}: surface points are x,y,z");
            s.move_point(*a, *b, p)?;
        }
        (Model::Curve(_), _) => anyhow::bail!("--move {spec:?}: a curve point is I=x,y[,z]"),
        (Model::Surface(_), _) => anyhow::bail!("--move {spec:?}: a surface point is I,J=x,y,z"),
    }
    Ok(())
}

pub fn load(a: &IfsModelArgs) -> anyhow::Result<Loaded> {
    let p = params(&a.params);
    let (name, file) = match (&a.preset, &a.ifs) {
        (Some(name), _) => (name.clone(), preset(name, &p)?),
        (None, Some(path)) => {
            anyhow::ensure!(
                p == PresetParams::default(),
                "--w, --degree and --height apply to presets; edit the model file instead"
            );
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            let f = ModelFile::from_json(&text).with_context(|| path.display().to_string())?;
            (f.name.clone(), f)
        }
        (None, None) => anyhow::bail!("give --preset NAME or --ifs FILE"),
    };
    let mut model = file.build().with_context(|| format!("model {name}"))?;
    if let Some(path) = &a.control {
        let v = read_control(path)?;
        model = apply_control(model, &v, path)?;
    }
    for m in &a.moves {
        apply_move(&mut model, m)?;
    }
    Ok(Loaded {
        name,
        model,
        opts: FamilyOptions {
            dyadic_depth: a.family_depth,
            period: a.family_period,
        },
    })
}

fn want_curve(l: Loaded) -> anyhow::Result<(String, CurveIfs, FamilyOptions)> {
    match l.model {
        Model::Curve(c) => Ok((l.name, c, l.opts)),
        Model::Surface(_) => anyhow::bail!(
            "{} is a surface; use `asperity ifs surface` / `ifs sdcf` (curves: bezier-quadratic, bezier-cubic, bezier, takagi-landsberg)",
            l.name
        ),
    }
}

/// A surface model; a 2-D curve model becomes its tensor square
/// (z ≈ h(f(s) + f(t)), see `asperity_ifs::model::tensor_square`).
fn want_surface(
    l: Loaded,
    p: &IfsPresetParams,
) -> anyhow::Result<(String, SurfaceIfs, FamilyOptions)> {
    match l.model {
        Model::Surface(s) => Ok((l.name, s, l.opts)),
        Model::Curve(c) => {
            let h = p.height.unwrap_or(0.25);
            let s = tensor_square(&c, h, TAKAGI_SHEAR).with_context(|| {
                format!(
                    "{} is a curve and cannot be squared into a surface (surfaces: bezier-bicubic, takagi-landsberg-surface, bezier-takagi)",
                    l.name
                )
            })?;
            Ok((format!("{} ⊗ {}", l.name, l.name), s, l.opts))
        }
    }
}

fn output(ctx: &Context, example: &str) -> anyhow::Result<PathBuf> {
    ctx.output
        .clone()
        .with_context(|| format!("no output file: give -o FILE (e.g. -o {example})"))
}

fn ext(p: &Path) -> String {
    p.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}

fn presets(ctx: &Context) -> anyhow::Result<()> {
    if ctx.json {
        let v: Vec<Value> = preset_names()
            .iter()
            .map(|(n, d)| {
                let kind = match preset(n, &PresetParams::default()).map(|f| f.surface.is_some()) {
                    Ok(true) => "surface",
                    _ => "curve",
                };
                json!({"name": n, "kind": kind, "description": d})
            })
            .collect();
        outln!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    for (n, d) in preset_names() {
        outln!("{n:<26} {d}");
    }
    Ok(())
}

fn write_preset(ctx: &Context, a: &IfsPresetArgs) -> anyhow::Result<()> {
    let f = preset(&a.name, &params(&a.params))?;
    let text = f.to_json();
    match &ctx.output {
        Some(path) => {
            asperity_io::write_text(path, &text)?;
            let mut r = Report::new("ifs preset", ctx);
            r.output(path);
            ctx.note(format!("wrote {}", path.display()));
            r.finish(ctx)
        }
        None => {
            out!("{text}");
            Ok(())
        }
    }
}

/// Writes polylines alone as OBJ `l` / PLY `edge` elements.
fn write_lines(path: &Path, lines: &[Vec<[f64; 3]>]) -> anyhow::Result<()> {
    let empty = TriMesh::new(Vec::new(), Vec::new())?;
    asperity_io::write_mesh_with_polylines(path, &empty, lines, &WriteOptions::default())
        .with_context(|| format!("writing {}", path.display()))
}

const T0_COLOR: [u8; 3] = [214, 39, 40];
const T1_COLOR: [u8; 3] = [31, 119, 180];

fn lighter(c: [u8; 3]) -> [u8; 3] {
    c.map(|x| (x as u32 + 2 * 255).div_euclid(3) as u8)
}

/// The paper's Figure 2: the attractor (black) with, for each operator, members of
/// its family of DCFs (light) and the lower/upper bound members (bold).
pub fn figure(
    c: &CurveIfs,
    an: &DirectionAnalysis,
    name: &str,
    family: usize,
    highlight: Option<(usize, &[[f64; 3]])>,
) -> anyhow::Result<String> {
    let xy = |p: &[[f64; 3]]| p.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>();
    let mut strokes = vec![Stroke {
        points: xy(&c.attractor(12)?),
        color: [0, 0, 0],
        width: 2,
        label: Some(format!("attractor ({name})")),
    }];
    for a in &an.operators {
        let color = if a.operator == 0 { T0_COLOR } else { T1_COLOR };
        let Some(d) = &a.dcf else { continue };
        let len = d.members.len();
        if len == 0 {
            continue;
        }
        let k = family.min(len);
        for j in 0..k {
            let m = &d.members[j * (len - 1) / (k - 1).max(1)];
            strokes.push(Stroke {
                points: xy(&dcf_polyline(c, a, &m.point, 200)?),
                color: lighter(color),
                width: 1,
                label: (j == 0)
                    .then(|| format!("family of DCF(T{}) ({})", a.operator, a.class.name())),
            });
        }
        for (m, which) in [(d.lower(), "lower"), (d.upper(), "upper")] {
            if let Some(m) = m {
                strokes.push(Stroke {
                    points: xy(&dcf_polyline(c, a, &m.point, 200)?),
                    color,
                    width: 2,
                    label: Some(format!(
                        "{which} bound of T{} (start s = {:.4}, c₂ = {:.4})",
                        a.operator, m.start, m.c2
                    )),
                });
            }
        }
    }
    if let Some((op, pts)) = highlight {
        strokes.push(Stroke {
            points: xy(pts),
            color: [44, 160, 44],
            width: 3,
            label: Some(format!("the requested DCF of T{op}")),
        });
    }
    Ok(drawing_svg(
        &Drawing {
            title: format!("{name}: attractor and families of DCFs"),
            strokes,
        },
        900,
        700,
    )?)
}

fn curve(ctx: &Context, a: &IfsCurveArgs) -> anyhow::Result<()> {
    let (name, c, opts) = want_curve(load(&a.model)?)?;
    let out = output(ctx, "curve.obj, curve.csv or curve.svg")?;
    let mut r = Report::new("ifs curve", ctx);
    let t = Instant::now();
    let pts = c.attractor(a.depth)?;
    r.measure("build_s", t.elapsed().as_secs_f64());
    match ext(&out).as_str() {
        "csv" => {
            let mut text = if c.dim() == 2 { "s,x,y\n" } else { "s,x,y,z\n" }.to_owned();
            let count = (pts.len() - 1) as f64;
            for (k, p) in pts.iter().enumerate() {
                let s = k as f64 / count;
                if c.dim() == 2 {
                    text += &format!("{s},{},{}\n", p[0], p[1]);
                } else {
                    text += &format!("{s},{},{},{}\n", p[0], p[1], p[2]);
                }
            }
            asperity_io::write_text(&out, &text)?;
        }
        "svg" => {
            let an = DirectionAnalysis::new(&c.pifs, &opts);
            asperity_io::write_text(&out, &figure(&c, &an, &name, 12, None)?)?;
        }
        "obj" | "ply" => write_lines(&out, std::slice::from_ref(&pts))?,
        e => anyhow::bail!(
            "{}: curves are written as .obj/.ply (lines), .csv or .svg, not .{e}",
            out.display()
        ),
    }
    r.output(&out);
    r.measure("points", pts.len());
    r.measure("depth", a.depth);
    ctx.note(format!(
        "{name}: {} attractor points written to {}",
        pts.len(),
        out.display()
    ));
    r.finish(ctx)
}

/// Grid lines of a surface's control net.
fn control_net(s: &SurfaceIfs) -> Vec<Vec<[f64; 3]>> {
    let (n, m) = s.grid_size();
    let p = s.control();
    let mut lines: Vec<Vec<[f64; 3]>> = (0..n).map(|a| p[a * m..(a + 1) * m].to_vec()).collect();
    lines.extend((0..m).map(|b| (0..n).map(|a| p[a * m + b]).collect()));
    lines
}

/// The attractor mesh with per-vertex pseudo-curvature when it is finite.
pub fn surface_mesh(
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    depth: u32,
    curvature: bool,
    budget: &asperity_core::MemoryBudget,
) -> anyhow::Result<(TriMesh, Option<String>, f64)> {
    let mut mesh = s.attractor_mesh(depth, budget)?;
    let mut note = None;
    let t = Instant::now();
    if curvature {
        let (an_s, an_t) = (
            DirectionAnalysis::new(&s.s, opts),
            DirectionAnalysis::new(&s.t, opts),
        );
        match vertex_curvature(s, &an_s, &an_t, depth) {
            Ok(attrs) => {
                for (name, v) in attrs {
                    mesh = mesh.with_scalar(name, v)?;
                }
            }
            Err(e) => note = Some(format!("no curvature attributes: {e}")),
        }
    }
    Ok((mesh, note, t.elapsed().as_secs_f64()))
}

fn surface(ctx: &Context, a: &IfsSurfaceArgs) -> anyhow::Result<()> {
    let (name, s, opts) = want_surface(load(&a.model)?, &a.model.params)?;
    let out = output(ctx, "attractor.ply")?;
    let f = Format::from_path(&out)?;
    anyhow::ensure!(
        f.info().mesh.can_write(),
        "{} cannot hold a mesh; use .ply, .obj, .stl or .glb",
        out.display()
    );
    let mut r = Report::new("ifs surface", ctx);
    let t = Instant::now();
    let (mesh, note, curvature_s) = surface_mesh(&s, &opts, a.depth, !a.no_curvature, &ctx.budget)?;
    r.measure("build_s", t.elapsed().as_secs_f64() - curvature_s);
    r.measure("curvature_s", curvature_s);
    if let Some(n) = &note {
        ctx.note(n);
        r.warnings.push(n.clone());
    }
    let t = Instant::now();
    asperity_io::write_mesh(&out, &mesh, &WriteOptions::default())
        .with_context(|| format!("writing {}", out.display()))?;
    r.measure("write_s", t.elapsed().as_secs_f64());
    r.output(&out);
    if let Some(net) = &a.control_net {
        write_lines(net, &control_net(&s))?;
        r.output(net);
    }
    r.measure("vertices", mesh.n_vertices());
    r.measure("triangles", mesh.n_faces());
    r.measure("depth", a.depth);
    r.measure(
        "attributes",
        mesh.scalars()
            .iter()
            .map(|s| s.name.clone())
            .collect::<Vec<_>>(),
    );
    ctx.note(format!(
        "{name}: {} vertices, {} triangles written to {}",
        mesh.n_vertices(),
        mesh.n_faces(),
        out.display()
    ));
    r.finish(ctx)
}

fn start(bound: Option<BoundArg>, param: f64) -> Start {
    match bound {
        Some(BoundArg::Lower) => Start::Lower,
        Some(BoundArg::Upper) => Start::Upper,
        None => Start::Parameter(param),
    }
}

fn dcf(ctx: &Context, a: &IfsDcfArgs) -> anyhow::Result<()> {
    let (name, c, opts) = want_curve(load(&a.model)?)?;
    let out = output(ctx, "dcf.svg, dcf.csv or dcf.obj")?;
    let an = DirectionAnalysis::new(&c.pifs, &opts);
    let i = a.operator as usize;
    let op = &an.operators[i];
    let s0 = a.start.unwrap_or(1.0 - i as f64);
    let q = start_point(&c.pifs, op, start(a.bound, s0))?;
    let pts = dcf_polyline(&c, op, &q, a.samples)?;
    match ext(&out).as_str() {
        "csv" => {
            let mut text = "t,x,y,z\n".to_owned();
            for (j, p) in pts.iter().enumerate() {
                let t = j as f64 / a.samples as f64;
                text += &format!("{t},{},{},{}\n", p[0], p[1], p[2]);
            }
            asperity_io::write_text(&out, &text)?;
        }
        "svg" => {
            let svg = figure(&c, &an, &name, a.family, Some((i, &pts)))?;
            asperity_io::write_text(&out, &svg)?;
        }
        "obj" | "ply" => write_lines(&out, std::slice::from_ref(&pts))?,
        e => anyhow::bail!(
            "{}: a DCF is written as .svg, .csv or .obj/.ply (a polyline), not .{e}",
            out.display()
        ),
    }
    let mut r = Report::new("ifs dcf", ctx);
    r.output(&out);
    r.measure("operator", i);
    r.measure("class", op.class.name());
    r.measure("alpha", op.dcf.as_ref().map(|d| d.alpha.clone()));
    r.measure("samples", a.samples);
    ctx.note(format!(
        "DCF of T{i} ({}) written to {}",
        op.class.name(),
        out.display()
    ));
    r.finish(ctx)
}

fn pair<T: std::str::FromStr>(s: &str, what: &str) -> anyhow::Result<(T, T)> {
    let (a, b) = s
        .split_once(',')
        .with_context(|| format!("{what} {s:?}: expected two values A,B"))?;
    let p = |x: &str| {
        x.trim()
            .parse::<T>()
            .ok()
            .with_context(|| format!("{what} {s:?}: {x:?} is not valid"))
    };
    Ok((p(a)?, p(b)?))
}

/// Concatenates meshes, colouring each.
fn merge_colored(parts: &[(&TriMesh, [u8; 4])]) -> anyhow::Result<TriMesh> {
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    let mut colors = Vec::new();
    for (m, c) in parts {
        let base = pos.len() as u32;
        pos.extend_from_slice(m.positions());
        tris.extend(m.triangles().iter().map(|t| t.map(|v| v + base)));
        colors.extend(std::iter::repeat_n(*c, m.n_vertices()));
    }
    Ok(TriMesh::new(pos, tris)?
        .with_colors(colors)?
        .with_computed_normals())
}

/// SDCF mesh of 𝒯ᵢⱼ from the starting points `starts` (one per direction).
pub fn sdcf_for(
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    (i, j): (usize, usize),
    starts: (Start, Start),
    resolution: usize,
    budget: &asperity_core::MemoryBudget,
) -> anyhow::Result<TriMesh> {
    let (an_s, an_t) = (
        DirectionAnalysis::new(&s.s, opts),
        DirectionAnalysis::new(&s.t, opts),
    );
    let (a, b) = (&an_s.operators[i], &an_t.operators[j]);
    let q = start_point(&s.s, a, starts.0)?;
    let q2 = start_point(&s.t, b, starts.1)?;
    Ok(sdcf_mesh(s, (a, &q), (b, &q2), resolution, budget)?)
}

fn sdcf(ctx: &Context, a: &IfsSdcfArgs) -> anyhow::Result<()> {
    let (name, s, opts) = want_surface(load(&a.model)?, &a.model.params)?;
    let out = output(ctx, "sdcf.ply")?;
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
        mesh = merge_colored(&[(&att, [190, 190, 190, 255]), (&mesh, [40, 90, 220, 255])])?;
    }
    asperity_io::write_mesh(&out, &mesh, &WriteOptions::default())
        .with_context(|| format!("writing {}", out.display()))?;
    let mut r = Report::new("ifs sdcf", ctx);
    r.output(&out);
    r.measure("operator", [i, j]);
    r.measure("vertices", mesh.n_vertices());
    ctx.note(format!(
        "{name}: SDCF of T{i}⊗T'{j} written to {}",
        out.display()
    ));
    r.finish(ctx)
}

fn fmt_range(r: Option<[f64; 2]>) -> String {
    match r {
        Some([a, b]) if (a - b).abs() <= 1e-12 * a.abs().max(1.0) => format!("{a:.10}"),
        Some([a, b]) => format!("[{a:.10}, {b:.10}]"),
        None => "—".to_owned(),
    }
}

fn curvature(ctx: &Context, a: &IfsCurvatureArgs) -> anyhow::Result<()> {
    let l = load(&a.model)?;
    let t = Instant::now();
    let file = l.file();
    let mut doc = json!({
        "model": l.name,
        "family": {"dyadic_depth": l.opts.dyadic_depth, "period": l.opts.period},
    });
    match &l.model {
        Model::Curve(c) => {
            let an = DirectionAnalysis::new(&c.pifs, &l.opts);
            let ops = curve_report(c, &an);
            let at: Vec<_> =
                a.at.iter()
                    .map(|s| {
                        let s: f64 = s.trim().parse().with_context(|| {
                            format!("--at {s:?}: a curve point is one parameter S")
                        })?;
                        Ok(curve_at(c, &an, s)?)
                    })
                    .collect::<anyhow::Result<_>>()?;
            doc["kind"] = json!("curve");
            doc["control_points"] = json!(file.curve.as_ref().map(|c| &c.control_points));
            if !ctx.json {
                outln!("{} (curve, N = {})", l.name, c.pifs.size());
                outln!(
                    "{:<4} {:<8} {:<20} {:<28} curvature",
                    "op",
                    "s",
                    "class",
                    "alpha"
                );
                for o in &ops {
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
                for p in &at {
                    for sd in &p.sides {
                        outln!(
                            "at s = {} ({}, T{} via {}): {} {}",
                            p.at,
                            sd.side,
                            sd.operator,
                            if sd.word.is_empty() { "—" } else { &sd.word },
                            sd.class,
                            fmt_range(sd.curvature)
                        );
                    }
                }
            }
            doc["operators"] = serde_json::to_value(&ops)?;
            doc["at"] = serde_json::to_value(&at)?;
        }
        Model::Surface(s) => {
            let (an_s, an_t) = (
                DirectionAnalysis::new(&s.s, &l.opts),
                DirectionAnalysis::new(&s.t, &l.opts),
            );
            let ops = surface_report(s, &an_s, &an_t);
            let at: Vec<_> =
                a.at.iter()
                    .map(|v| {
                        let (u, w): (f64, f64) = pair(v, "--at")?;
                        Ok(surface_at(s, &an_s, &an_t, u, w)?)
                    })
                    .collect::<anyhow::Result<_>>()?;
            doc["kind"] = json!("surface");
            doc["control_points"] = json!(file.surface.as_ref().map(|s| &s.control_points));
            if !ctx.json {
                let (n, m) = s.grid_size();
                outln!("{} (tensor-product surface, {n}×{m} control grid)", l.name);
                outln!(
                    "{:<8} {:<10} {:<12} {:<36} mean",
                    "op",
                    "(s,t)",
                    "class",
                    "gaussian"
                );
                for o in &ops {
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
                for p in &at {
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
            doc["operators"] = serde_json::to_value(&ops)?;
            doc["at"] = serde_json::to_value(&at)?;
        }
    }
    doc["seconds"] = json!(t.elapsed().as_secs_f64());
    if ctx.json {
        outln!("{}", serde_json::to_string_pretty(&doc)?);
    }
    Ok(())
}
