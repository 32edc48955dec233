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
use asperity_render::plot::histogram_svg;
use asperity_render::{
    ColorMap, Polyline, RenderOptions, Shader, View, hillshade, render_height, render_mesh,
    render_points,
};

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

    /// Render options for gallery pictures (smaller with `--quick`).
    pub fn view(&self) -> RenderOptions {
        let (w, h) = if self.quick { (400, 300) } else { (800, 600) };
        RenderOptions {
            width: w,
            height: h,
            budget: self.ctx.budget,
            ..RenderOptions::default()
        }
    }

    /// Writes an SVG document (a plot) and records it.
    pub fn svg(&self, name: &str, svg: &str) -> anyhow::Result<String> {
        let path = self.dir.join(name);
        asperity_io::write_text(&path, svg)?;
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

    /// Writes `STEM.ply` and a render of it in its vertex colours as `STEM.png`;
    /// returns (file, picture).
    pub fn colored_mesh(&self, stem: &str, m: &TriMesh) -> anyhow::Result<(String, String)> {
        let file = self.write(
            &format!("{stem}.ply"),
            &Surface::Mesh(m.clone()),
            &WriteOptions::default(),
        )?;
        let pic = self.picture(
            &format!("{stem}.png"),
            &render_mesh(
                m,
                &RenderOptions {
                    shader: Shader::VertexColor,
                    ..self.view()
                },
            )?,
        )?;
        Ok((file, pic))
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

/// Kim et al. §5–6: the two-pass pipeline (growth, then level-set reconstruction).
fn reconstruction(env: &Env) -> anyhow::Result<Section> {
    use asperity_growth::dla::{DlaParams, SeedShape, dla};
    use asperity_levelset::{ReconstructParams, Sizing, extract, reconstruct};
    use asperity_render::plot::{Plot, Series, Style, plot_svg};
    let budget = env.ctx.budget;
    let seed = env.ctx.seed;
    let none = asperity_core::NoProgress;
    let mut items = Vec::new();
    let mut movement = Vec::new();
    let opts = WriteOptions::default();

    // Fig. 8: RDSR on a sphere; Fig. 9: DLA from the plane.
    let (radius, layers) = if env.quick { (10.0, 5.0) } else { (20.0, 10.0) };
    let sphere = rdsr_sphere(radius, layers, env)?.points();
    let (side, particles) = if env.quick { (32, 1_500) } else { (64, 8_000) };
    let terrain = dla(
        &DlaParams {
            dim: 3,
            size: [side, side, side],
            particles,
            stick: 1.0,
            seed_shape: SeedShape::Plane,
            launch_gap: 2.0,
        },
        seed,
        0,
        &budget,
        &none,
    )?
    .points();
    let cases = [
        (
            "sphere",
            format!("Figure 8: RDSR on a sphere (radius {radius}, {layers} monolayers)"),
            sphere,
            format!(
                "asperity generate rdsr-sphere --radius {radius} --layers {layers} -o sphere.glb"
            ),
        ),
        (
            "terrain",
            format!(
                "Figures 9–10: DLA terrain with arches ({side}³ lattice, {particles} particles)"
            ),
            terrain,
            format!(
                "asperity generate dla-terrain --size {side}x{side}x{side} --particles {particles} -o terrain.glb"
            ),
        ),
    ];
    for (name, title, points, cli) in cases {
        let params = ReconstructParams {
            sizing: Sizing::Spacing(0.7),
            offset: Some(3.0),
            iterations: 60,
            extract: asperity_levelset::ExtractOptions {
                curvature: false,
                min_shell_triangles: 32,
            },
            ..Default::default()
        };
        let mut initial = None;
        let rec = reconstruct(&points, &params, &budget, &none, &mut |s, ls| {
            if s.step == 0 {
                initial = Some(extract(&ls.phi, &ls.grid, &params.extract).0);
            }
        })?;
        let initial = initial.context("the pipeline reports its initial surface")?;
        let m = &rec.mesh;
        let first = env.write(
            &format!("levelset_{name}_initial.ply"),
            &Surface::Mesh(initial.clone()),
            &opts,
        )?;
        let pic = env.picture(
            &format!("levelset_{name}_initial.png"),
            &render_mesh(&initial, &env.view())?,
        )?;
        items.push(Item {
            title: format!("{title}: initial surface by tagging (ε = 3)"),
            image: Some(pic),
            files: vec![first],
            facts: vec![
                fact(
                    "grid",
                    format!(
                        "{}×{}×{}, h = 0.7",
                        rec.grid.dims[0], rec.grid.dims[1], rec.grid.dims[2]
                    ),
                ),
                fact("triangles", initial.n_faces()),
            ],
        });
        let file = env.write(
            &format!("levelset_{name}.ply"),
            &Surface::Mesh(m.clone()),
            &opts,
        )?;
        let pic = env.picture(
            &format!("levelset_{name}.png"),
            &render_mesh(m, &env.view())?,
        )?;
        items.push(Item {
            title: format!(
                "{title}: after {} steps of the convection flow",
                rec.evolution.steps.len()
            ),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact("points", points.len()),
                fact("triangles", m.n_faces()),
                fact("watertight", m.is_watertight()),
                fact("genus", m.genus().map_or("—".into(), |g| g.to_string())),
                fact("pieces", rec.extraction.components),
                fact("CLI", cli),
            ],
        });
        movement.push((
            name,
            rec.evolution
                .steps
                .iter()
                .map(|s| (s.step as f64, s.front_movement.max(1e-6)))
                .collect::<Vec<_>>(),
        ));
    }
    let plot = Plot {
        title: "Front movement per step (mean |Δφ| near the front, cells)".into(),
        x_label: "step".into(),
        y_label: "cells per step".into(),
        log_x: false,
        log_y: true,
        series: movement
            .into_iter()
            .map(|(n, points)| Series {
                name: n.into(),
                points,
                style: Style::Line,
            })
            .collect(),
    };
    let svg = env.svg("levelset_movement.svg", &plot_svg(&plot, 800, 560)?)?;
    items.push(Item {
        title: "Convergence: the front stops on the data".into(),
        image: Some(svg),
        files: vec![],
        facts: vec![fact("checks", "crates/levelset/tests/reconstruction.rs")],
    });

    // §6: the convection flow keeps roughness that a curvature term removes.
    let n = if env.quick { 3_000 } else { 12_000 };
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut rng_state = seed ^ 0x9e37_79b9_7f4a_7c15;
    let rough: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            // A sphere with a deterministic bumpy radius.
            rng_state = rng_state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            let r = 1.0
                + 0.06 * (7.0 * t.sin() * s).sin() * (9.0 * z).cos()
                + 0.02 * ((rng_state >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
            [r * s * t.cos(), r * s * t.sin(), r * z]
        })
        .collect();
    for (flow, weight) in [("convection", None), ("regularized", Some(2.0))] {
        let params = ReconstructParams {
            sizing: Sizing::Resolution(if env.quick { 48 } else { 80 }),
            curvature_weight: weight,
            ..Default::default()
        };
        let rec = reconstruct(&rough, &params, &budget, &none, &mut |_, _| {})?;
        let file = env.write(
            &format!("levelset_flow_{flow}.ply"),
            &Surface::Mesh(rec.mesh.clone()),
            &opts,
        )?;
        let pic = env.picture(
            &format!("levelset_flow_{flow}.png"),
            &render_mesh(&rec.mesh, &env.view())?,
        )?;
        items.push(Item {
            title: format!("The {flow} flow on a bumpy sphere"),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact("area", format!("{:.4}", rec.mesh.area())),
                fact(
                    "CLI",
                    format!("asperity reconstruct pts.ply --flow {flow} -o mesh.ply"),
                ),
            ],
        });
    }

    Ok(Section {
        title: "Level-set reconstruction (kim-machiraju-thompson §5)".into(),
        source: "asperity-levelset — §5.2 Eqs. 6–12, Algorithm 1; §6 Figs. 7–11".into(),
        blurb: "Growth point sets become watertight surfaces of any genus: unsigned distance, an offset surface by \
                tagging, then the convection flow φ_t = d|∇φ| in a narrow band and marching cubes. The flow keeps the \
                roughness a curvature-regularised flow smooths away."
            .into(),
        items,
    })
}

