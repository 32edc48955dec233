//! Peridier's cellular-automaton surfaces, figure by figure: rule 450's facets
//! (Figure 1), its table (Figure 2), its steps (Figure 3), the rule gallery
//! (Figure 4), smooth shading against facets (Figure 6), a draped circle
//! (Figure 9), and a large surface.

use asperity_engine::Result;
use asperity_engine::ca::{CaGalleryParams, RuleCode, gallery_image, render_facets};
use asperity_engine::core::{Diagonal, HeightField, RgbaImage};
use asperity_engine::io::{Surface, WriteOptions};
use asperity_engine::methods::ca::facets::{circle, drape, facet_mesh};
use asperity_engine::methods::ca::{
    Boundary, CaParams, Family, Init, Rule, accumulate, initial_grid,
};
use asperity_engine::methods::render::cells::{cell_image, strip};
use asperity_engine::methods::render::{
    ColorMap, Polyline, RenderOptions, Shader, hillshade, render_mesh,
};
use asperity_engine::params::Size2;

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any CA run's, writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let rule450 = Rule::new(Family::Totalistic9, 2, 450)?;
    let flat = RenderOptions {
        shader: Shader::Flat,
        ..env.view()
    };
    let mut items = figures_1_to_3(env, &rule450, &flat)?;
    items.push(figure_4(env)?);
    items.extend(figures_6_and_9(env, &flat)?);
    items.extend(large(env, rule450, &flat)?);
    Ok(Section {
        title: "Cellular-automaton surfaces (peridier)".into(),
        source: "asperity-ca — peridier, Figures 1–4, 6, 7, 9".into(),
        blurb: "Elevations are the cell-by-cell sum of the steps of a 2-D totalistic cellular automaton (Wolfram numbering), drawn with \
                flat triangular facets on alternating diagonals, with an interpolation consistent with them."
            .into(),
        items,
    })
}

/// Figures 1–3: rule 450 on a 21×15 grid for 5 steps — the facets, the table,
/// and the steps summed into it.
fn figures_1_to_3(env: &Env, rule450: &Rule, flat: &RenderOptions) -> Result<Vec<Item>> {
    let init = initial_grid(&Init::Seed, Some([21, 15]), 2, &env.budget)?;
    let params = CaParams {
        keep_states: true,
        ..CaParams::new(rule450.clone(), 5)
    };
    let run = accumulate(&init, &params, &env.budget)?;
    env.write(
        "ca_rule450_21x15.npy",
        &Surface::Height(run.heights.clone()),
    )?;
    let fig1 = env.picture("ca_fig1_rule450.png", &render_facets(&run.heights, flat)?)?;
    let (lo, hi) = run.heights.min_max();
    let fig3 = env.picture(
        "ca_fig3_steps.png",
        &steps_strip(run.states.as_deref().unwrap_or(&[]), [21, 15]),
    )?;
    Ok(vec![
        Item::new(
            "Figure 1: rule 450, 21×15 grid, 5 steps, facets",
            Some(fig1),
            vec!["ca_rule450_21x15.npy".into()],
            vec![
                fact("rule", "two-state nine-neighbour totalistic 450"),
                fact(
                    "initial grid",
                    "one centre cell (the paper's default is not stated)",
                ),
                fact("heights", format!("{lo} … {hi}")),
            ],
        ),
        figure_2(rule450),
        Item::new(
            "Figure 3: steps 0–5, summed cell by cell into Figure 1",
            Some(fig3),
            vec![],
            vec![fact("state 1", "black")],
        ),
    ])
}

/// Figure 2: the rule's look-up table as facts.
fn figure_2(rule: &Rule) -> Item {
    let rows = rule
        .describe()
        .lines()
        .skip(1)
        .map(|l| {
            let (k, v) = l.split_once(':').unwrap_or((l, ""));
            fact(k.trim(), v.trim())
        })
        .collect();
    Item::new(
        "Figure 2: the look-up table of rule 450",
        None,
        vec![],
        rows,
    )
}

/// The steps side by side, state 1 black, cells 8 pixels apart.
fn steps_strip(states: &[u8], [nx, ny]: [usize; 2]) -> RgbaImage {
    let color = |v: u8| {
        if v == 1 {
            [0, 0, 0, 255]
        } else {
            [235, 235, 235, 255]
        }
    };
    let steps: Vec<RgbaImage> = states
        .chunks(nx * ny)
        .map(|s| cell_image(s, [nx, ny], 8, true, [255; 4], color))
        .collect();
    strip(&steps, 6, [255; 4])
}

/// Figure 4: rules 8 and 480 × two initial conditions.
fn figure_4(env: &Env) -> Result<Item> {
    let grid = CaGalleryParams {
        rules: vec![RuleCode("8".into()), RuleCode("480".into())],
        inits: vec![
            format!("random:0.2@{}", env.seed),
            format!("random:0.5@{}", env.seed),
        ],
        tile: Size2(if env.quick { [240, 180] } else { [400, 300] }),
        ..CaGalleryParams::default()
    };
    let fig4 = env.picture(
        "ca_fig4_gallery.png",
        &gallery_image(
            &grid,
            env.seed,
            &env.budget,
            &asperity_engine::core::TimeBudget::unlimited(),
        )?,
    )?;
    Ok(Item::new(
        "Figure 4: rows = rules 8, 480; columns = two initial conditions",
        Some(fig4),
        vec![],
        vec![
            fact("grid", "41×41 cyclic, 10 steps"),
            fact("columns", "random densities 0.2 and 0.5"),
            fact("CLI", "asperity ca gallery --rules 8,480 …"),
        ],
    ))
}

