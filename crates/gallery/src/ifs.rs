//! Projected-IFS fractal curves and surfaces (poull-gentil): the
//! Takagi–Landsberg curve with its families of DCFs (Figure 2), the Takagi ⊗
//! Takagi attractor with per-vertex pseudo-curvature (Figures 1 and 4), an SDCF
//! on it (Figure 4), and a surface smooth in one direction and rough in the
//! other, with its control net.

use asperity_engine::Result;
use asperity_engine::core::TriMesh;
use asperity_engine::error::invalid;
use asperity_engine::ifs::{
    control_net, figure, orbit_figure, sdcf_for, surface_mesh, tensor_dcf_for,
};
use asperity_engine::methods::ifs::curvature::{curve_report, surface_report};
use asperity_engine::methods::ifs::sdcf::Start;
use asperity_engine::methods::ifs::{
    CurveIfs, DirectionAnalysis, FamilyOptions, Model, PresetParams, SurfaceIfs, preset,
};
use asperity_engine::methods::render::{Polyline, RenderOptions, Shader, View};

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any model's, writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let opts = FamilyOptions::default();
    let takagi = surface_preset("takagi-landsberg-surface")?;
    let items = vec![
        figure_2(env, &opts)?,
        orbits(env, &opts, false)?,
        orbits(env, &opts, true)?,
        takagi_surface(env, &opts, &takagi)?,
        sdcf(env, &opts, &takagi)?,
        mixed(env, &opts)?,
    ];
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

fn load(name: &str) -> Result<Model> {
    Ok(preset(name, &PresetParams::default())?.build()?)
}

fn curve_preset(name: &str) -> Result<CurveIfs> {
    match load(name)? {
        Model::Curve(c) => Ok(c),
        Model::Surface(_) => Err(invalid(format!("{name} is a curve preset"))),
    }
}

fn surface_preset(name: &str) -> Result<SurfaceIfs> {
    match load(name)? {
        Model::Surface(s) => Ok(s),
        Model::Curve(_) => Err(invalid(format!("{name} is a surface preset"))),
    }
}

fn range(r: Option<[f64; 2]>) -> String {
    r.map_or("—".to_owned(), |[a, b]| format!("[{a:.6}, {b:.6}]"))
}

/// Fig. 2: the Takagi–Landsberg curve (w = 1/√2) and its families of DCFs.
fn figure_2(env: &Env, opts: &FamilyOptions) -> Result<Item> {
    let curve = curve_preset("takagi-landsberg")?;
    let an = DirectionAnalysis::new(&curve.pifs, opts);
    let svg = figure(&curve, &an, "Takagi–Landsberg w = 1/√2", 10, None)?;
    let fig = env.text("ifs_takagi_dcf.svg", &svg)?;
    let rep = curve_report(&curve, &an);
    let json = env.text(
        "ifs_takagi_curvature.json",
        &serde_json::to_string_pretty(&rep).map_err(|e| invalid(e.to_string()))?,
    )?;
    Ok(Item::new(
        "Takagi–Landsberg curve and its families of DCFs (Fig. 2)",
        Some(fig),
        vec![json],
        vec![
            fact("α (T0)", "0, 1, 2 — α₂ = 2: a finite range"),
            fact("curvature at s = 0", range(rep[0].curvature)),
            fact("closed form", "[−(6 − 4√2), −(102 − 72√2)]"),
            fact(
                "CLI",
                "asperity ifs dcf --preset takagi-landsberg --bound upper -o dcf.svg",
            ),
        ],
    ))
}