/// An RDSR (Family) deposit of `layers` monolayers on a ball of `radius` cells
/// (kim-machiraju-thompson Fig. 8), shared by the growth and reconstruction sections.
fn rdsr_sphere(
    radius: f64,
    layers: f64,
    env: &Env,
) -> anyhow::Result<asperity_growth::curved::CurvedDeposit> {
    use asperity_growth::curved::{CurvedParams, CurvedSubstrate, deposit_curved};
    Ok(deposit_curved(
        &CurvedParams {
            model: asperity_growth::Model::Rdsr { radius: 1 },
            substrate: CurvedSubstrate::Sphere(radius),
            layers,
            samples_per_decade: 5,
        },
        env.ctx.seed,
        0,
        &env.ctx.budget,
        &asperity_core::NoProgress,
    )?)
}

/// poull-gentil: projected-IFS curves and surfaces, DCFs, SDCFs and pseudo-curvature.
fn ifs(env: &Env) -> anyhow::Result<Section> {
    use asperity_ifs::curvature::{curve_report, surface_report};
    use asperity_ifs::{DirectionAnalysis, FamilyOptions, Model, PresetParams, preset};
    let opts = FamilyOptions::default();
    let wo = WriteOptions::default();
    let load = |name: &str| -> anyhow::Result<Model> {
        Ok(preset(name, &PresetParams::default())?.build()?)
    };
    let fmt =
        |r: Option<[f64; 2]>| r.map_or("—".to_owned(), |[a, b]| format!("[{a:.6}, {b:.6}]"));
    let mut items = Vec::new();

    // Fig. 2: the Takagi–Landsberg curve (w = 1/√2) and its families of DCFs.
    let Model::Curve(curve) = load("takagi-landsberg")? else {
        anyhow::bail!("takagi-landsberg is a curve preset")
    };
    let an = DirectionAnalysis::new(&curve.pifs, &opts);
    let svg = crate::ifs_cmd::figure(&curve, &an, "Takagi–Landsberg w = 1/√2", 10, None)?;
    let fig = env.svg("ifs_takagi_dcf.svg", &svg)?;
    let rep = curve_report(&curve, &an);
    let json = env.svg(
        "ifs_takagi_curvature.json",
        &serde_json::to_string_pretty(&rep)?,
    )?;
    items.push(Item {
        title: "Takagi–Landsberg curve and its families of DCFs (Fig. 2)".into(),
        image: Some(fig),
        files: vec![json],
        facts: vec![
            fact("α (T0)", "0, 1, 2 — α₂ = 2: a finite range"),
            fact("curvature at s = 0", fmt(rep[0].curvature)),
            fact("closed form", "[−(6 − 4√2), −(102 − 72√2)]"),
            fact(
                "CLI",
                "asperity ifs dcf --preset takagi-landsberg --bound upper -o dcf.svg",
            ),
        ],
    });

    // Figs. 1/4: the Takagi ⊗ Takagi surface with per-vertex pseudo-curvature.
    let Model::Surface(surf) = load("takagi-landsberg-surface")? else {
        anyhow::bail!("takagi-landsberg-surface is a surface preset")
    };
    let depth = if env.quick { 6 } else { 8 };
    let (mesh, note, _) = crate::ifs_cmd::surface_mesh(&surf, &opts, depth, true, &env.ctx.budget)?;
    if let Some(n) = note {
        anyhow::bail!("{n}");
    }
    let file = env.write("ifs_takagi_surface.ply", &Surface::Mesh(mesh.clone()), &wo)?;
    let pic = env.picture("ifs_takagi_surface.png", &render_mesh(&mesh, &env.view())?)?;
    let (an_s, an_t) = (
        DirectionAnalysis::new(&surf.s, &opts),
        DirectionAnalysis::new(&surf.t, &opts),
    );
    let srep = surface_report(&surf, &an_s, &an_t);
    let sjson = env.svg(
        "ifs_takagi_surface_curvature.json",
        &serde_json::to_string_pretty(&srep)?,
    )?;
    items.push(Item {
        title: "Takagi ⊗ Takagi attractor (Figs. 1 and 4)".into(),
        image: Some(pic),
        files: vec![file, sjson],
        facts: vec![
            fact("vertices", mesh.n_vertices()),
            fact("depth", depth),
            fact("𝒦 at (0,0)", fmt(srep[0].gaussian)),
            fact("ℋ at (0,0)", fmt(srep[0].mean)),
            fact(
                "at every dyadic point",
                "the same ranges: for w = 1/√2 the maps preserve them (see the PLY attributes)",
            ),
            fact(
                "CLI",
                "asperity ifs surface --preset takagi-landsberg-surface --depth 8 -o t.ply",
            ),
        ],
    });

    // Fig. 4: the attractor with one SDCF of T0⊗T'0 (from the opposite corner).
    let sd = crate::ifs_cmd::sdcf_for(
        &surf,
        &opts,
        (0, 0),
        (
            asperity_ifs::sdcf::Start::Parameter(1.0),
            asperity_ifs::sdcf::Start::Parameter(1.0),
        ),
        if env.quick { 32 } else { 64 },
        &env.ctx.budget,
    )?;
    let att = surf.attractor_mesh(if env.quick { 5 } else { 6 }, &env.ctx.budget)?;
    let both = {
        let mut pos = att.positions().to_vec();
        let base = pos.len() as u32;
        pos.extend_from_slice(sd.positions());
        let mut tris = att.triangles().to_vec();
        tris.extend(sd.triangles().iter().map(|t| t.map(|v| v + base)));
        let mut cols = vec![[200, 200, 200, 255]; att.n_vertices()];
        cols.extend(std::iter::repeat_n([40, 90, 220, 255], sd.n_vertices()));
        TriMesh::new(pos, tris)?
            .with_colors(cols)?
            .with_computed_normals()
    };
    let (sfile, spic) = env.colored_mesh("ifs_sdcf", &both)?;
    items.push(Item {
        title: "An SDCF (blue) of T0⊗T′0 on the attractor (Fig. 4)".into(),
        image: Some(spic),
        files: vec![sfile],
        facts: vec![
            fact("start", "Q = c₁ ⊗ c′₁ (the opposite corner)"),
            fact(
                "CLI",
                "asperity ifs sdcf --preset takagi-landsberg-surface --with-attractor 6 -o sdcf.ply",
            ),
        ],
    });

    // A surface with a smooth and a rough direction, with its control net.
    let Model::Surface(mixed) = load("bezier-takagi")? else {
        anyhow::bail!("bezier-takagi is a surface preset")
    };
    let (mesh, note, _) = crate::ifs_cmd::surface_mesh(
        &mixed,
        &opts,
        if env.quick { 6 } else { 8 },
        true,
        &env.ctx.budget,
    )?;
    if let Some(n) = note {
        anyhow::bail!("{n}");
    }
    let (n, m) = mixed.grid_size();
    let p = mixed.control();
    let mut net: Vec<Polyline> = (0..n)
        .map(|a| Polyline {
            points: p[a * m..(a + 1) * m].to_vec(),
            color: [200, 40, 40, 255],
            closed: false,
        })
        .collect();
    net.extend((0..m).map(|b| Polyline {
        points: (0..n).map(|a| p[a * m + b]).collect(),
        color: [200, 40, 40, 255],
        closed: false,
    }));
    let mfile = env.write("ifs_bezier_takagi.ply", &Surface::Mesh(mesh.clone()), &wo)?;
    let mpic = env.picture(
        "ifs_bezier_takagi.png",
        &render_mesh(
            &mesh,
            &RenderOptions {
                polylines: net,
                shader: Shader::Curvature,
                scalar: Some("gaussian_max".into()),
                ..env.view()
            },
        )?,
    )?;
    let (a, b) = (
        DirectionAnalysis::new(&mixed.s, &opts),
        DirectionAnalysis::new(&mixed.t, &opts),
    );
    let mrep = surface_report(&mixed, &a, &b);
    items.push(Item {
        title: "Smooth along s (Bézier), rough along t (Takagi): Gaussian pseudo-curvature (max) and control net"
            .into(),
        image: Some(mpic),
        files: vec![mfile],
        facts: vec![
            fact("𝒦 at (0,0)", fmt(mrep[0].gaussian)),
            fact("CLI", "asperity ifs surface --preset bezier-takagi --control-net net.obj -o s.ply"),
        ],
    });

    Ok(Section {
        title: "Projected-IFS fractal surfaces and pseudo-curvature (poull-gentil)".into(),
        source: "asperity-ifs — §2 P-IFS and DCF, §3 SDCF, §4 ranges of pseudo-curvature".into(),
        blurb: "Self-similar curves and tensor-product surfaces from two barycentric operators per direction, \
                deformed by their control points. Each operator's DCF family gives the pseudo-curvature at its \
                fixed point — infinite, zero, or a finite range when α₂ = 2 — and the self-similarity carries \
                it to every dyadic point."
            .into(),
        items,
    })
}