/// Figures 5/6 and 9: smooth shading versus facets on random data, and a
/// circle draped on the facets.
fn figures_6_and_9(env: &Env, flat: &RenderOptions) -> Result<Vec<Item>> {
    let mut rng = asperity_engine::core::seeded(env.seed);
    let heights = (0..225)
        .map(|_| rand::Rng::random::<f64>(&mut rng) * 3.0)
        .collect();
    let rand_h = HeightField::from_vec([15, 15], heights)?;
    let smooth = rand_h.to_trimesh(Diagonal::Forward)?;
    let phong = RenderOptions {
        shader: Shader::Phong,
        ..env.view()
    };
    let fig6a = env.render("ca_fig6_smooth.png", &smooth, &phong)?;
    let facets = facet_mesh(&rand_h, true)?;
    let fig6b = env.render("ca_fig6_facets.png", &facets, flat)?;
    let fig9 = figure_9(env, &rand_h, flat)?;
    Ok(vec![
        Item::new(
            "Figure 6: irregular data, smoothly shaded",
            Some(fig6a),
            vec![],
            vec![fact(
                "what",
                "one diagonal everywhere, smooth normals: interpolation artefacts",
            )],
        ),
        Item::new(
            "Figure 6: the same data as alternating-diagonal facets",
            Some(fig6b),
            vec![],
            vec![fact(
                "what",
                "flat facets, nodes in 4 or 8 facets (Figure 7)",
            )],
        ),
        fig9,
    ])
}

/// Figure 9: a circle draped on the facets, written as mesh + lines.
fn figure_9(env: &Env, h: &HeightField, flat: &RenderOptions) -> Result<Item> {
    let facets = facet_mesh(h, true)?;
    let ring = drape(h, &circle(7.0, 7.0, 5.0, 180))?;
    env.mesh("ca_fig9_circle.ply", &facets)?;
    let obj = env.dir.join("ca_fig9_circle.obj");
    asperity_engine::io::write_mesh_with_polylines(
        &obj,
        &facet_mesh(h, false)?,
        std::slice::from_ref(&ring),
        &WriteOptions::default(),
    )?;
    env.report.borrow_mut().output(&obj);
    let opts = RenderOptions {
        polylines: vec![Polyline {
            points: ring.clone(),
            color: [220, 30, 30, 255],
            closed: true,
        }],
        ..flat.clone()
    };
    let fig9 = env.picture("ca_fig9_circle.png", &render_mesh(&facets, &opts)?)?;
    Ok(Item::new(
        "Figure 9: a circle drawn on the facets",
        Some(fig9),
        vec!["ca_fig9_circle.ply".into(), "ca_fig9_circle.obj".into()],
        vec![
            fact("curve points", ring.len()),
            fact(
                "method",
                "split at every grid line and facet diagonal, z by the four-case interpolation",
            ),
        ],
    ))
}

/// A large cyclic surface of rule 450, in 3-D and as a map.
fn large(env: &Env, rule450: Rule, flat: &RenderOptions) -> Result<Vec<Item>> {
    let n = if env.quick { 128 } else { 256 };
    let steps = if env.quick { 24 } else { 48 };
    let init = Init::Random {
        density: 0.3,
        seed: env.seed,
    };
    let grid = initial_grid(&init, Some([n, n]), 2, &env.budget)?;
    let t = std::time::Instant::now();
    let params = CaParams {
        boundary: Boundary::Cyclic,
        ..CaParams::new(rule450, steps)
    };
    let big = accumulate(&grid, &params, &env.budget)?;
    let secs = t.elapsed().as_secs_f64();
    env.write(
        "ca_rule450_large.gsf",
        &Surface::Height(big.heights.clone()),
    )?;
    let view = env.picture("ca_large_3d.png", &render_facets(&big.heights, flat)?)?;
    let map = env.picture(
        "ca_large_map.png",
        &hillshade::height_map(&big.heights, ColorMap::Magma, 0.4, true),
    )?;
    // Timings go to report.json only: the page must be the same bytes on every run.
    env.measure("ca_large_seconds", secs);
    let cli =
        format!("asperity ca run --rule 450 --steps {steps} --init random:0.3 --size {n}x{n}");
    Ok(vec![
        Item::new(
            format!("Rule 450, {n}×{n} cyclic, {steps} steps"),
            Some(view),
            vec!["ca_rule450_large.gsf".into()],
            vec![
                fact("initial grid", "random, density 0.3"),
                fact("CLI", cli),
            ],
        ),
        Item::new(
            "The same surface as a map",
            Some(map),
            vec![],
            vec![fact("colour map", "magma with relief")],
        ),
    ])
}
