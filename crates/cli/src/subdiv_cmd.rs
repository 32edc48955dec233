//! `asperity subdiv`: Catmull–Clark multiresolution surfaces with procedural
//! detail (velho-perlin; library: `asperity-subdiv`) — from options or from a
//! scene file, with animation frames and detail export/re-apply.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use asperity_core::{PolyMesh, TriMesh};
use asperity_io::{Format, WriteOptions};
use asperity_subdiv::base;
use asperity_subdiv::catmull_clark::{Boundary, Creased, limit_normals};
use asperity_subdiv::evaluate::{Captured, Composed, Inputs, evaluate};
use asperity_subdiv::multires::synthesize;
use asperity_subdiv::scene::{Mode, Scene, feature_from_spec, parse};

use asperity_core::Progress as _;

use crate::cli::{BoundaryArg, Context, SubdivArgs};
use crate::progress::Bar;
use crate::report::Report;

/// A built-in base by name, or a mesh file (relative to `dir`).
pub fn load_base(spec: &str, dir: &Path) -> anyhow::Result<PolyMesh> {
    Ok(match spec {
        "cube" => base::cube(),
        "sphere" => base::quad_sphere(2),
        "torus" => base::torus(1.0, 0.35, 16, 8),
        "cylinder" => base::cylinder(0.6, 1.0, 8),
        "plane" => base::plane(4),
        "fuse" => base::fuse(24, 10),
        spec if spec.starts_with("revolution:") => {
            let p = dir.join(&spec["revolution:".len()..]);
            base::revolution(&read_profile(&p)?, 16)
        }
        path => {
            let p = dir.join(path);
            asperity_io::read_poly_mesh(&p).with_context(|| {
                format!(
                    "reading the base mesh {} (or use cube, sphere, torus, cylinder, plane, fuse)",
                    p.display()
                )
            })?
        }
    })
}

/// A profile for a surface of revolution: one `r z` pair per line (white
/// space or commas), bottom to top, every r > 0; `#` starts a comment.
fn read_profile(path: &Path) -> anyhow::Result<Vec<[f64; 2]>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading the profile {}", path.display()))?;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .map(str::parse)
            .collect::<Result<_, _>>()
            .ok()
            .filter(|v: &Vec<f64>| v.len() == 2 && v.iter().all(|x| x.is_finite()) && v[0] > 0.0)
            .with_context(|| {
                format!(
                    "{} line {}: expected `r z` with r > 0, got {line:?}",
                    path.display(),
                    i + 1
                )
            })?;
        out.push([v[0], v[1]]);
    }
    anyhow::ensure!(
        out.len() >= 2,
        "{}: a profile needs at least two `r z` rows",
        path.display()
    );
    Ok(out)
}

/// `A-B:S` crease tags.
fn parse_crease(spec: &str) -> anyhow::Result<(u32, u32, f64)> {
    let err = || format!("--crease {spec:?}: expected A-B:SHARPNESS, e.g. 0-1:2 or 0-1:inf");
    let (edge, s) = spec.split_once(':').with_context(err)?;
    let (a, b) = edge.split_once('-').with_context(err)?;
    let s: f64 = s.trim().parse().ok().with_context(err)?;
    Ok((
        a.trim().parse().ok().with_context(err)?,
        b.trim().parse().ok().with_context(err)?,
        s,
    ))
}

fn with_creases(mesh: PolyMesh, creases: &[(u32, u32, f64)]) -> anyhow::Result<Creased> {
    let mut c = Creased::smooth(mesh);
    let n = c.mesh.n_vertices() as u32;
    let edges: std::collections::HashSet<(u32, u32)> = c
        .mesh
        .faces()
        .flat_map(|f| {
            (0..f.len()).map(move |k| {
                let (a, b) = (f[k], f[(k + 1) % f.len()]);
                (a.min(b), a.max(b))
            })
        })
        .collect();
    for &(a, b, s) in creases {
        anyhow::ensure!(a < n && b < n, "crease {a}-{b}: the base has {n} vertices");
        anyhow::ensure!(
            edges.contains(&(a.min(b), a.max(b))),
            "crease {a}-{b}: not an edge of the base"
        );
        anyhow::ensure!(s >= 0.0, "crease {a}-{b}: sharpness {s} is negative");
        c.creases.insert((a.min(b), a.max(b)), s);
    }
    Ok(c)
}