/// velho-perlin: Catmull–Clark multiresolution surfaces with procedural detail.
fn subdivision(env: &Env) -> anyhow::Result<Section> {
    use asperity_subdiv::catmull_clark::{Boundary, Creased, limit_positions};
    use asperity_subdiv::multires::synthesize;
    let wo = WriteOptions::default();
    let mut items = Vec::new();
    // The cube and its limit surface, with the control cage.
    let cube = Creased::smooth(asperity_subdiv::base::cube());
    let levels = synthesize(&cube, &[], 4, Boundary::EdgeOnly)?;
    let fine = &levels[4];
    let limit = fine
        .mesh
        .clone()
        .with_positions(limit_positions(fine, Boundary::EdgeOnly)?)?;
    let tri = limit.triangulate().with_computed_normals();
    let cage: Vec<Polyline> = cube
        .mesh
        .faces()
        .map(|f| Polyline {
            points: f
                .iter()
                .map(|&v| cube.mesh.positions()[v as usize])
                .collect(),
            color: [200, 40, 40, 255],
            closed: true,
        })
        .collect();
    let file = env.write("subdiv_cube_limit.ply", &Surface::Mesh(tri.clone()), &wo)?;
    let pic = env.picture(
        "subdiv_cube_limit.png",
        &render_mesh(
            &tri,
            &RenderOptions {
                polylines: cage,
                ..env.view()
            },
        )?,
    )?;
    items.push(Item {
        title: "Catmull–Clark: the cube's limit surface (4 levels) inside its control cage".into(),
        image: Some(pic),
        files: vec![file],
        facts: vec![
            fact("corner after 1 / 2 levels", "5/9, 55/108 (exact, tested)"),
            fact(
                "CLI",
                "asperity subdiv --base cube --levels 4 --limit -o cube.ply",
            ),
        ],
    });
    // The example scenes (crates/subdiv/scenes), each as in the paper's figures.
    for (name, text, title) in SCENES {
        let mut scene =
            asperity_subdiv::scene::parse(text, if *name == "tentacle" { 0.15 } else { 0.0 })
                .map_err(|e| anyhow::anyhow!("scene {name}: {e}"))?;
        if env.quick {
            scene.levels = scene.levels.saturating_sub(1).max(2);
        }
        let base = Creased::smooth(crate::subdiv_cmd::load_base(
            &scene.base,
            std::path::Path::new(""),
        )?);
        let t = std::time::Instant::now();
        let c = asperity_subdiv::evaluate::evaluate(
            &scene,
            &base,
            &Default::default(),
            &asperity_core::NoProgress,
        )?;
        // Timings go to report.json (the gallery must not depend on them).
        env.report
            .borrow_mut()
            .measure(&format!("subdiv_{name}_seconds"), t.elapsed().as_secs_f64());
        let mut tri = c.mesh.mesh.triangulate().with_computed_normals();
        let n_vertices = tri.n_vertices();
        let alpha = c
            .scalars
            .iter()
            .find(|(n, _)| n == "alpha")
            .map(|(_, v)| v.clone());
        let (file, pic) = match (&c.colors, alpha) {
            (Some(col), _) => {
                env.colored_mesh(&format!("subdiv_{name}"), &tri.with_colors(col.clone())?)?
            }
            (None, Some(a)) => {
                // Blends: polished metal to rust by the blend weight.
                let col = a
                    .iter()
                    .map(|&t| {
                        let m = |x: f64, y: f64| (x + (y - x) * t) as u8;
                        [m(175.0, 140.0), m(180.0, 70.0), m(190.0, 30.0), 255]
                    })
                    .collect();
                tri = tri.with_scalar("alpha", a)?;
                env.colored_mesh(&format!("subdiv_{name}"), &tri.with_colors(col)?)?
            }
            (None, None) => {
                let file = env.write(
                    &format!("subdiv_{name}.ply"),
                    &Surface::Mesh(tri.clone()),
                    &wo,
                )?;
                let pic = env.picture(
                    &format!("subdiv_{name}.png"),
                    &render_mesh(&tri, &env.view())?,
                )?;
                (file, pic)
            }
        };
        items.push(Item {
            title: (*title).into(),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact("levels", scene.levels),
                fact("vertices", n_vertices),
                fact("quads", c.mesh.mesh.n_faces()),
                fact(
                    "CLI",
                    format!("asperity subdiv crates/subdiv/scenes/{name}.toml -o {name}.glb"),
                ),
            ],
        });
    }
    // Figure 5 (tentacle growth, levels 1–4) and Figure 9 (spurs at level 1, at
    // level 3, at both), each as a row of surfaces.
    {
        use asperity_subdiv::compose::{Layer, grow};
        use asperity_subdiv::detail::{Feature, Procedure, Seeds, Spur, Tentacle};
        let sphere = Creased::smooth(asperity_subdiv::base::quad_sphere(2));
        let tentacle = |alternate: bool| Layer {
            name: "t".into(),
            features: vec![Feature {
                procedure: Procedure::Tentacle(Tentacle {
                    length: 0.15,
                    theta: 0.5,
                    alternate,
                    twist: true,
                }),
                seeds: Seeds::Points(vec![[0.3, -1.0, 0.3]]),
                levels: None,
            }],
            edits: Vec::new(),
        };
        for (alternate, stem, title) in [
            (
                true,
                "subdiv_fig5_tentacle_levels",
                "Figure 5: a tentacle by the paper's pseudo-code, levels 1 to 4 (left to right) — the sign flip on even levels digs the tip in",
            ),
            (
                false,
                "subdiv_fig5_tentacle_levels_no_flip",
                "Figure 5 without the sign flip: the same procedure grows a curling horn",
            ),
        ] {
            let mut row = Vec::new();
            for l in 1..=4 {
                let m = grow(
                    &sphere,
                    l,
                    Boundary::EdgeOnly,
                    &tentacle(alternate),
                    env.ctx.seed,
                )?;
                row.push(m.finest().mesh.triangulate());
            }
            let tri = side_by_side(&row)?.with_computed_normals();
            let file = env.write(&format!("{stem}.ply"), &Surface::Mesh(tri.clone()), &wo)?;
            let pic = env.picture(&format!("{stem}.png"), &render_mesh(&tri, &env.view())?)?;
            items.push(Item {
                title: title.into(),
                image: Some(pic),
                files: vec![file],
                facts: vec![fact(
                    "per level",
                    if alternate {
                        "length·l·(sin(θ + πl/3), cos(θ + πl/3), 1), negated on even levels"
                    } else {
                        "length·l·(sin(θ + πl/3), cos(θ + πl/3), 1)"
                    },
                )],
            });
        }
        let spurs = |levels: Vec<usize>| Layer {
            name: "s".into(),
            features: vec![Feature {
                procedure: Procedure::Spur(Spur { height: 2.5 }),
                seeds: Seeds::Poisson { spacing: 0.6 },
                levels: Some(levels),
            }],
            edits: Vec::new(),
        };
        let mut row = Vec::new();
        for ls in [vec![1], vec![3], vec![1, 3]] {
            let m = grow(&sphere, 4, Boundary::EdgeOnly, &spurs(ls), env.ctx.seed)?;
            row.push(m.finest().mesh.triangulate());
        }
        let tri = side_by_side(&row)?.with_computed_normals();
        let file = env.write(
            "subdiv_fig9_spur_levels.ply",
            &Surface::Mesh(tri.clone()),
            &wo,
        )?;
        let pic = env.picture(
            "subdiv_fig9_spur_levels.png",
            &render_mesh(&tri, &env.view())?,
        )?;
        items.push(Item {
            title: "Figure 9: spurs placed at level 1 (a), at level 3 (b), at both (c)".into(),
            image: Some(pic),
            files: vec![file],
            facts: vec![fact(
                "spur",
                "the seed vertex pushed 2.5 mean edge lengths of its level along n",
            )],
        });
    }
    Ok(Section {
        title: "Multiresolution subdivision surfaces with procedural detail (velho-perlin)".into(),
        source: "asperity-subdiv — Catmull–Clark with boundaries, creases, limit positions and normals; §2 \
                 multiresolution; §3–4 rock, fbm, berry, tentacle, mine, mushroom, spur; §5 placement and edits; \
                 §6 multiscale blending and the planet shader; scenes in crates/subdiv/scenes"
            .into(),
        blurb: "Levels of Catmull–Clark subdivision with detail offsets in local frames of the predicted surface. \
                Procedures add detail level by level — fractal (amplitude shrinking with scale) or morphogenic \
                (growing with the level); features sit at chosen vertices and levels; edits scale bands of \
                levels around a point; two surfaces blend level by level with a transition c/2^(l−1) wide, so \
                coarse features cross the seam and fine ones switch sharply."
            .into(),
        items,
    })
}

