//! Cellular automata on triangle meshes (gobron-chiba): surface Voronoi
//! diagrams on the cup and the sphere (with the exact spherical diagram and the
//! per-step statistics of Figure 16), copper corrosion with patina (Figure 22),
//! and Gray–Scott spots to show the engine is general.

use asperity_engine::Result;
use asperity_engine::core::{TriMesh, shapes};
use asperity_engine::methods::render::plot::{Plot, Series, Style, plot_png};
use asperity_engine::methods::render::{RenderOptions, Shader};
use asperity_engine::methods::surfca::cells::figure8;
use asperity_engine::methods::surfca::corrosion::{Behaviour, CorrosionParams, corrode, initial};
use asperity_engine::methods::surfca::engine::{RunOptions, RunStats, run};
use asperity_engine::methods::surfca::reaction_diffusion::{GrayScott, seeded_state};
use asperity_engine::methods::surfca::voronoi::{
    PAPER_P, VoronoiRule, random_sites, spherical_agreement, voronoi,
};
use asperity_engine::methods::surfca::{CellSize, build};
use asperity_engine::surfca::{Covered, corrosion_mesh, label_color, patina_shading, rd_color};

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any cell build's, writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let (cup, _) = voronoi_item(env, "cup", shapes::cup(48), 16)?;
    let (sphere, steps) = voronoi_item(env, "sphere", shapes::icosphere(3, 1.0), 12)?;
    let cylinder = asperity_engine::files::builtin_mesh("cylinder")?;
    let (cylinder, _) = voronoi_item(env, "cylinder", cylinder, 10)?;
    let mut items = vec![cup, sphere, cylinder];
    items.extend(steps);
    items.push(figure8_plot(env)?);
    items.push(corrosion(env)?);
    items.push(gray_scott(env)?);
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

/// `mesh` covered with about `n` cells.
fn covered(env: &Env, mesh: TriMesh, n: usize) -> Result<Covered> {
    let cells = build(&mesh, CellSize::Count(n), &env.budget)?;
    Ok(Covered {
        mesh,
        repair: None,
        cells,
        cells_s: 0.0,
    })
}

/// A surface Voronoi diagram of `sites` random sites on `mesh`; on the sphere,
/// also its agreement with the exact diagram and the per-step statistics.
fn voronoi_item(
    env: &Env,
    name: &str,
    mesh: TriMesh,
    sites: usize,
) -> Result<(Item, Option<Item>)> {
    // (a cell mesh's base triangles meet at unmatched grid borders, which the
    // download copy must keep whole, so the quick size keeps the quick gallery
    // small; see crate::downloads)
    let target = if env.quick { 15_000 } else { 150_000 };
    let cov = covered(env, mesh, target)?;
    let cells = &cov.cells;
    let s = random_sites(cells, sites, env.seed);
    let rule = VoronoiRule {
        diagonal_p: PAPER_P,
    };
    let (labels, stats) = voronoi(cells, &s, &rule, env.seed, 100_000, |_, _| true);
    let m = cov.cell_mesh(|c| label_color(labels[c]))?;
    let (file, pic) = env.colored_mesh(&format!("surfca_voronoi_{name}"), &m)?;
    let mut files = vec![file];
    if name == "cup" {
        // The original mesh with the cells in a texture atlas, as
        // `surface-ca … -o v.glb` writes it.
        let textured = asperity_engine::methods::surfca::atlas::atlas_mesh(
            &cov.mesh,
            cells,
            |c| label_color(labels[c]),
            &env.budget,
        )?;
        files.push(env.mesh("surfca_voronoi_cup.glb", &textured)?);
    }
    let cli = format!(
        "asperity surface-ca builtin:{name} --app voronoi --sites {sites} --cells {target} -o v.glb"
    );
    let mut facts = vec![
        fact("cells", cells.len()),
        fact("cell size", format!("{:.4}", cells.h)),
        fact("steps to cover", stats.steps),
        fact(
            "pairing redundancy (links / the paper's measure)",
            format!(
                "{:.1} % / {:.1} %",
                100.0 * cells.stats.pairing_redundancy,
                100.0 * cells.stats.paper_redundancy
            ),
        ),
        fact("CLI", cli),
    ];
    let mut steps_item = None;
    if name == "sphere" {
        // Agreement with the exact spherical Voronoi diagram of the same sites.
        let agree = spherical_agreement(cells, &s, &labels);
        let area = format!("{:.2} % of the area", 100.0 * agree);
        facts.push(fact("agreement with the exact diagram", area));
        steps_item = Some(steps_plot(env, &stats, cells.len())?);
    }
    let title = match name {
        "cylinder" => format!(
            "Figure 13(b): a cylindrical Voronoi diagram ({sites} sites), grown on the capped cylinder"
        ),
        _ => format!("Surface Voronoi diagram on the {name} ({sites} sites)"),
    };
    Ok((Item::new(title, Some(pic), files, facts), steps_item))
}