/// The scene from the options (no scene file).
fn scene_from_args(a: &SubdivArgs, ctx: &Context, t: f64) -> anyhow::Result<Scene> {
    let mut features = Vec::new();
    for d in &a.detail {
        features.push(feature_from_spec(d, t).map_err(|e| anyhow::anyhow!(e))?);
    }
    Ok(Scene {
        base: a.base.clone(),
        levels: a.levels as usize,
        seed: ctx.seed,
        boundary: match a.boundary {
            BoundaryArg::EdgeOnly => Boundary::EdgeOnly,
            BoundaryArg::EdgeAndCorner => Boundary::EdgeAndCorner,
        },
        limit: a.limit,
        layers: vec![asperity_subdiv::compose::Layer {
            name: "main".into(),
            features,
            edits: Vec::new(),
        }],
        blend: None,
        alpha_map: None,
        mode: Mode::Displace,
        creases: a
            .crease
            .iter()
            .map(|c| parse_crease(c))
            .collect::<anyhow::Result<_>>()?,
        surfaces: Vec::new(),
    })
}

/// Reads an alpha map: one number in [0, 1] per base vertex, separated by
/// white space or commas (a text or CSV column).
fn read_alpha_map(path: &Path) -> anyhow::Result<Vec<f64>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading the alpha map {}", path.display()))?;
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f64>()
                .with_context(|| format!("alpha map {}: {s:?} is not a number", path.display()))
        })
        .collect()
}

/// The output mesh: triangulated, with limit or computed normals, colours and scalars.
fn to_trimesh(c: &Composed, scene: &Scene) -> anyhow::Result<TriMesh> {
    let mut tri = c.mesh.mesh.triangulate();
    tri = if scene.limit && scene.levels > 0 {
        tri.with_normals(limit_normals(&c.mesh, scene.boundary)?)?
    } else {
        tri.with_computed_normals()
    };
    if let Some(col) = &c.colors {
        tri = tri.with_colors(col.clone())?;
    }
    for (name, v) in &c.scalars {
        tri = tri.with_scalar(name, v.clone())?;
    }
    Ok(tri)
}

fn frame_path(out: &Path, i: u32) -> PathBuf {
    let stem = out.file_stem().and_then(|s| s.to_str()).unwrap_or("frame");
    let ext = out.extension().and_then(|s| s.to_str()).unwrap_or("ply");
    out.with_file_name(format!("{stem}_{i:04}.{ext}"))
}

/// Exported details: enough to check they fit the base they are applied to.
#[derive(serde::Serialize, serde::Deserialize)]
struct DetailFile {
    format: String,
    base_vertices: usize,
    base_faces: usize,
    levels: usize,
    /// Per level, per vertex (t₁, t₂, n) components; empty = none.
    details: Vec<Vec<[f64; 3]>>,
}

