//! The renderer: shaders on a rough rock, views with overlays, height-field
//! map views, point splats and plots (the light model is gobron-chiba's
//! "Simple Light Model").

use asperity_engine::Result;
use asperity_engine::core::fourier_surface::{FourierParams, fourier_surface};
use asperity_engine::core::{HeightField, TriMesh};
use asperity_engine::methods::render::plot::histogram_svg;
use asperity_engine::methods::render::{
    ColorMap, Polyline, Projection, RenderOptions, Shader, View, hillshade, render_height,
    render_points,
};
use rand::Rng;

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let rock = rock(if env.quick { 5 } else { 6 }, env.seed)?;
    let mut items = shaders(env, &rock)?;
    env.mesh("rock.ply", &rock)?;
    items.push(overlay(env, &rock)?);
    items.extend(height_views(env)?);
    items.push(splats(env)?);
    items.push(curvature_plot(env, &rock)?);
    Ok(Section {
        title: "Renderer: shaders, views, overlays, plots".into(),
        source: "asperity-render — light model from gobron-chiba §\"Simple Light Model\"".into(),
        blurb: "Headless CPU rendering with 4× supersampling, shadows from the key light and ambient obscurance. \
                Every picture in this gallery comes from `asperity render` code paths."
            .into(),
        items,
    })
}

/// An icosphere displaced radially by 3-D random-phase Fourier noise with a
/// power-law spectrum (amplitude ∝ |k|^−(1+H)): a rough "rock" for the shaders.
fn rock(level: u32, seed: u64) -> Result<TriMesh> {
    let sphere = asperity_engine::core::shapes::icosphere(level, 1.0);
    let mut rng = asperity_engine::core::seeded(seed);
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

/// The rock under each shader.
fn shaders(env: &Env, rock: &TriMesh) -> Result<Vec<Item>> {
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
        let opts = RenderOptions {
            shader,
            ..env.view()
        };
        let file = env.render(&format!("render_rock_{name}.png"), rock, &opts)?;
        items.push(Item::new(
            format!("Shader: {name}"),
            Some(file),
            vec![],
            vec![fact("what", caption), fact("triangles", rock.n_faces())],
        ));
    }
    Ok(items)
}

/// The rock's profile in the plane z = 0, drawn over it: a polyline overlay.
fn overlay(env: &Env, rock: &TriMesh) -> Result<Item> {
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
    let opts = RenderOptions {
        view: View::Front,
        polylines: vec![Polyline {
            points: equator,
            color: [220, 40, 40, 255],
            closed: true,
        }],
        ..env.view()
    };
    let file = env.render("render_rock_front_polyline.png", rock, &opts)?;
    Ok(Item::new(
        "Front view with a polyline overlay",
        Some(file),
        vec!["rock.ply".into()],
        vec![fact("overlay", "the rock's equator, depth-tested")],
    ))
}

fn terrain(n: usize, spacing: f64, env: &Env) -> Result<HeightField> {
    let p = FourierParams {
        n,
        hurst: 0.8,
        modes: 16,
        rms: 0.06,
        spacing,
    };
    Ok(fourier_surface(&p, env.seed + 1, &env.budget)?)
}

/// A height field as hillshade and as an orthographic top view.
fn height_views(env: &Env) -> Result<Vec<Item>> {
    let h = terrain(if env.quick { 65 } else { 129 }, 1.0 / 128.0, env)?;
    let relief = env.picture(
        "render_height_hillshade.png",
        &hillshade::hillshade(&h, 315.0, 45.0),
    )?;
    let opts = RenderOptions {
        view: View::Top,
        projection: Projection::Orthographic,
        ..env.view()
    };
    let top = env.picture("render_height_top.png", &render_height(&h, &opts)?)?;
    Ok(vec![
        Item::new(
            "Height field: hillshade",
            Some(relief),
            vec![],
            vec![fact(
                "light",
                "azimuth 315°, altitude 45° (GDAL convention)",
            )],
        ),
        Item::new(
            "Height field: orthographic top view, height colour map",
            Some(top),
            vec![],
            vec![fact("colour map", "viridis, min → max")],
        ),
    ])
}

/// A point set coloured by height, drawn as lit splats.
fn splats(env: &Env) -> Result<Item> {
    let coarse = terrain(65, 1.0 / 64.0, env)?;
    let mut colored = coarse.to_point_set();
    let (lo, hi) = coarse.min_max();
    let cols = colored.positions().iter().map(|q| {
        let c = ColorMap::Magma.map((q[2] - lo) / (hi - lo).max(1e-300));
        [c[0], c[1], c[2], 255]
    });
    colored.set_colors(cols.collect())?;
    let file = env.picture("render_points.png", &render_points(&colored, &env.view())?)?;
    Ok(Item::new(
        "Point set as lit splats",
        Some(file),
        vec![],
        vec![fact("points", colored.len())],
    ))
}

/// A histogram of the rock's mean curvature as SVG.
fn curvature_plot(env: &Env, rock: &TriMesh) -> Result<Item> {
    let curv = asperity_engine::methods::render::render::mean_curvature(rock);
    let svg = histogram_svg(
        &curv,
        60,
        "Mean curvature of the rough sphere",
        "H (1/length; unit sphere: 1)",
        640,
        400,
    )?;
    let plot = env.text("plot_rock_curvature.svg", &svg)?;
    Ok(Item::new(
        "Plot: curvature histogram (SVG)",
        Some(plot),
        vec![],
        vec![fact(
            "reference",
            "an undisplaced unit sphere has H = 1 everywhere",
        )],
    ))
}
