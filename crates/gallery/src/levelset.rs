//! Level-set reconstruction (kim-machiraju-thompson §5–6): the two-pass
//! pipeline on the paper's examples — RDSR on a sphere (Figure 8) and a DLA
//! terrain with arches (Figures 9–10) — from the initial surface by tagging to
//! the converged flow, and the §6 contrast of the convection flow with a
//! curvature-regularised one.

use asperity_core::{NoProgress, TriMesh};
use asperity_engine::Result;
use asperity_engine::error::invalid;
use asperity_growth::dla::{DlaParams, SeedShape, Sides, dla};
use asperity_levelset::{
    ExtractOptions, FlowChoice, ReconstructParams, Sizing, extract, reconstruct,
};
use asperity_render::plot::{Plot, Series, Style, plot_svg};

use crate::growth::rdsr_sphere;
use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any simulation's, reconstruction's, writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let mut items = Vec::new();
    let mut movement = Vec::new();
    for case in cases(env)? {
        let (initial, converged, steps) = pipeline(env, &case)?;
        items.push(initial);
        items.push(converged);
        movement.push((case.name, steps));
    }
    items.push(convergence(env, movement)?);
    let rough = bumpy_sphere(env.seed, if env.quick { 3_000 } else { 12_000 });
    for (flow, weight) in [("convection", None), ("regularized", Some(2.0))] {
        items.push(flow_contrast(env, &rough, flow, weight)?);
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

/// A point set of one of the paper's figures, with its caption and CLI line.
struct Case {
    name: &'static str,
    title: String,
    points: Vec<[f64; 3]>,
    cli: String,
}

/// Fig. 8: RDSR on a sphere; Fig. 9: DLA from the plane.
fn cases(env: &Env) -> Result<Vec<Case>> {
    let (radius, layers) = if env.quick { (10.0, 5.0) } else { (20.0, 10.0) };
    let sphere = rdsr_sphere(radius, layers, env)?.points();
    let (side, particles) = if env.quick { (32, 1_500) } else { (64, 6_000) };
    let params = DlaParams {
        dim: 3,
        size: [side, side, side],
        particles,
        stick: 1.0,
        seed_shape: SeedShape::Plane,
        launch_gap: 2.0,
        sides: Sides::Walls,
    };
    let terrain = dla(&params, env.seed, 0, &env.budget, &NoProgress)?.points();
    Ok(vec![
        Case {
            name: "sphere",
            title: format!("Figure 8: RDSR on a sphere (radius {radius}, {layers} monolayers)"),
            points: sphere,
            cli: format!(
                "asperity generate rdsr-sphere --radius {radius} --layers {layers} -o sphere.glb"
            ),
        },
        Case {
            name: "terrain",
            title: format!(
                "Figures 9–10: DLA terrain with arches ({side}³ lattice, {particles} particles)"
            ),
            points: terrain,
            cli: format!(
                "asperity generate dla-terrain --size {side}x{side}x{side} --particles {particles} -o terrain.glb"
            ),
        },
    ])
}

/// Front movement per step: (step, cells).
type Movement = Vec<(f64, f64)>;

/// The pipelines' settings (`asperity generate …`): h = 0.7, ε = 3, 60 steps.
fn pipeline_params() -> ReconstructParams {
    ReconstructParams {
        sizing: Sizing::Spacing(0.7),
        offset: Some(asperity_levelset::Length::World(3.0)),
        iterations: 60,
        extract: ExtractOptions {
            curvature: false,
            min_shell_triangles: 32,
        },
        ..Default::default()
    }
}

/// The card of the initial surface by tagging.
fn initial_item(env: &Env, case: &Case, initial: &TriMesh, dims: [usize; 3]) -> Result<Item> {
    let (file, pic) = env.shaded_mesh(&format!("levelset_{}_initial", case.name), initial)?;
    Ok(Item::new(
        format!("{}: initial surface by tagging (ε = 3)", case.title),
        Some(pic),
        vec![file],
        vec![
            fact(
                "grid",
                format!("{}×{}×{}, h = 0.7", dims[0], dims[1], dims[2]),
            ),
            fact("triangles", initial.n_faces()),
        ],
    ))
}

/// The pipeline's defaults (`asperity generate …`): the initial surface and the
/// converged one as cards, and the front movement per step.
fn pipeline(env: &Env, case: &Case) -> Result<(Item, Item, Movement)> {
    let params = pipeline_params();
    let mut initial = None;
    let rec = reconstruct(
        &case.points,
        &params,
        &env.budget,
        &NoProgress,
        &mut |s, ls| {
            if s.step == 0 {
                initial = Some(extract(&ls.phi, &ls.grid, &params.extract).0);
            }
        },
    )?;
    let initial: TriMesh =
        initial.ok_or_else(|| invalid("the pipeline reports its initial surface"))?;
    let start = initial_item(env, case, &initial, rec.grid.dims)?;
    let m = &rec.mesh;
    let (file, pic) = env.shaded_mesh(&format!("levelset_{}", case.name), m)?;
    let steps = &rec.evolution.steps;
    let end = Item::new(
        format!(
            "{}: after {} steps of the convection flow",
            case.title,
            steps.len()
        ),
        Some(pic),
        vec![file],
        vec![
            fact("points", case.points.len()),
            fact("triangles", m.n_faces()),
            fact("watertight", m.is_watertight()),
            fact("genus", m.genus().map_or("—".into(), |g| g.to_string())),
            fact("pieces", rec.extraction.components),
            fact("CLI", &case.cli),
        ],
    );
    let movement = steps
        .iter()
        .map(|s| (s.step as f64, s.front_movement.max(1e-6)))
        .collect();
    Ok((start, end, movement))
}

/// The front movement per step of every case on one plot.
fn convergence(env: &Env, movement: Vec<(&str, Movement)>) -> Result<Item> {
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
    let svg = env.text("levelset_movement.svg", &plot_svg(&plot, 800, 560)?)?;
    Ok(Item::new(
        "Convergence: the front stops on the data",
        Some(svg),
        vec![],
        vec![fact("checks", "crates/levelset/tests/reconstruction.rs")],
    ))
}

/// `n` points on a sphere with a deterministic bumpy radius.
fn bumpy_sphere(seed: u64, n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut rng_state = seed ^ 0x9e37_79b9_7f4a_7c15;
    (0..n)
        .map(|i| {
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
        .collect()
}

/// §6: the convection flow keeps roughness that a curvature term removes.
fn flow_contrast(env: &Env, rough: &[[f64; 3]], flow: &str, weight: Option<f64>) -> Result<Item> {
    let params = ReconstructParams {
        sizing: Sizing::Resolution(if env.quick { 48 } else { 80 }),
        flow: match weight {
            Some(weight_cells) => FlowChoice::Regularized { weight_cells },
            None => FlowChoice::Convection,
        },
        ..Default::default()
    };
    let rec = reconstruct(rough, &params, &env.budget, &NoProgress, &mut |_, _| {})?;
    let (file, pic) = env.shaded_mesh(&format!("levelset_flow_{flow}"), &rec.mesh)?;
    Ok(Item::new(
        format!("The {flow} flow on a bumpy sphere"),
        Some(pic),
        vec![file],
        vec![
            fact("area", format!("{:.4}", rec.mesh.area())),
            fact(
                "CLI",
                format!("asperity reconstruct pts.ply --flow {flow} -o mesh.ply"),
            ),
        ],
    ))
}