/// Meshes placed in a row along x (for figures that compare stages).
fn side_by_side(meshes: &[TriMesh]) -> anyhow::Result<TriMesh> {
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    let mut x = 0.0;
    for m in meshes {
        let b = m.bounds().context("a mesh has vertices")?;
        let shift = x - b.min[0];
        let first = pos.len() as u32;
        pos.extend(m.positions().iter().map(|p| [p[0] + shift, p[1], p[2]]));
        tris.extend(m.triangles().iter().map(|t| t.map(|v| v + first)));
        x += b.max[0] - b.min[0] + 0.3 * (b.max[0] - b.min[0]);
    }
    Ok(TriMesh::new(pos, tris)?)
}

/// The example scenes shown in the gallery: (name, TOML, title).
const SCENES: &[(&str, &str, &str)] = &[
    (
        "rock",
        include_str!("../../subdiv/scenes/rock.toml"),
        "Rock (§4.2, Fig. 3): a random value per control point per level, 1/f amplitude",
    ),
    (
        "berry",
        include_str!("../../subdiv/scenes/berry.toml"),
        "Berry (§4.2, Fig. 4): domes on Poisson-disk seeds, regrown from child clusters",
    ),
    (
        "tentacle",
        include_str!("../../subdiv/scenes/tentacle.toml"),
        "Tentacles (§4.2, Fig. 5): the paper's pseudo-code, θ animated (frame t = 0.15)",
    ),
    (
        "mine",
        include_str!("../../subdiv/scenes/mine.toml"),
        "Submarine mine (§4.2, Fig. 6): the tentacle without twist or sign alternation",
    ),
    (
        "mushroom_planet",
        include_str!("../../subdiv/scenes/mushroom_planet.toml"),
        "Mushroom planet (§4.2, Fig. 7): mushroom clouds on a rocky sphere",
    ),
    (
        "spurs",
        include_str!("../../subdiv/scenes/spurs.toml"),
        "Placement at levels 1 and 3 (§5.1, Fig. 9c): large and small spurs",
    ),
    (
        "edited_rock",
        include_str!("../../subdiv/scenes/edited_rock.toml"),
        "Local edits (§5.2): rock smoothed near +z, exaggerated near +x",
    ),
    (
        "rusted_fuse",
        include_str!("../../subdiv/scenes/rusted_fuse.toml"),
        "Rusted fuse (§6.1, Fig. 11): fuse and rock blended across a (1, 2, 0) plane",
    ),
    (
        "planet",
        include_str!("../../subdiv/scenes/planet.toml"),
        "Blended planet (§6.2, Fig. 12): two rock scalars blended, then shaded",
    ),
];