/// Cells labelled and changed per step: the logistic curve of Figure 16.
fn steps_plot(env: &Env, stats: &RunStats, n: usize) -> Result<Item> {
    let line = |name: &str, points: Vec<(f64, f64)>| Series {
        name: name.into(),
        points,
        style: Style::Line,
    };
    let per = &stats.per_step;
    let plot = Plot {
        title: "Surface Voronoi on a sphere: per-step statistics (cf. Figure 16)".into(),
        x_label: "step".into(),
        y_label: "fraction".into(),
        log_x: false,
        log_y: false,
        series: vec![
            line(
                "labelled (area fraction)",
                per.iter()
                    .map(|p| (p.step as f64, p.class_fraction[1]))
                    .collect(),
            ),
            line(
                "changed cells (fraction)",
                per.iter()
                    .map(|p| (p.step as f64, p.changed as f64 / n as f64))
                    .collect(),
            ),
        ],
    };
    let png = env.picture("surfca_voronoi_steps.png", &plot_png(&plot, 800, 520)?)?;
    Ok(Item::new(
        "Cells labelled and changed per step: the logistic curve of Figure 16",
        Some(png),
        vec![],
        vec![fact("steps", stats.steps)],
    ))
}

/// Figure 8 measured: the paper's redundancy of edge pairing (edge cells paired
/// by their projections on the edge, counted on built grids) against 1 − cos x,
/// beside the redundancy of the links asperity makes by default and of the
/// paper's links (`--pairing paper`).
fn figure8_plot(env: &Env) -> Result<Item> {
    let (angles, placements) = if env.quick { (12, 3) } else { (24, 8) };
    let points = figure8(angles, placements, &env.budget)?;
    let deg = |x: f64| x.to_degrees();
    let series = |name: &str, style: Style, f: &dyn Fn(&_) -> f64| Series {
        name: name.into(),
        points: points.iter().map(|p| (deg(p.x), 100.0 * f(p))).collect(),
        style,
    };
    let curve = Series {
        name: "1 − cos x (the paper's Figure 8)".into(),
        points: (0..=90)
            .map(|k| {
                let x = std::f64::consts::FRAC_PI_4 * k as f64 / 90.0;
                (deg(x), 100.0 * (1.0 - x.cos()))
            })
            .collect(),
        style: Style::Fit,
    };
    let plot = Plot {
        title: "Edge-pairing redundancy against the grids' angle (cf. Figure 8)".into(),
        x_label: "x, angle between the two grids (degrees)".into(),
        y_label: "cells receiving twice (%)".into(),
        log_x: false,
        log_y: false,
        series: vec![
            curve,
            series(
                "the paper's measure: edge cells paired by projection",
                Style::Points,
                &|p| p.paper,
            ),
            series("the links of --pairing paper", Style::Line, &|p| {
                p.paper_links
            }),
            series("asperity's default (unfolded) links", Style::Line, &|p| {
                p.unfolded
            }),
        ],
    };
    let png = env.picture("surfca_pairing_redundancy.png", &plot_png(&plot, 800, 520)?)?;
    let n = points.len() as f64;
    let mean = |f: &dyn Fn(&_) -> f64| 100.0 * points.iter().map(f).sum::<f64>() / n;
    let paper = mean(&|p| p.paper);
    let worst = points
        .iter()
        .map(|p| 100.0 * (p.paper - p.estimate).abs())
        .fold(0.0, f64::max);
    env.measure("pairing_redundancy_figure8", &points);
    Ok(Item::new(
        "Figure 8: cells receiving edge data twice, counted on the grids, against 1 − cos x",
        Some(png),
        vec![],
        vec![
            fact(
                "set-up",
                format!(
                    "two triangles sharing an edge of 100 cells, one grid along it and one x from it; \
                     {angles} angles in [0, π/4], {placements} grid placements each"
                ),
            ),
            fact(
                "the paper's measure, mean",
                format!("{paper:.1} % (the paper: 1 − 2√2/π ≈ 9.9 %)"),
            ),
            fact("largest gap to 1 − cos x", format!("{worst:.1} points")),
            fact(
                "asperity's unfolded links, mean",
                format!("{:.1} %", mean(&|p| p.unfolded)),
            ),
            fact(
                "the paper's links, mean",
                format!("{:.1} %", mean(&|p| p.paper_links)),
            ),
            fact(
                "CLI",
                "asperity surface-ca builtin:cup --pairing paper -o v.glb",
            ),
        ],
    ))
}