pub fn run(ctx: &Context, a: &SubdivArgs) -> anyhow::Result<()> {
    let out = ctx
        .output
        .clone()
        .context("no output file: give -o FILE (e.g. -o rock.ply)")?;
    anyhow::ensure!(
        Format::from_path(&out)?.info().mesh.can_write(),
        "{} cannot hold a mesh; use .ply, .obj, .stl or .glb",
        out.display()
    );
    anyhow::ensure!(
        (0.0..=1.0).contains(&a.time),
        "--time {} is outside [0, 1]",
        a.time
    );
    let scene_text = match &a.scene {
        Some(p) => Some(
            std::fs::read_to_string(p)
                .with_context(|| format!("reading the scene {}", p.display()))?,
        ),
        None => None,
    };
    let dir = a
        .scene
        .as_ref()
        .and_then(|p| p.parent())
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let scene_at = |t: f64| -> anyhow::Result<Scene> {
        match &scene_text {
            Some(text) => {
                let mut sc = parse(text, t).map_err(|e| {
                    anyhow::anyhow!(
                        "{}: {e}",
                        a.scene.as_deref().unwrap_or(Path::new("")).display()
                    )
                })?;
                sc.limit |= a.limit;
                Ok(sc)
            }
            None => scene_from_args(a, ctx, t),
        }
    };
    let first = scene_at(a.time)?;
    let base_mesh = load_base(&first.base, &dir)?;
    let base = with_creases(base_mesh, &first.creases)?;
    let levels = first.levels;
    anyhow::ensure!(levels <= 10, "levels = {levels}: at most 10");
    // Quads after level k: Σ|f| · 4^(k−1); refuse before allocating.
    let corners: u128 = base.mesh.faces().map(|f| f.len() as u128).sum();
    let quads = if levels == 0 {
        base.mesh.n_faces() as u128
    } else {
        corners << (2 * (levels - 1))
    };
    ctx.budget.check_elements(
        quads,
        // Positions and details of two surfaces, topology, output triangles.
        3 * 24 + 4 * 16 + 2 * 12 + 48,
        "the subdivided mesh",
    )?;
    let mut inputs = Inputs {
        alpha_map: match &first.alpha_map {
            Some(p) => Some(read_alpha_map(&dir.join(p))?),
            None => None,
        },
        captured: Vec::new(),
    };
    for (layer, file) in &first.surfaces {
        let (b, details) = analyze_file(&dir.join(file), &base, &first)?;
        inputs.captured.push(Captured {
            layer: layer.clone(),
            base: b,
            details,
        });
    }
    let mut report = Report::new("subdiv", ctx);
    let frames = a.frames.unwrap_or(1);
    let bar = Bar::new(ctx.quiet || ctx.json);
    if frames > 1 {
        bar.start(u64::from(frames), "subdiv frames");
    }
    let mut last: Option<Composed> = None;
    let t0 = std::time::Instant::now();
    for i in 0..frames {
        let t = if a.frames.is_some() {
            if frames == 1 {
                0.0
            } else {
                f64::from(i) / f64::from(frames - 1)
            }
        } else {
            a.time
        };
        let scene = if i == 0 && a.frames.is_none() {
            first.clone()
        } else {
            scene_at(t)?
        };
        let composed = match (&a.apply_details, &a.analyze) {
            (Some(p), _) => apply_details(p, &base, &scene)?,
            (None, Some(p)) => analyze_fine(p, &base, &scene)?,
            (None, None) if frames == 1 => evaluate(&scene, &base, &inputs, &bar)?,
            (None, None) => evaluate(&scene, &base, &inputs, &asperity_core::NoProgress)?,
        };
        let tri = to_trimesh(&composed, &scene)?;
        let path = if a.frames.is_some() {
            frame_path(&out, i)
        } else {
            out.clone()
        };
        if a.triangles {
            asperity_io::write_mesh(&path, &tri, &WriteOptions::default())
        } else {
            asperity_io::write_poly_mesh(&path, &composed.mesh.mesh, &tri, &WriteOptions::default())
        }
        .with_context(|| format!("writing {}", path.display()))?;
        report.output(&path);
        if frames > 1 {
            bar.advance(1);
        }
        last = Some(composed);
    }
    bar.finish();
    report.measure("build_and_write_s", t0.elapsed().as_secs_f64());
    let composed = last.context("at least one frame")?;
    if let Some(p) = &a.export_details {
        let file = DetailFile {
            format: "asperity-subdiv-details-1".into(),
            base_vertices: base.mesh.n_vertices(),
            base_faces: base.mesh.n_faces(),
            levels,
            details: composed.details.clone(),
        };
        let text = serde_json::to_string(&file)?;
        asperity_io::write_text(p, &text).with_context(|| format!("writing {}", p.display()))?;
        report.output(p);
    }
    report.measure(
        "levels",
        composed
            .counts
            .iter()
            .map(|(v, f)| serde_json::json!({ "vertices": v, "faces": f }))
            .collect::<Vec<_>>(),
    );
    report.measure(
        "euler_characteristic",
        composed.mesh.mesh.euler_characteristic(),
    );
    ctx.note(format!(
        "{} levels: {} vertices, {} quads{}",
        levels,
        composed.mesh.mesh.n_vertices(),
        composed.mesh.mesh.n_faces(),
        if frames > 1 {
            format!(", {frames} frames")
        } else {
            String::new()
        }
    ));
    report.finish(ctx)
}