/// Figs. 2 and 3 on the 4-point P-IFS over the square (0,0), (0,1), (1,1),
/// (1,0) (`takagi-square`): the DCF family of T0, the DCF of T1 from c₀, the
/// orbit T1ⁿ·c₀; Fig. 3 projects the same P-IFS with (1,1) moved to (1,−1)
/// and adds the transformations' pseudo-tangents.
fn orbits(env: &Env, opts: &FamilyOptions, reprojected: bool) -> Result<Item> {
    let mut curve = curve_preset("takagi-square")?;
    if reprojected {
        curve.move_point(2, [1.0, -1.0, 0.0])?;
    }
    let an = DirectionAnalysis::new(&curve.pifs, opts);
    let (stem, title, caption) = if reprojected {
        (
            "ifs_fig3_tangents",
            "Fig. 3: the same P-IFS, control points (0,0), (0,1), (1,−1), (1,0)",
            "Figure 3: the same P-IFS projected with (1,1) moved to (1,−1) — the curve bends by −2x² — and the pseudo-tangents of T0 and T1 at their fixed points (purple)",
        )
    } else {
        (
            "ifs_fig2_orbit",
            "Fig. 2: a P-IFS whose attractor is the Takagi curve",
            "Figure 2: a 4-point P-IFS whose attractor is the Takagi curve — the family of DCFs of T0 (red), the DCF of T1 from c₀ (blue), the points T1ⁿ·c₀ (green) running into c₁",
        )
    };
    let svg = orbit_figure(&curve, &an, title, reprojected)?;
    let fig = env.text(&format!("{stem}.svg"), &svg)?;
    let control = curve
        .control()
        .iter()
        .map(|p| format!("({}, {})", p[0], p[1]))
        .collect::<Vec<_>>()
        .join(", ");
    Ok(Item::new(
        caption,
        Some(fig),
        vec![],
        vec![
            fact("control points", control),
            fact(
                "P-IFS",
                "3 points (the paper's 4-point operators are not printed)",
            ),
        ],
    ))
}

/// The attractor mesh of `s` at `depth` with its curvature attributes.
fn mesh_with_curvature(
    env: &Env,
    s: &SurfaceIfs,
    opts: &FamilyOptions,
    depth: u32,
) -> Result<TriMesh> {
    let (mesh, note) = surface_mesh(s, opts, depth, true, &env.budget)?;
    match note {
        Some(n) => Err(invalid(n)),
        None => Ok(mesh),
    }
}

/// Figs. 1/4: the Takagi ⊗ Takagi surface with per-vertex pseudo-curvature.
fn takagi_surface(env: &Env, opts: &FamilyOptions, surf: &SurfaceIfs) -> Result<Item> {
    let depth = if env.quick { 6 } else { 8 };
    let mesh = mesh_with_curvature(env, surf, opts, depth)?;
    let (file, pic) = env.shaded_mesh("ifs_takagi_surface", &mesh)?;
    let (an_s, an_t) = (
        DirectionAnalysis::new(&surf.s, opts),
        DirectionAnalysis::new(&surf.t, opts),
    );
    let srep = surface_report(surf, &an_s, &an_t);
    let sjson = env.text(
        "ifs_takagi_surface_curvature.json",
        &serde_json::to_string_pretty(&srep).map_err(|e| invalid(e.to_string()))?,
    )?;
    Ok(Item::new(
        "Takagi ⊗ Takagi attractor (Figs. 1 and 4)",
        Some(pic),
        vec![file, sjson],
        vec![
            fact("vertices", mesh.n_vertices()),
            fact("depth", depth),
            fact("𝒦 at (0,0)", range(srep[0].gaussian)),
            fact("ℋ at (0,0)", range(srep[0].mean)),
            fact(
                "at every dyadic point",
                "the same ranges: for w = 1/√2 the maps preserve them (see the PLY attributes)",
            ),
            fact(
                "CLI",
                "asperity ifs surface --preset takagi-landsberg-surface --depth 8 -o t.ply",
            ),
        ],
    ))
}

