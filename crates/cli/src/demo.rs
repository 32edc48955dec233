//! `asperity demo`: every available method on small built-in defaults, written
//! into a gallery directory with an `index.html`.
//!
//! Each method family contributes one [`Section`] through a function in
//! [`SECTIONS`]; a new method issue adds its function there. Sections write their
//! files through [`Env::write`], which records them for the page and the report.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Context as _;
use asperity_core::fourier_surface::{FourierParams, fourier_surface};
use asperity_core::{Diagonal, HeightField, Progress, RgbaImage, TriMesh};
use asperity_io::{Surface, WriteOptions};

use crate::cli::{Context, DemoArgs};
use crate::progress::Bar;
use crate::report::Report;

/// What a section function gets.
pub struct Env<'a> {
    pub dir: PathBuf,
    pub ctx: &'a Context,
    pub quick: bool,
    pub report: std::cell::RefCell<Report>,
}

impl Env<'_> {
    /// Writes `s` as `name` in the gallery and records it.
    pub fn write(&self, name: &str, s: &Surface, opts: &WriteOptions) -> anyhow::Result<String> {
        let path = self.dir.join(name);
        asperity_io::write(&path, s, opts)?;
        self.report.borrow_mut().output(&path);
        Ok(name.to_owned())
    }

    /// Writes an RGBA picture as PNG (atomically) and records it.
    pub fn picture(&self, name: &str, img: &RgbaImage) -> anyhow::Result<String> {
        let path = self.dir.join(name);
        asperity_io::write_png(&path, img)?;
        self.report.borrow_mut().output(&path);
        Ok(name.to_owned())
    }
}

/// One card in the gallery.
pub struct Item {
    pub title: String,
    pub image: Option<String>,
    pub files: Vec<String>,
    pub facts: Vec<(String, String)>,
}

/// One method family's part of the gallery.
pub struct Section {
    pub title: String,
    pub source: String,
    pub blurb: String,
    pub items: Vec<Item>,
}

type SectionFn = fn(&Env) -> anyhow::Result<Section>;

/// The gallery, in page order. Method issues add their section here.
const SECTIONS: &[(&str, SectionFn)] = &[("foundation", foundation)];

pub fn run(ctx: &Context, a: &DemoArgs) -> anyhow::Result<()> {
    let dir = a
        .out
        .clone()
        .or_else(|| ctx.output.clone())
        .unwrap_or_else(|| PathBuf::from("gallery"));
    std::fs::create_dir_all(&dir)
        .with_context(|| format!("cannot create gallery directory {}", dir.display()))?;
    let env = Env {
        dir: dir.clone(),
        ctx,
        quick: a.quick,
        report: std::cell::RefCell::new(Report::new("demo", ctx)),
    };
    let bar = Bar::new(ctx.quiet || ctx.json);
    bar.start(SECTIONS.len() as u64, "demo");
    let mut sections = Vec::new();
    for (name, f) in SECTIONS {
        let t = std::time::Instant::now();
        let s = f(&env).with_context(|| format!("demo section {name}"))?;
        env.report
            .borrow_mut()
            .measure(&format!("{name}_seconds"), t.elapsed().as_secs_f64());
        sections.push(s);
        bar.advance(1);
    }
    bar.finish();
    let index = dir.join("index.html");
    let html = page(&sections, ctx.seed, a.quick);
    asperity_io::write_atomic(&index, |w| {
        std::io::Write::write_all(w, html.as_bytes()).map_err(|source| asperity_io::IoError::Os {
            path: index.clone(),
            source,
        })
    })?;
    let mut report = env.report.into_inner();
    report.output(&index);
    report.measure(
        "sections",
        sections.iter().map(|s| s.title.clone()).collect::<Vec<_>>(),
    );
    let json = serde_json::to_string_pretty(&report)?;
    let report_path = dir.join("report.json");
    asperity_io::write_atomic(&report_path, |w| {
        std::io::Write::write_all(w, json.as_bytes()).map_err(|source| asperity_io::IoError::Os {
            path: report_path.clone(),
            source,
        })
    })?;
    ctx.note(format!("gallery written to {}", index.display()));
    report.finish(ctx)
}