/// Copper corrosion and patina on the cup (Figure 22), shaded by the two-layer model.
fn corrosion(env: &Env) -> Result<Item> {
    // (every cell its own colour: a mesh of seams, which the download copy
    // cannot simplify, so the quick size keeps the quick gallery small)
    let n = if env.quick { 15_000 } else { 220_000 };
    let cov = covered(env, shapes::cup(48), n)?;
    let p = CorrosionParams::default();
    let mut states = initial(&cov.cells, &p, env.seed);
    let steps = if env.quick { 150 } else { 300 };
    corrode(&cov.cells, &p, &mut states, env.seed, steps, |_, _| true);
    let m = corrosion_mesh(&cov, &states)?;
    let file = env.mesh("surfca_patina_cup.ply", &m)?;
    // Each layer lit with its own material, then mixed (the paper's order).
    let opts = RenderOptions {
        shader: Shader::VertexColor,
        two_layer: Some(patina_shading()),
        ..env.view()
    };
    let pic = env.render("surfca_patina_cup.png", &m, &opts)?;
    let corroded = states
        .iter()
        .filter(|s| s.behaviour == Behaviour::Corroded)
        .count();
    Ok(Item::new(
        format!("Copper corrosion and green patina on the cup after {steps} steps (cf. Figure 22)"),
        Some(pic),
        vec![file],
        vec![
            fact("cells", cov.cells.len()),
            fact(
                "corroded",
                format!("{:.1} %", 100.0 * corroded as f64 / cov.cells.len() as f64),
            ),
            fact(
                "colour",
                "matte patina over shiny copper, each lit first, then mixed through the layers (the paper's two-layer model)",
            ),
            fact(
                "CLI",
                format!(
                    "asperity surface-ca builtin:cup --app corrosion --cells {n} --steps {steps} -o patina.glb"
                ),
            ),
        ],
    ))
}

/// A third application on the same engine: Gray–Scott spots on the sphere.
fn gray_scott(env: &Env) -> Result<Item> {
    let (n, steps) = if env.quick {
        (8_000, 1500)
    } else {
        (40_000, 4000)
    };
    let cov = covered(env, shapes::icosphere(3, 1.0), n)?;
    let mut st = seeded_state(&cov.cells, 12, env.seed);
    let opts = RunOptions {
        seed: env.seed,
        max_steps: steps,
        stop_when_stable: false,
    };
    run(&cov.cells, &GrayScott::default(), &mut st, &opts, |_, _| {
        true
    });
    let m = cov.cell_mesh(|c| rd_color(&st[c]))?;
    let (file, pic) = env.colored_mesh("surfca_gray_scott", &m)?;
    Ok(Item::new(
        format!("Gray–Scott reaction–diffusion after {steps} steps: the engine is general"),
        Some(pic),
        vec![file],
        vec![
            fact("cells", cov.cells.len()),
            fact("F, k", "0.0367, 0.0649 (Pearson's self-replicating spots)"),
            fact(
                "CLI",
                "asperity surface-ca builtin:sphere --app gray-scott --cells 40000 --steps 4000 -o rd.glb",
            ),
        ],
    ))
}