/// gobron-chiba: cellular automata on triangle meshes (surface Voronoi).
fn surface_ca(env: &Env) -> anyhow::Result<Section> {
    use asperity_render::plot::{Plot, Series, Style, plot_png};
    use asperity_surfca::voronoi::{PAPER_P, VoronoiRule, random_sites, voronoi};
    use asperity_surfca::{CellSize, build};
    let mut items = Vec::new();
    let cells_target = if env.quick { 30_000 } else { 150_000 };
    let mut steps_item = None;
    for (name, mesh, sites) in [
        ("cup", asperity_core::shapes::cup(48), 16usize),
        ("sphere", asperity_core::shapes::icosphere(3, 1.0), 12),
    ] {
        let cells = build(&mesh, CellSize::Count(cells_target), &env.ctx.budget)?;
        let s = random_sites(&cells, sites, env.ctx.seed);
        let (labels, stats) = voronoi(
            &cells,
            &s,
            &VoronoiRule {
                diagonal_p: PAPER_P,
            },
            env.ctx.seed,
            100_000,
            |_, _| true,
        );
        let m = crate::surfca_cmd::cell_mesh(&mesh, &cells, |c| {
            crate::surfca_cmd::label_color(labels[c])
        })?;
        let (file, pic) = env.colored_mesh(&format!("surfca_voronoi_{name}"), &m)?;
        let mut facts = vec![
            fact("cells", cells.len()),
            fact("cell size", format!("{:.4}", cells.h)),
            fact("steps to cover", stats.steps),
            fact(
                "pairing redundancy",
                format!("{:.1} %", 100.0 * cells.stats.pairing_redundancy),
            ),
            fact(
                "CLI",
                format!(
                    "asperity surface-ca builtin:{name} --app voronoi --sites {sites} --cells {cells_target} -o v.glb"
                ),
            ),
        ];
        if name == "sphere" {
            // Agreement with the exact spherical Voronoi diagram of the same sites.
            let agree = asperity_surfca::voronoi::spherical_agreement(&cells, &s, &labels);
            facts.push(fact(
                "agreement with the exact diagram",
                format!("{:.2} % of the area", 100.0 * agree),
            ));
            let plot = Plot {
                title: "Surface Voronoi on a sphere: per-step statistics (cf. Figure 16)".into(),
                x_label: "step".into(),
                y_label: "fraction".into(),
                log_x: false,
                log_y: false,
                series: vec![
                    Series {
                        name: "labelled (area fraction)".into(),
                        points: stats
                            .per_step
                            .iter()
                            .map(|p| (p.step as f64, p.class_fraction[1]))
                            .collect(),
                        style: Style::Line,
                    },
                    Series {
                        name: "changed cells (fraction)".into(),
                        points: stats
                            .per_step
                            .iter()
                            .map(|p| (p.step as f64, p.changed as f64 / cells.len() as f64))
                            .collect(),
                        style: Style::Line,
                    },
                ],
            };
            let png = env.picture("surfca_voronoi_steps.png", &plot_png(&plot, 800, 520)?)?;
            steps_item = Some(Item {
                title: "Cells labelled and changed per step: the logistic curve of Figure 16"
                    .into(),
                image: Some(png),
                files: vec![],
                facts: vec![fact("steps", stats.steps)],
            });
        }
        items.push(Item {
            title: format!("Surface Voronoi diagram on the {name} ({sites} sites)"),
            image: Some(pic),
            files: vec![file],
            facts,
        });
    }
    items.extend(steps_item);

    // Copper corrosion and patina on the cup (Figure 22), shaded by the two-layer model.
    {
        use asperity_surfca::corrosion::{Behaviour, CorrosionParams, corrode, initial};
        let mesh = asperity_core::shapes::cup(48);
        let cells = build(
            &mesh,
            CellSize::Count(if env.quick { 40_000 } else { 220_000 }),
            &env.ctx.budget,
        )?;
        let p = CorrosionParams::default();
        let mut states = initial(&cells, &p, env.ctx.seed);
        let steps = if env.quick { 150 } else { 300 };
        corrode(&cells, &p, &mut states, env.ctx.seed, steps, |_, _| true);
        let m = crate::surfca_cmd::cell_mesh(&mesh, &cells, |c| {
            crate::surfca_cmd::patina_color(&states[c])
        })?;
        let (file, pic) = env.colored_mesh("surfca_patina_cup", &m)?;
        let corroded = states
            .iter()
            .filter(|s| s.behaviour == Behaviour::Corroded)
            .count();
        items.push(Item {
            title: format!("Copper corrosion and green patina on the cup after {steps} steps (cf. Figure 22)"),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact("cells", cells.len()),
                fact(
                    "corroded",
                    format!("{:.1} %", 100.0 * corroded as f64 / cells.len() as f64),
                ),
                fact("colour", "patina over copper by the paper's two-layer light model"),
                fact(
                    "CLI",
                    format!(
                        "asperity surface-ca builtin:cup --app corrosion --cells 220000 --steps {steps} -o patina.glb"
                    ),
                ),
            ],
        });
    }
    // A third application on the same engine: Gray–Scott spots on the sphere.
    {
        use asperity_surfca::engine::{RunOptions, run};
        use asperity_surfca::reaction_diffusion::{GrayScott, seeded_state};
        let mesh = asperity_core::shapes::icosphere(3, 1.0);
        let (n, steps) = if env.quick {
            (8_000, 1500)
        } else {
            (40_000, 4000)
        };
        let cells = build(&mesh, CellSize::Count(n), &env.ctx.budget)?;
        let mut st = seeded_state(&cells, 12, env.ctx.seed);
        run(
            &cells,
            &GrayScott::default(),
            &mut st,
            &RunOptions {
                seed: env.ctx.seed,
                max_steps: steps,
                stop_when_stable: false,
            },
            |_, _| true,
        );
        let m = crate::surfca_cmd::cell_mesh(&mesh, &cells, |c| {
            let col = ColorMap::Viridis.map((st[c].v as f64 / 0.45).clamp(0.0, 1.0));
            [col[0], col[1], col[2], 255]
        })?;
        let (file, pic) = env.colored_mesh("surfca_gray_scott", &m)?;
        items.push(Item {
            title: format!("Gray–Scott reaction–diffusion after {steps} steps: the engine is general"),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact("cells", cells.len()),
                fact("F, k", "0.0367, 0.0649 (Pearson's self-replicating spots)"),
                fact(
                    "CLI",
                    "asperity surface-ca builtin:sphere --app gray-scott --cells 40000 --steps 4000 -o rd.glb",
                ),
            ],
        });
    }
    Ok(Section {
        title: "Cellular automata on triangle meshes (gobron-chiba)".into(),
        source: "asperity-surfca — per-triangle cell grids, edge and vertex links, Figure 14's diagonal probability"
            .into(),
        blurb: "Every triangle carries its own grid of square cells; cells talk across edges and around vertices, \
                so a CA runs on the surface itself with no texture mapping. Here: Voronoi regions grown from random \
                sites by regular probabilistic growth, and copper corrosion whose patina is coloured by the paper's \
                light-through-two-layers model."
            .into(),
        items,
    })
}

type SectionFn = fn(&Env) -> anyhow::Result<Section>;