/// Perceptually ordered colour map (control points of matplotlib's viridis),
/// for previews until the renderer provides shaded views.
pub fn viridis(t: f64) -> [u8; 4] {
    const C: [[f64; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let k = (t.floor() as usize).min(3);
    let f = t - k as f64;
    let c = |a: usize| (C[k][a] + f * (C[k + 1][a] - C[k][a])).round() as u8;
    [c(0), c(1), c(2), 255]
}

fn height_colors(h: &HeightField) -> (Vec<[u8; 4]>, RgbaImage) {
    let (lo, hi) = h.min_max();
    let span = if hi > lo { hi - lo } else { 1.0 };
    let colors: Vec<[u8; 4]> = h.data().iter().map(|z| viridis((z - lo) / span)).collect();
    let pixels = colors.iter().flatten().copied().collect();
    let img = RgbaImage::from_pixels(h.nx() as u32, h.ny() as u32, pixels)
        .expect("one colour per sample");
    (colors, img)
}

fn torus(major: f64, minor: f64, nu: usize, nv: usize) -> TriMesh {
    let tau = std::f64::consts::TAU;
    let mut p = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (u, v) = (tau * i as f64 / nu as f64, tau * j as f64 / nv as f64);
            p.push([
                (major + minor * v.cos()) * u.cos(),
                (major + minor * v.cos()) * u.sin(),
                minor * v.sin(),
            ]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let t = (0..nu)
        .flat_map(|i| {
            (0..nv).flat_map(move |j| {
                [
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                    [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
                ]
            })
        })
        .collect();
    TriMesh::new(p, t)
        .expect("indices in range")
        .with_computed_normals()
}

fn fact(k: &str, v: impl std::fmt::Display) -> (String, String) {
    (k.to_owned(), v.to_string())
}

/// The foundation section: the shared types and every file format, on a built-in
/// sample surface (not a paper's method; see `synth`).
fn foundation(env: &Env) -> anyhow::Result<Section> {
    let n = if env.quick { 65 } else { 257 };
    let params = FourierParams {
        n,
        hurst: 0.8,
        modes: n / 8,
        rms: 0.05,
        spacing: 1.0 / (n - 1) as f64,
    };
    let h = fourier_surface(&params, env.ctx.seed, &env.ctx.budget)?;
    let (colors, img) = height_colors(&h);
    let opts = WriteOptions::default();
    let mut items = Vec::new();

    let preview = env.picture("sample_height_colors.png", &img)?;
    let mut files = Vec::new();
    for name in [
        "sample_height.png",
        "sample_height.npy",
        "sample_height.exr",
        "sample_height.gsf",
        "sample_height.csv",
    ] {
        files.push(env.write(name, &Surface::Height(h.clone()), &opts)?);
    }
    let (lo, hi) = h.min_max();
    items.push(Item {
        title: format!("Sample height field {n}×{n} (Fourier synthesis, H = 0.8)"),
        image: Some(preview),
        files,
        facts: vec![
            fact("samples", format!("{n} × {n}")),
            fact("spacing", format!("{:.5}", h.spacing()[0])),
            fact("height range", format!("{lo:.4} … {hi:.4}")),
            fact("rms height", "0.05"),
            fact("seed", env.ctx.seed),
        ],
    });

    let mesh = h
        .to_trimesh(Diagonal::Alternating)?
        .with_computed_normals()
        .with_colors(colors)?
        .with_scalar("height", h.data().to_vec())?
        .with_texture(img);
    let mut files = Vec::new();
    for name in [
        "sample_mesh.ply",
        "sample_mesh.obj",
        "sample_mesh.glb",
        "sample_mesh.stl",
    ] {
        files.push(env.write(name, &Surface::Mesh(mesh.clone()), &opts)?);
    }
    files.push(env.write(
        "sample_points.xyz",
        &Surface::Points(h.to_point_set()),
        &opts,
    )?);
    items.push(Item {
        title: "The same surface as a mesh (alternating diagonals)".into(),
        image: Some("sample_height.png".into()),
        files,
        facts: vec![
            fact("vertices", mesh.n_vertices()),
            fact("triangles", mesh.n_faces()),
            fact("Euler characteristic", mesh.euler_characteristic()),
            fact("boundary loops", mesh.boundary_loops().len()),
            fact("area", format!("{:.5}", mesh.area())),
            fact(
                "attributes",
                "normals, colours, UVs + texture, scalar 'height'",
            ),
        ],
    });

    let t = torus(
        1.0,
        0.35,
        if env.quick { 24 } else { 64 },
        if env.quick { 12 } else { 32 },
    );
    let files = vec![
        env.write("torus.ply", &Surface::Mesh(t.clone()), &opts)?,
        env.write("torus.glb", &Surface::Mesh(t.clone()), &opts)?,
    ];
    items.push(Item {
        title: "Closed mesh: torus topology check".into(),
        image: None,
        files,
        facts: vec![
            fact("vertices", t.n_vertices()),
            fact("triangles", t.n_faces()),
            fact("Euler characteristic", t.euler_characteristic()),
            fact("genus", t.genus().map_or("n/a".into(), |g| g.to_string())),
            fact("watertight", t.is_watertight()),
            fact(
                "volume",
                format!(
                    "{:.4} (exact 2π²Rr² = {:.4})",
                    t.signed_volume(),
                    2.0 * std::f64::consts::PI.powi(2) * 0.35f64.powi(2)
                ),
            ),
        ],
    });
    env.report.borrow_mut().measure("sample_rms", 0.05);
    Ok(Section {
        title: "Foundation: shared types and file formats".into(),
        source: "asperity-core, asperity-io".into(),
        blurb: "A built-in self-affine test surface written in every height-field, mesh and point format asperity supports. \
                Open the .gsf in Gwyddion, the .ply/.obj/.glb in Blender or MeshLab, the .npy with numpy.load. \
                Shaded 3D views arrive with the renderer."
            .into(),
        items,
    })
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn page(sections: &[Section], seed: u64, quick: bool) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>asperity gallery</title>\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>\
body{{font-family:system-ui,sans-serif;margin:2rem auto;max-width:1100px;padding:0 1rem;color:#222}}\
h1{{margin-bottom:.2rem}} .meta{{color:#666}} section{{margin-top:2.5rem}}\
.cards{{display:grid;grid-template-columns:repeat(auto-fill,minmax(320px,1fr));gap:1rem}}\
.card{{border:1px solid #ddd;border-radius:8px;padding:1rem;background:#fafafa}}\
.card img{{width:100%;image-rendering:pixelated;border-radius:4px;background:#000}}\
table{{border-collapse:collapse;width:100%;font-size:.9rem}} td{{padding:2px 4px;border-bottom:1px solid #eee}}\
td:first-child{{color:#555}} .files a{{margin-right:.6rem;font-size:.9rem}}</style></head><body>\
<h1>asperity gallery</h1><p class=\"meta\">asperity {} · seed {seed}{} · <a href=\"report.json\">report.json</a></p>",
        env!("CARGO_PKG_VERSION"),
        if quick { " · quick sizes" } else { "" }
    );
    for s in sections {
        let _ = write!(
            h,
            "<section><h2>{}</h2><p class=\"meta\">{}</p><p>{}</p><div class=\"cards\">",
            esc(&s.title),
            esc(&s.source),
            esc(&s.blurb)
        );
        for it in &s.items {
            let _ = write!(h, "<div class=\"card\"><h3>{}</h3>", esc(&it.title));
            if let Some(img) = &it.image {
                let _ = write!(h, "<img src=\"{}\" alt=\"{}\">", esc(img), esc(&it.title));
            }
            h += "<table>";
            for (k, v) in &it.facts {
                let _ = write!(h, "<tr><td>{}</td><td>{}</td></tr>", esc(k), esc(v));
            }
            h += "</table><p class=\"files\">";
            for f in &it.files {
                let _ = write!(h, "<a href=\"{0}\">{0}</a>", esc(f));
            }
            h += "</p></div>";
        }
        h += "</div></section>";
    }
    h += "</body></html>\n";
    h
}