/// Analyses a fine mesh (connectivity: `scene.levels` subdivisions of `base`)
/// into base positions and details by quasi-interpolation.
fn analyze_file(
    path: &Path,
    base: &Creased,
    scene: &Scene,
) -> anyhow::Result<(Creased, asperity_subdiv::multires::Details)> {
    let fine = asperity_io::read_poly_mesh(path)
        .with_context(|| format!("reading the fine mesh {}", path.display()))?;
    let plain = synthesize(base, &[], scene.levels, scene.boundary)?;
    let expect = plain.last().context("levels")?;
    anyhow::ensure!(
        fine.n_vertices() == expect.mesh.n_vertices()
            && (fine.face_vertices() == expect.mesh.face_vertices()
                || fine.triangulate().triangles() == expect.mesh.triangulate().triangles()),
        "{}: its connectivity is not {} subdivisions of the base ({} vertices expected, {} found); write it with asperity subdiv (PLY) and edit positions only",
        path.display(),
        scene.levels,
        expect.mesh.n_vertices(),
        fine.n_vertices()
    );
    Ok(asperity_subdiv::multires::analyze(
        base,
        fine.positions(),
        scene.levels,
        scene.boundary,
    )?)
}

/// Analyses a fine mesh into `base` positions and details (quasi-interpolation).
fn analyze_fine(path: &Path, base: &Creased, scene: &Scene) -> anyhow::Result<Composed> {
    let (coarse, details) = analyze_file(path, base, scene)?;
    synthesized(&coarse, details, scene.levels, scene.boundary)
}

/// The surface of `base` with `details` applied, as a composition.
fn synthesized(
    base: &Creased,
    details: asperity_subdiv::multires::Details,
    levels: usize,
    boundary: Boundary,
) -> anyhow::Result<Composed> {
    let all = synthesize(base, &details, levels, boundary)?;
    let counts = all
        .iter()
        .map(|l| (l.mesh.n_vertices(), l.mesh.n_faces()))
        .collect();
    Ok(Composed {
        mesh: all.last().context("levels")?.clone(),
        colors: None,
        scalars: Vec::new(),
        details,
        counts,
    })
}

/// Re-applies exported details to `base` (which may have been edited).
fn apply_details(path: &Path, base: &Creased, scene: &Scene) -> anyhow::Result<Composed> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading the details {}", path.display()))?;
    let f: DetailFile = serde_json::from_str(&text)
        .with_context(|| format!("{} is not an asperity details file", path.display()))?;
    anyhow::ensure!(
        f.format == "asperity-subdiv-details-1",
        "{}: unknown details format {:?}",
        path.display(),
        f.format
    );
    anyhow::ensure!(
        f.base_vertices == base.mesh.n_vertices() && f.base_faces == base.mesh.n_faces(),
        "{}: the details belong to a base of {} vertices and {} faces; this base has {} and {}",
        path.display(),
        f.base_vertices,
        f.base_faces,
        base.mesh.n_vertices(),
        base.mesh.n_faces()
    );
    synthesized(base, f.details, f.levels, scene.boundary)
}