/// The gallery, in page order. Method issues add their section here.
const SECTIONS: &[(&str, SectionFn)] = &[
    ("foundation", foundation),
    ("renderer", renderer),
    ("peridier", peridier),
    ("growth", growth),
    ("levelset", reconstruction),
    ("ifs", ifs),
    ("surfca", surface_ca),
    ("subdiv", subdivision),
];

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
    if let Some(bad) = a
        .only
        .iter()
        .find(|o| !SECTIONS.iter().any(|(n, _)| n == o))
    {
        let names: Vec<&str> = SECTIONS.iter().map(|(n, _)| *n).collect();
        anyhow::bail!("--only {bad}: no such section ({})", names.join(", "));
    }
    let chosen: Vec<&(&str, SectionFn)> = SECTIONS
        .iter()
        .filter(|(n, _)| a.only.is_empty() || a.only.iter().any(|o| o == n))
        .collect();
    let bar = Bar::new(ctx.quiet || ctx.json);
    bar.start(chosen.len() as u64, "demo");
    let mut sections = Vec::new();
    for (name, f) in chosen {
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
    asperity_io::write_text(&index, &html)?;
    let mut report = env.report.into_inner();
    report.output(&index);
    report.measure(
        "sections",
        sections.iter().map(|s| s.title.clone()).collect::<Vec<_>>(),
    );
    let json = serde_json::to_string_pretty(&report)?;
    let report_path = dir.join("report.json");
    asperity_io::write_text(&report_path, &json)?;
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

    let preview = env.picture(
        "sample_height_map.png",
        &hillshade::height_map(&h, ColorMap::Viridis, 0.5, true),
    )?;
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
    let view3d = env.picture(
        "sample_mesh_3d.png",
        &render_mesh(
            &mesh,
            &RenderOptions {
                shader: Shader::Texture,
                ..env.view()
            },
        )?,
    )?;
    items.push(Item {
        title: "The same surface as a mesh (alternating diagonals)".into(),
        image: Some(view3d),
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
    let torus_view = env.picture(
        "torus.png",
        &render_mesh(
            &t,
            &RenderOptions {
                wireframe: Some([30, 30, 40, 160]),
                ..env.view()
            },
        )?,
    )?;
    items.push(Item {
        title: "Closed mesh: torus topology check".into(),
        image: Some(torus_view),
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
                Pictures are rendered headless on the CPU by asperity-render."
            .into(),
        items,
    })
}

/// An icosphere displaced radially by 3-D random-phase Fourier noise with a
/// power-law spectrum (amplitude ∝ |k|^−(1+H)): a rough "rock" for the renderer's
/// shader gallery.
fn rock(level: u32, seed: u64) -> anyhow::Result<TriMesh> {
    use rand::Rng;
    let sphere = asperity_core::shapes::icosphere(level, 1.0);
    let mut rng = asperity_core::seeded(seed);
    let waves: Vec<([f64; 3], f64, f64)> = (0..160)
        .map(|_| {
            let k = 2.0 * 20f64.powf(rng.random::<f64>()); // |k| log-uniform in [2, 40]
            let (z, ph): (f64, f64) = (
                rng.random::<f64>() * 2.0 - 1.0,
                rng.random::<f64>() * std::f64::consts::TAU,
            );
            let s = (1.0 - z * z).sqrt();
            (
                [k * s * ph.cos(), k * s * ph.sin(), k * z],
                k.powf(-1.5),
                rng.random::<f64>() * std::f64::consts::TAU,
            )
        })
        .collect();
    let norm: f64 = waves.iter().map(|w| w.1 * w.1).sum::<f64>().sqrt();
    let p = sphere
        .positions()
        .iter()
        .map(|q| {
            let d: f64 = waves
                .iter()
                .map(|(k, a, ph)| a * (k[0] * q[0] + k[1] * q[1] + k[2] * q[2] + ph).cos())
                .sum();
            let r = 1.0 + 0.16 * d / norm;
            q.map(|c| c * r)
        })
        .collect();
    Ok(TriMesh::new(p, sphere.triangles().to_vec())?.with_computed_normals())
}

/// The renderer's gallery: shaders, views, point splats, map views and plots.
fn renderer(env: &Env) -> anyhow::Result<Section> {
    let rock = rock(if env.quick { 5 } else { 6 }, env.ctx.seed)?;
    let mut items = Vec::new();
    for (shader, name, caption) in [
        (
            Shader::Phong,
            "phong",
            "Smooth shading, the gobron-chiba light model (ambient + diffuse + Phong specular), shadow map and ambient obscurance",
        ),
        (Shader::Flat, "flat", "Flat shading: one normal per facet"),
        (
            Shader::Curvature,
            "curvature",
            "Mean curvature (cotangent Laplacian), diverging colour map",
        ),
        (Shader::Normals, "normals", "World normals as RGB"),
    ] {
        let img = render_mesh(
            &rock,
            &RenderOptions {
                shader,
                ..env.view()
            },
        )?;
        let file = env.picture(&format!("render_rock_{name}.png"), &img)?;
        items.push(Item {
            title: format!("Shader: {name}"),
            image: Some(file),
            files: vec![],
            facts: vec![fact("what", caption), fact("triangles", rock.n_faces())],
        });
    }
    env.write(
        "rock.ply",
        &Surface::Mesh(rock.clone()),
        &WriteOptions::default(),
    )?;
    // The rock's profile in the plane z = 0, drawn over it: a polyline overlay.
    let equator: Vec<[f64; 3]> = (0..360)
        .map(|k| {
            let a = (k as f64).to_radians();
            let dir = [a.cos(), a.sin(), 0.0];
            // Radius of the nearest vertex direction, slightly lifted to stay visible.
            let r = rock
                .positions()
                .iter()
                .filter(|q| q[2].abs() < 0.05)
                .max_by(|u, v| {
                    let du = (u[0] * dir[0] + u[1] * dir[1]) / (u[0].hypot(u[1]));
                    let dv = (v[0] * dir[0] + v[1] * dir[1]) / (v[0].hypot(v[1]));
                    du.total_cmp(&dv)
                })
                .map_or(1.0, |q| q[0].hypot(q[1]));
            dir.map(|c| c * r * 1.01)
        })
        .collect();
    let img = render_mesh(
        &rock,
        &RenderOptions {
            view: View::Front,
            polylines: vec![Polyline {
                points: equator,
                color: [220, 40, 40, 255],
                closed: true,
            }],
            ..env.view()
        },
    )?;
    let file = env.picture("render_rock_front_polyline.png", &img)?;
    items.push(Item {
        title: "Front view with a polyline overlay".into(),
        image: Some(file),
        files: vec!["rock.ply".into()],
        facts: vec![fact("overlay", "the rock's equator, depth-tested")],
    });

    let p = FourierParams {
        n: if env.quick { 65 } else { 129 },
        hurst: 0.8,
        modes: 16,
        rms: 0.06,
        spacing: 1.0 / 128.0,
    };
    let h = fourier_surface(&p, env.ctx.seed + 1, &env.ctx.budget)?;
    let relief = env.picture(
        "render_height_hillshade.png",
        &hillshade::hillshade(&h, 315.0, 45.0),
    )?;
    items.push(Item {
        title: "Height field: hillshade".into(),
        image: Some(relief),
        files: vec![],
        facts: vec![fact(
            "light",
            "azimuth 315°, altitude 45° (GDAL convention)",
        )],
    });
    let top = render_height(
        &h,
        &RenderOptions {
            view: View::Top,
            projection: asperity_render::Projection::Orthographic,
            ..env.view()
        },
    )?;
    let file = env.picture("render_height_top.png", &top)?;
    items.push(Item {
        title: "Height field: orthographic top view, height colour map".into(),
        image: Some(file),
        files: vec![],
        facts: vec![fact("colour map", "viridis, min → max")],
    });

    let coarse = fourier_surface(
        &FourierParams {
            n: 65,
            hurst: 0.8,
            modes: 16,
            rms: 0.06,
            spacing: 1.0 / 64.0,
        },
        env.ctx.seed + 1,
        &env.ctx.budget,
    )?;
    let mut colored = coarse.to_point_set();
    let (lo, hi) = coarse.min_max();
    let cols = colored.positions().iter().map(|q| {
        let c = ColorMap::Magma.map((q[2] - lo) / (hi - lo).max(1e-300));
        [c[0], c[1], c[2], 255]
    });
    colored.set_colors(cols.collect())?;
    let img = render_points(&colored, &env.view())?;
    let file = env.picture("render_points.png", &img)?;
    items.push(Item {
        title: "Point set as lit splats".into(),
        image: Some(file),
        files: vec![],
        facts: vec![fact("points", colored.len())],
    });

    let curv = asperity_render::render::mean_curvature(&rock);
    let plot = env.svg(
        "plot_rock_curvature.svg",
        &histogram_svg(
            &curv,
            60,
            "Mean curvature of the rough sphere",
            "H (1/length; unit sphere: 1)",
            640,
            400,
        )?,
    )?;
    items.push(Item {
        title: "Plot: curvature histogram (SVG)".into(),
        image: Some(plot),
        files: vec![],
        facts: vec![fact(
            "reference",
            "an undisplaced unit sphere has H = 1 everywhere",
        )],
    });

    Ok(Section {
        title: "Renderer: shaders, views, overlays, plots".into(),
        source: "asperity-render — light model from gobron-chiba §\"Simple Light Model\"".into(),
        blurb: "Headless CPU rendering with 4× supersampling, shadows from the key light and ambient obscurance. \
                Every picture in this gallery comes from `asperity render` code paths."
            .into(),
        items,
    })
}

/// Peridier's cellular-automaton surfaces, figure by figure.
fn peridier(env: &Env) -> anyhow::Result<Section> {
    use asperity_ca::facets::{circle, drape, facet_mesh};
    use asperity_ca::{Boundary, CaParams, Family, Init, Rule, accumulate, initial_grid};
    let budget = env.ctx.budget;
    let rule450 = Rule::new(Family::Totalistic9, 2, 450)?;
    let mut items = Vec::new();
    let small = RenderOptions {
        shader: Shader::Flat,
        ..env.view()
    };

    // Figures 1–3: rule 450 on a 21×15 grid, 5 steps.
    let init = initial_grid(&Init::Seed, Some([21, 15]), 2, &budget)?;
    let run = accumulate(
        &init,
        &CaParams {
            keep_states: true,
            ..CaParams::new(rule450.clone(), 5)
        },
        &budget,
    )?;
    env.write(
        "ca_rule450_21x15.npy",
        &Surface::Height(run.heights.clone()),
        &WriteOptions::default(),
    )?;
    let fig1 = env.picture(
        "ca_fig1_rule450.png",
        &crate::ca_cmd::render_facets(&run.heights, &small)?,
    )?;
    items.push(Item {
        title: "Figure 1: rule 450, 21×15 grid, 5 steps, facets".into(),
        image: Some(fig1),
        files: vec!["ca_rule450_21x15.npy".into()],
        facts: vec![
            fact("rule", "two-state nine-neighbour totalistic 450"),
            fact(
                "initial grid",
                "one centre cell (the paper's default is not stated)",
            ),
            fact(
                "heights",
                format!("{} … {}", run.heights.min_max().0, run.heights.min_max().1),
            ),
        ],
    });
    let table = rule450.describe();
    items.push(Item {
        title: "Figure 2: the look-up table of rule 450".into(),
        image: None,
        files: vec![],
        facts: table
            .lines()
            .skip(1)
            .map(|l| {
                let (k, v) = l.split_once(':').unwrap_or((l, ""));
                fact(k.trim(), v.trim())
            })
            .collect(),
    });
    let states = run.states.as_deref().unwrap_or(&[]);
    let (nx, ny, scale) = (21u32, 15u32, 8u32);
    let mut strip = RgbaImage::filled(6 * (nx * scale + 6), ny * scale, [255, 255, 255, 255]);
    for (t, step) in states.chunks((nx * ny) as usize).enumerate() {
        for (n, &v) in step.iter().enumerate() {
            let c = if v == 1 {
                [0, 0, 0, 255]
            } else {
                [235, 235, 235, 255]
            };
            let (x, y) = (
                t as u32 * (nx * scale + 6) + (n as u32 % nx) * scale,
                (n as u32 / nx) * scale,
            );
            for dy in 0..scale - 1 {
                for dx in 0..scale - 1 {
                    strip.put(x + dx, y + dy, c);
                }
            }
        }
    }
    let fig3 = env.picture("ca_fig3_steps.png", &strip)?;
    items.push(Item {
        title: "Figure 3: steps 0–5, summed cell by cell into Figure 1".into(),
        image: Some(fig3),
        files: vec![],
        facts: vec![fact("state 1", "black")],
    });

    // Figure 4: rules 8 and 480 × two initial conditions.
    let args = crate::cli::CaGalleryArgs {
        rules: vec!["8".into(), "480".into()],
        rule_args: crate::cli::RuleArgs {
            family: "totalistic9".into(),
            states: 2,
        },
        inits: vec![
            format!("random:0.2@{}", env.ctx.seed),
            format!("random:0.5@{}", env.ctx.seed),
        ],
        steps: 10,
        size: (41, 41),
        tile: if env.quick { (240, 180) } else { (400, 300) },
    };
    let fig4 = env.picture(
        "ca_fig4_gallery.png",
        &crate::ca_cmd::gallery_image(env.ctx, &args)?,
    )?;
    items.push(Item {
        title: "Figure 4: rows = rules 8, 480; columns = two initial conditions".into(),
        image: Some(fig4),
        files: vec![],
        facts: vec![
            fact("grid", "41×41 cyclic, 10 steps"),
            fact("columns", "random densities 0.2 and 0.5"),
            fact("CLI", "asperity ca gallery --rules 8,480 …"),
        ],
    });

    // Figures 5/6 and 9: smooth plot versus facets on random data, a circle on it.
    let mut rng = asperity_core::seeded(env.ctx.seed);
    let rand_h = HeightField::from_vec(
        [15, 15],
        (0..225)
            .map(|_| rand::Rng::random::<f64>(&mut rng) * 3.0)
            .collect(),
    )?;
    let smooth = rand_h.to_trimesh(Diagonal::Forward)?;
    let fig6a = env.picture(
        "ca_fig6_smooth.png",
        &render_mesh(
            &smooth,
            &RenderOptions {
                shader: Shader::Phong,
                ..env.view()
            },
        )?,
    )?;
    let facets = facet_mesh(&rand_h, true)?;
    let fig6b = env.picture("ca_fig6_facets.png", &render_mesh(&facets, &small)?)?;
    items.push(Item {
        title: "Figure 6: irregular data, smoothly shaded".into(),
        image: Some(fig6a),
        files: vec![],
        facts: vec![fact(
            "what",
            "one diagonal everywhere, smooth normals: interpolation artefacts",
        )],
    });
    items.push(Item {
        title: "Figure 6: the same data as alternating-diagonal facets".into(),
        image: Some(fig6b),
        files: vec![],
        facts: vec![fact(
            "what",
            "flat facets, nodes in 4 or 8 facets (Figure 7)",
        )],
    });
    let ring = drape(&rand_h, &circle(7.0, 7.0, 5.0, 180))?;
    env.write(
        "ca_fig9_circle.ply",
        &Surface::Mesh(facets.clone()),
        &WriteOptions::default(),
    )?;
    asperity_io::write_mesh_with_polylines(
        &env.dir.join("ca_fig9_circle.obj"),
        &facet_mesh(&rand_h, false)?,
        std::slice::from_ref(&ring),
        &WriteOptions::default(),
    )?;
    env.report
        .borrow_mut()
        .output(&env.dir.join("ca_fig9_circle.obj"));
    let fig9 = env.picture(
        "ca_fig9_circle.png",
        &render_mesh(
            &facets,
            &RenderOptions {
                polylines: vec![Polyline {
                    points: ring.clone(),
                    color: [220, 30, 30, 255],
                    closed: true,
                }],
                ..small.clone()
            },
        )?,
    )?;
    items.push(Item {
        title: "Figure 9: a circle drawn on the facets".into(),
        image: Some(fig9),
        files: vec!["ca_fig9_circle.obj".into()],
        facts: vec![
            fact("curve points", ring.len()),
            fact(
                "method",
                "split at every grid line and facet diagonal, z by the four-case interpolation",
            ),
        ],
    });

    // A large surface.
    let n = if env.quick { 128 } else { 256 };
    let steps = if env.quick { 24 } else { 48 };
    let init = initial_grid(
        &Init::Random {
            density: 0.3,
            seed: env.ctx.seed,
        },
        Some([n, n]),
        2,
        &budget,
    )?;
    let t = std::time::Instant::now();
    let big = accumulate(
        &init,
        &CaParams {
            boundary: Boundary::Cyclic,
            ..CaParams::new(rule450, steps)
        },
        &budget,
    )?;
    let secs = t.elapsed().as_secs_f64();
    env.write(
        "ca_rule450_large.gsf",
        &Surface::Height(big.heights.clone()),
        &WriteOptions::default(),
    )?;
    let view = env.picture(
        "ca_large_3d.png",
        &crate::ca_cmd::render_facets(&big.heights, &small)?,
    )?;
    let map = env.picture(
        "ca_large_map.png",
        &hillshade::height_map(&big.heights, ColorMap::Magma, 0.4, true),
    )?;
    items.push(Item {
        title: format!("Rule 450, {n}×{n} cyclic, {steps} steps"),
        image: Some(view),
        files: vec!["ca_rule450_large.gsf".into()],
        facts: vec![
            fact("initial grid", "random, density 0.3"),
            fact(
                "CLI",
                format!(
                    "asperity ca run --rule 450 --steps {steps} --init random:0.3 --size {n}x{n}"
                ),
            ),
        ],
    });
    // Timings go to report.json only: the page must be the same bytes on every run.
    env.report.borrow_mut().measure("ca_large_seconds", secs);
    items.push(Item {
        title: "The same surface as a map".into(),
        image: Some(map),
        files: vec![],
        facts: vec![fact("colour map", "magma with relief")],
    });

    Ok(Section {
        title: "Cellular-automaton surfaces (peridier)".into(),
        source: "asperity-ca — peridier, Figures 1–4, 6, 7, 9".into(),
        blurb: "Elevations are the cell-by-cell sum of the steps of a 2-D totalistic cellular automaton (Wolfram numbering), drawn with \
                flat triangular facets on alternating diagonals, with an interpolation consistent with them."
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

/// Points coloured by a per-point value in [0, 1] (deposition order, height).
fn colored_points(
    pts: Vec<[f64; 3]>,
    t: impl Fn(usize, &[f64; 3]) -> f64,
    map: ColorMap,
) -> anyhow::Result<asperity_core::PointSet> {
    let cols: Vec<[u8; 4]> = pts
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let c = map.map(t(k, p).clamp(0.0, 1.0));
            [c[0], c[1], c[2], 255]
        })
        .collect();
    let mut ps = asperity_core::PointSet::new(pts);
    ps.set_colors(cols)?;
    Ok(ps)
}

/// kim-machiraju-thompson §4: RD, RDSR, BD, DLA and curved substrates.
fn growth(env: &Env) -> anyhow::Result<Section> {
    use asperity_analysis::scaling::{
        density_dimension, density_profile, growth_exponent, gyration_dimension,
    };
    use asperity_growth::dla::{DlaParams, SeedShape, dla};
    use asperity_growth::{DepositionParams, Lattice, Model, deposit_ensemble};
    use asperity_render::plot::{Plot, Series, Style, plot_svg};
    let budget = env.ctx.budget;
    let seed = env.ctx.seed;
    let none = asperity_core::NoProgress;
    let mut items = Vec::new();
    let l = if env.quick { 64 } else { 128 };

    // Figure 3: RD versus RDSR (and BD) height fields, same time.
    let mut width_series = Vec::new();
    for (model, name) in [
        (Model::Rd, "rd"),
        (Model::Rdsr { radius: 1 }, "rdsr"),
        (Model::Bd, "bd"),
    ] {
        let p = DepositionParams::new(model, Lattice::new(l, 2)?, 100.0);
        let (d, s) = deposit_ensemble(&p, seed, 1, &budget, &none)?;
        let h = d.height_field();
        let file = env.write(
            &format!("growth_{name}.npy"),
            &Surface::Height(h.clone()),
            &WriteOptions::default(),
        )?;
        let img = render_height(
            &h,
            &RenderOptions {
                shader: Shader::Height,
                z_scale: 0.5,
                ..env.view()
            },
        )?;
        let pic = env.picture(&format!("growth_{name}.png"), &img)?;
        let beta = growth_exponent(&s.t, &s.width(), [1.0, 100.0])
            .map(|f| f.exponent)
            .unwrap_or(f64::NAN);
        items.push(Item {
            title: format!("{}: {l}×{l} columns, 100 monolayers", name.to_uppercase()),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact(
                    "interface width W",
                    format!("{:.3}", s.w2.last().copied().unwrap_or(0.0).sqrt()),
                ),
                fact("β (log–log, t ∈ [1, 100])", format!("{beta:.3}")),
                fact(
                    "CLI",
                    format!("asperity growth {name} --size {l} --layers 100 -o h.npy"),
                ),
            ],
        });
        width_series.push((name, s));
    }
    let plot = Plot {
        title: "Interface width W(t), 2+1D".into(),
        x_label: "t (monolayers)".into(),
        y_label: "W".into(),
        log_x: true,
        log_y: true,
        series: width_series
            .iter()
            .map(|(n, s)| Series {
                name: n.to_uppercase(),
                points: s.t.iter().copied().zip(s.width()).collect(),
                style: Style::Line,
            })
            .collect(),
    };
    let svg = env.svg("growth_width.svg", &plot_svg(&plot, 800, 560)?)?;
    items.push(Item {
        title: "W(t): RD grows as t^½, RDSR logarithmically (2+1D EW), BD as KPZ".into(),
        image: Some(svg),
        files: vec![],
        facts: vec![fact("exponent checks", "crates/growth/tests/reference.rs")],
    });

    // Figure 4 / Figure 1: a DLA cluster from a point seed.
    let n = if env.quick { 5_000 } else { 30_000 };
    let c = dla(&DlaParams::point(3, n), seed, 0, &budget, &none)?;
    let pts = c.points();
    let d = gyration_dimension(&pts).map(|d| d.d).unwrap_or(f64::NAN);
    let total = pts.len() as f64;
    let ps = colored_points(pts, |k, _| k as f64 / total, ColorMap::Magma)?;
    let file = env.write(
        "growth_dla_point.ply",
        &Surface::Points(ps.clone()),
        &WriteOptions::default(),
    )?;
    let pic = env.picture("growth_dla_point.png", &render_points(&ps, &env.view())?)?;
    items.push(Item {
        title: format!("DLA from a point seed, {n} particles, p = 1"),
        image: Some(pic),
        files: vec![file],
        facts: vec![
            fact(
                "fractal dimension (R_g fit)",
                format!("{d:.3} (3-D DLA ≈ 2.5)"),
            ),
            fact("colour", "deposition order"),
            fact(
                "CLI",
                format!("asperity growth dla --particles {n} -o pts.ply"),
            ),
        ],
    });

    // Figures 9–11: DLA terrain on the bottom plane, moss-like with small p.
    let side = if env.quick { 48 } else { 96 };
    for (stick, tag) in [(1.0, "dendritic"), (0.1, "moss")] {
        let params = DlaParams {
            dim: 3,
            size: [side, side, 2 * side],
            particles: side * side * 3 / 2,
            stick,
            seed_shape: SeedShape::Plane,
            launch_gap: 2.0,
        };
        let c = dla(&params, seed, 0, &budget, &none)?;
        let parts: Vec<[f64; 3]> = c.particles().iter().map(|p| p.map(f64::from)).collect();
        let rho = density_profile(&parts, (side * side) as f64);
        let dd = density_dimension(&rho, 3)
            .map(|d| format!("{:.2}", d.d))
            .unwrap_or_else(|e| e.to_string());
        let top = parts.iter().map(|p| p[2]).fold(1.0, f64::max);
        let ps = colored_points(c.points(), |_, p| p[2] / top, ColorMap::Viridis)?;
        let file = env.write(
            &format!("growth_dla_plane_{tag}.ply"),
            &Surface::Points(ps.clone()),
            &WriteOptions::default(),
        )?;
        let pic = env.picture(
            &format!("growth_dla_plane_{tag}.png"),
            &render_points(&ps, &env.view())?,
        )?;
        items.push(Item {
            title: format!("DLA terrain on a plane, p = {stick} ({tag})"),
            image: Some(pic),
            files: vec![file],
            facts: vec![
                fact("lattice", format!("{side}×{side}×{}, periodic in x and y", 2 * side)),
                fact("particles", c.particles().len()),
                fact("D from ρ(z) ∝ z^(D−3)", dd),
                fact("CLI", format!("asperity growth dla --seed-shape plane --size {side}x{side}x{} --stick {stick} -o pts.ply", 2 * side)),
            ],
        });
    }

    // Figure 8: RDSR on a sphere.
    let (radius, layers) = if env.quick { (12.0, 6.0) } else { (24.0, 12.0) };
    let d = rdsr_sphere(radius, layers, env)?;
    let c0 = (d.size[0] / 2) as f64;
    let pts: Vec<[f64; 3]> = d.points();
    let rmax = radius + d.thickness;
    let ps = colored_points(
        pts,
        |_, p| {
            (((p[0] - c0).powi(2) + (p[1] - c0).powi(2) + (p[2] - c0).powi(2)).sqrt() - radius)
                / (rmax - radius).max(1.0)
        },
        ColorMap::Viridis,
    )?;
    let file = env.write(
        "growth_rdsr_sphere.ply",
        &Surface::Points(ps.clone()),
        &WriteOptions::default(),
    )?;
    let pic = env.picture("growth_rdsr_sphere.png", &render_points(&ps, &env.view())?)?;
    items.push(Item {
        title: format!("Figure 8: RDSR on a sphere of radius {radius}, {layers} monolayers"),
        image: Some(pic),
        files: vec![file],
        facts: vec![
            fact("particles", d.cells.len() - d.seeds),
            fact("thickness", format!("{:.1} cells", d.thickness)),
            fact("CLI", format!("asperity growth rdsr --substrate sphere --radius {radius} --layers {layers} -o pts.ply")),
        ],
    });

    Ok(Section {
        title: "Surface growth (kim-machiraju-thompson §4)".into(),
        source: "asperity-growth — §4.1 Fig. 3, §4.2 Fig. 4, §6 Figs. 8–11".into(),
        blurb: "Random deposition, deposition with surface relaxation (Family), ballistic deposition and diffusion-limited \
                aggregation on the lattice, on a plane, a sphere or any closed mesh. The point sets feed the level-set \
                reconstruction; the exponents are checked against theory in the tests."
            .into(),
        items,
    })
}