/// Fig. 4: the attractor with one SDCF of T0⊗T'0 (from the opposite corner),
/// and the three DCFs it contains: those of T0 and T′0 (green, cyan) along its
/// edges t = 0 and s = 0, and that of 𝒯00 = T0⊗T′0 (yellow), computed from
/// 𝒯00's own spectrum (`asperity_ifs::invariant`): the square surface has
/// λ₁ = λ′₁, so it lies along the SDCF's diagonal s = t.
fn sdcf(env: &Env, opts: &FamilyOptions, surf: &SurfaceIfs) -> Result<Item> {
    let starts = (Start::Parameter(1.0), Start::Parameter(1.0));
    let resolution = if env.quick { 32 } else { 64 };
    let sd = sdcf_for(surf, opts, (0, 0), starts, resolution, &env.budget)?;
    let att = surf.attractor_mesh(if env.quick { 5 } else { 6 }, &env.budget)?;
    let both = TriMesh::merge_colored(&[(&att, [200, 200, 200, 255]), (&sd, [40, 90, 220, 255])])?;
    let mut lines = dcf_lines(&sd)?;
    // 𝒯00's DCF from its own spectrum (λ₁ = λ′₁ twice), not read off the mesh:
    // it must land on the SDCF's diagonal.
    let yellow = lines.last_mut().ok_or_else(|| invalid("three DCF lines"))?;
    yellow.points = tensor_dcf_for(surf, opts, (0, 0), starts, resolution)?;
    let file = env.mesh("ifs_sdcf.ply", &both)?;
    // From below: the SDCF lies under the attractor's cusps, which would
    // hide the DCFs drawn on it.
    let b = both
        .bounds()
        .ok_or_else(|| invalid("the attractor has vertices"))?;
    let (c, e) = (b.center(), b.extent());
    let size = e[0].max(e[1]).max(e[2]);
    let view = RenderOptions {
        polylines: lines,
        shader: Shader::VertexColor,
        view: View::Explicit {
            eye: [c[0] + 1.2 * size, c[1] - 1.6 * size, c[2] - 1.1 * size],
            target: c,
        },
        ..env.view()
    };
    let pic = env.render("ifs_sdcf.png", &both, &view)?;
    Ok(Item::new(
        "Fig. 4: an SDCF (blue) of 𝒯00 = T0⊗T′0 on the attractor, with the DCFs of T0 (green), T′0 (cyan) and 𝒯00 (yellow) it contains",
        Some(pic),
        vec![file],
        vec![
            fact("start", "Q = c₁ ⊗ c′₁ (the opposite corner)"),
            fact(
                "DCF of 𝒯00",
                "from 𝒯00's own spectrum (1, λ₁ twice, …: eigenvalues λᵢλ′ⱼ with multiplicity); \
                 it lies on the SDCF at s = t because λ₁ = λ′₁",
            ),
            fact(
                "CLI",
                "asperity ifs sdcf --preset takagi-landsberg-surface --with-attractor 6 -o sdcf.ply",
            ),
        ],
    ))
}

/// The DCFs on an SDCF mesh (uv = (s, t)): T0's along t = 0 (green), T′0's
/// along s = 0 (cyan), 𝒯00's along s = t (yellow).
fn dcf_lines(sd: &TriMesh) -> Result<Vec<Polyline>> {
    let uv = sd
        .uvs()
        .ok_or_else(|| invalid("the SDCF mesh carries (s, t) as uv"))?;
    let along = |keep: &dyn Fn([f64; 2]) -> bool, color: [u8; 4]| {
        let mut pts: Vec<([f64; 2], [f64; 3])> = uv
            .iter()
            .zip(sd.positions())
            .filter(|(w, _)| keep(**w))
            .map(|(w, p)| (*w, *p))
            .collect();
        pts.sort_by(|a, b| (a.0[0] + a.0[1]).total_cmp(&(b.0[0] + b.0[1])));
        Polyline {
            points: pts.into_iter().map(|(_, p)| p).collect(),
            color,
            closed: false,
        }
    };
    let eps = 1e-9;
    Ok(vec![
        along(&|w| w[1].abs() < eps, [40, 170, 60, 255]),
        along(&|w| w[0].abs() < eps, [0, 190, 200, 255]),
        along(&|w| (w[0] - w[1]).abs() < eps, [235, 200, 0, 255]),
    ])
}

/// A surface with a smooth and a rough direction, with its control net.
fn mixed(env: &Env, opts: &FamilyOptions) -> Result<Item> {
    let surf = surface_preset("bezier-takagi")?;
    let mesh = mesh_with_curvature(env, &surf, opts, if env.quick { 6 } else { 8 })?;
    let net = control_net(&surf)
        .into_iter()
        .map(|points| Polyline {
            points,
            color: [200, 40, 40, 255],
            closed: false,
        })
        .collect();
    let file = env.mesh("ifs_bezier_takagi.ply", &mesh)?;
    let view = RenderOptions {
        polylines: net,
        shader: Shader::Curvature,
        scalar: Some("gaussian_max".into()),
        ..env.view()
    };
    let pic = env.render("ifs_bezier_takagi.png", &mesh, &view)?;
    let (a, b) = (
        DirectionAnalysis::new(&surf.s, opts),
        DirectionAnalysis::new(&surf.t, opts),
    );
    let rep = surface_report(&surf, &a, &b);
    Ok(Item::new(
        "Smooth along s (Bézier), rough along t (Takagi): Gaussian pseudo-curvature (max) and control net",
        Some(pic),
        vec![file],
        vec![
            fact("𝒦 at (0,0)", range(rep[0].gaussian)),
            fact(
                "CLI",
                "asperity ifs surface --preset bezier-takagi --control-net net.obj -o s.ply",
            ),
        ],
    ))
}
