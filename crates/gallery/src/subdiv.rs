//! Multiresolution subdivision surfaces with procedural detail (velho-perlin):
//! the cube's limit surface in its cage, the example scenes of the paper's
//! figures (`crates/subdiv/scenes`), a tentacle growing level by level
//! (Figure 5) and spurs placed at chosen levels (Figure 9).

use std::path::Path;

use asperity_engine::Result;
use asperity_engine::core::TriMesh;
use asperity_engine::core::vec3::{add, cross, dist, dot, norm, scale, sub, unit};
use asperity_engine::error::invalid;
use asperity_engine::methods::render::{Polyline, RenderOptions};
use asperity_engine::methods::subdiv::catmull_clark::{Boundary, Creased, limit_positions};
use asperity_engine::methods::subdiv::compose::{Anchor, Layer, grow};
use asperity_engine::methods::subdiv::detail::{
    Berry, Feature, Procedure, Seeds, Spur, Tentacle, TentacleReading,
};
use asperity_engine::methods::subdiv::evaluate::{Composed, evaluate};
use asperity_engine::methods::subdiv::multires::synthesize;
use asperity_engine::subdiv::load_base;

use crate::{Env, Item, Section, fact};

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
        "planet_earth",
        include_str!("../../subdiv/scenes/planet_earth.toml"),
        "Earth-like planet (§6.2, Fig. 12a): the 1/f rock scalar alone, shaded",
    ),
    (
        "planet_alien",
        include_str!("../../subdiv/scenes/planet_alien.toml"),
        "Alien planet (§6.2, Fig. 12b): the rougher, slower-decaying rock scalar alone, shaded",
    ),
    (
        "planet",
        include_str!("../../subdiv/scenes/planet.toml"),
        "Blended planet (§6.2, Fig. 12c): 12a and 12b blended level by level, then shaded",
    ),
];

/// The section.
///
/// # Errors
/// Any scene's, writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let mut items = vec![cube_limit(env)?];
    for (name, text, title) in SCENES {
        items.push(scene(env, name, text, title)?);
    }
    items.push(figure_4(env)?);
    items.extend(figure_10(env)?);
    items.extend(figure_5(env)?);
    items.push(figure_9(env)?);
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

/// The cube and its limit surface (4 levels), with the control cage.
fn cube_limit(env: &Env) -> Result<Item> {
    let cube = Creased::smooth(asperity_engine::methods::subdiv::base::cube());
    let levels = synthesize(&cube, &[], 4, Boundary::EdgeOnly)?;
    let fine = &levels[4];
    let limit = fine
        .mesh
        .clone()
        .with_positions(limit_positions(fine, Boundary::EdgeOnly)?)?;
    let tri = limit.triangulate().with_computed_normals();
    let p = cube.mesh.positions();
    let cage = cube
        .mesh
        .faces()
        .map(|f| Polyline {
            points: f.iter().map(|&v| p[v as usize]).collect(),
            color: [200, 40, 40, 255],
            closed: true,
        })
        .collect();
    let file = env.mesh("subdiv_cube_limit.ply", &tri)?;
    let opts = RenderOptions {
        polylines: cage,
        ..env.view()
    };
    let pic = env.render("subdiv_cube_limit.png", &tri, &opts)?;
    Ok(Item::new(
        "Catmull–Clark: the cube's limit surface (4 levels) inside its control cage",
        Some(pic),
        vec![file],
        vec![
            fact("corner after 1 / 2 levels", "5/9, 55/108 (exact, tested)"),
            fact(
                "CLI",
                "asperity subdiv --base cube --levels 4 --limit -o cube.ply",
            ),
        ],
    ))
}

/// One example scene, as in the paper's figure.
fn scene(env: &Env, name: &str, text: &str, title: &str) -> Result<Item> {
    let t = if name == "tentacle" { 0.15 } else { 0.0 };
    let mut scene = asperity_engine::methods::subdiv::scene::parse(text, t)
        .map_err(|e| invalid(format!("scene {name}: {e}")))?;
    if env.quick {
        scene.levels = scene.levels.saturating_sub(1).max(2);
    }
    let base = Creased::smooth(load_base(&scene.base, Path::new(""), &env.budget)?);
    let clock = std::time::Instant::now();
    let c = evaluate(
        &scene,
        &base,
        &Default::default(),
        &asperity_engine::core::NoProgress,
    )?;
    // Timings go to report.json (the gallery must not depend on them).
    env.measure(
        &format!("subdiv_{name}_seconds"),
        clock.elapsed().as_secs_f64(),
    );
    let tri = c.mesh.mesh.triangulate().with_computed_normals();
    let n_vertices = tri.n_vertices();
    let (files, pic) = scene_files(env, name, &c, tri)?;
    Ok(Item::new(
        title,
        Some(pic),
        files,
        vec![
            fact("levels", scene.levels),
            fact("vertices", n_vertices),
            fact("quads", c.mesh.mesh.n_faces()),
            fact(
                "CLI",
                format!("asperity subdiv crates/subdiv/scenes/{name}.toml -o {name}.glb"),
            ),
        ],
    ))
}

/// A scene's mesh and picture: in its colours (scalar mode), polished metal to
/// rust by the blend weight (blends), or shaded. A coloured scene is also
/// written as `.glb` (linear `COLOR_0`), the file Blender users open.
fn scene_files(env: &Env, name: &str, c: &Composed, tri: TriMesh) -> Result<(Vec<String>, String)> {
    let stem = format!("subdiv_{name}");
    let alpha = c
        .scalars
        .iter()
        .find(|(n, _)| n == "alpha")
        .map(|(_, v)| v.clone());
    let colored = match (&c.colors, alpha) {
        (Some(col), _) => tri.with_colors(col.clone())?,
        (None, Some(a)) => {
            let col = a
                .iter()
                .map(|&t| {
                    let m = |x: f64, y: f64| (x + (y - x) * t) as u8;
                    [m(175.0, 140.0), m(180.0, 70.0), m(190.0, 30.0), 255]
                })
                .collect();
            tri.with_scalar("alpha", a)?.with_colors(col)?
        }
        (None, None) => {
            let (file, pic) = env.shaded_mesh(&stem, &tri)?;
            return Ok((vec![file], pic));
        }
    };
    let (file, pic) = env.colored_mesh(&stem, &colored)?;
    let glb = env.mesh(&format!("{stem}.glb"), &colored)?;
    Ok((vec![file, glb], pic))
}

/// Meshes placed in a row along x (for figures that compare stages).
fn side_by_side(meshes: &[TriMesh]) -> Result<TriMesh> {
    let mut pos = Vec::new();
    let mut tris = Vec::new();
    let mut x = 0.0;
    for m in meshes {
        let b = m.bounds().ok_or_else(|| invalid("a mesh has vertices"))?;
        let shift = x - b.min[0];
        let first = pos.len() as u32;
        pos.extend(m.positions().iter().map(|p| [p[0] + shift, p[1], p[2]]));
        tris.extend(m.triangles().iter().map(|t| t.map(|v| v + first)));
        x += b.max[0] - b.min[0] + 0.3 * (b.max[0] - b.min[0]);
    }
    Ok(TriMesh::new(pos, tris)?)
}

/// A row of the finest levels of `layers` grown on the sphere, with normals.
fn row(env: &Env, layers: impl Iterator<Item = (usize, Layer)>) -> Result<TriMesh> {
    let sphere = Creased::smooth(asperity_engine::methods::subdiv::base::quad_sphere(2));
    let meshes = layers
        .map(|(levels, layer)| {
            let m = grow(&sphere, levels, Boundary::EdgeOnly, &layer, env.seed)?;
            Ok(m.finest().mesh.triangulate())
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(side_by_side(&meshes)?.with_computed_normals())
}

fn one_feature(name: &str, feature: Feature) -> Layer {
    Layer {
        name: name.into(),
        features: vec![feature],
        edits: Vec::new(),
    }
}

/// A tentacle from the paper's pseudo-code, grown as a limb or applied to the
/// seed vertex alone (with or without the sign flip on even levels).
fn tentacle(reading: TentacleReading, alternate: bool) -> Layer {
    one_feature(
        "t",
        Feature {
            procedure: Procedure::Tentacle(Tentacle {
                length: 0.15,
                theta: 0.5,
                alternate,
                twist: true,
                reading,
            }),
            seeds: Seeds::Points(vec![[0.3, -1.0, 0.3]]),
            levels: None,
        },
    )
}

/// Figure 5: tentacle growth, levels 1–4: the limb reading, and the literal
/// one with and without the sign flip.
fn figure_5(env: &Env) -> Result<Vec<Item>> {
    let limb = TentacleReading::Limb {
        radius: 0.45,
        taper: 0.7,
    };
    let mut items = Vec::new();
    for (reading, alternate, stem, title) in [
        (
            limb,
            false,
            "subdiv_fig5_tentacle_limb",
            "Figure 5: a tentacle growing over levels 1 to 4 (left to right) — each level extrudes a narrower cap further out, turned by π/3 (the limb reading of the pseudo-code)",
        ),
        (
            TentacleReading::Literal,
            true,
            "subdiv_fig5_tentacle_levels",
            "Figure 5, literal reading: the pseudo-code's offset on the seed vertex alone — the sign flip on even levels digs the tip in",
        ),
        (
            TentacleReading::Literal,
            false,
            "subdiv_fig5_tentacle_levels_no_flip",
            "Figure 5, literal reading without the sign flip: a short curling horn",
        ),
    ] {
        let tri = row(env, (1..=4).map(|l| (l, tentacle(reading, alternate))))?;
        let (file, pic) = env.shaded_mesh(stem, &tri)?;
        let law = match (reading, alternate) {
            (TentacleReading::Limb { .. }, _) => {
                "a ball of radius 0.45·0.7ˡ⁻¹ around the tip moved length·l along (sin(θ + πl/3), cos(θ + πl/3), 1)"
            }
            (_, true) => "length·l·(sin(θ + πl/3), cos(θ + πl/3), 1), negated on even levels",
            (_, false) => "length·l·(sin(θ + πl/3), cos(θ + πl/3), 1)",
        };
        let facts = vec![fact("per level", law)];
        items.push(Item::new(title, Some(pic), vec![file], facts));
    }
    Ok(items)
}

/// Figure 4: the berry's construction — domes from the initial seeds (a,
/// level 1 of detail), the first recursion added (b), the final berry after
/// three levels of detail (c).
fn figure_4(env: &Env) -> Result<Item> {
    let berry = |detail_levels: Vec<usize>| {
        one_feature(
            "b",
            Feature {
                procedure: Procedure::Berry(Berry {
                    radius: 0.45,
                    ratio: 0.5,
                    children: 5,
                    height: 0.8,
                }),
                seeds: Seeds::Poisson { spacing: 0.9 },
                levels: Some(detail_levels),
            },
        )
    };
    let levels = if env.quick { 4 } else { 5 };
    let tri = row(
        env,
        [vec![2], vec![2, 3], vec![2, 3, 4]]
            .into_iter()
            .map(|ls| (levels, berry(ls))),
    )?;
    let (file, pic) = env.shaded_mesh("subdiv_fig4_berry_stages", &tri)?;
    Ok(Item::new(
        "Figure 4: the berry — (a) base domes from the initial seeds, (b) the first recursion added, (c) three levels of detail",
        Some(pic),
        vec![file],
        vec![
            fact(
                "dome",
                "R·√(1 − r²/R²) along the evolving normal, R halved per level",
            ),
            fact(
                "children",
                "up to 5 Poisson-disk seeds inside each parent dome",
            ),
        ],
    ))
}

/// Figure 10: local signal processing — (a) the rock of `edited_rock.toml`
/// without its edits, (b) with them: smoothed near +z, exaggerated near +x.
/// Red rings mark each edit's disc: its radius in base edges (the edit
/// measures it in edge hops on the surface; the ring is that length along a
/// great circle).
fn figure_10(env: &Env) -> Result<Vec<Item>> {
    let text = include_str!("../../subdiv/scenes/edited_rock.toml");
    let mut scene = asperity_engine::methods::subdiv::scene::parse(text, 0.0)
        .map_err(|e| invalid(format!("scene edited_rock: {e}")))?;
    if env.quick {
        scene.levels = scene.levels.saturating_sub(1).max(2);
    }
    let base = Creased::smooth(load_base(&scene.base, Path::new(""), &env.budget)?);
    let rings = edit_rings(&base, &scene.layers[0].edits);
    let mut items = Vec::new();
    for (edited, stem, title) in [
        (
            false,
            "subdiv_fig10_original",
            "Figure 10 (a): the rock before local editing",
        ),
        (
            true,
            "subdiv_fig10_edited",
            "Figure 10 (b): local signal processing — fine levels removed near +z (smoothed), levels 2–5 tripled near +x; red rings: the edit discs",
        ),
    ] {
        let mut sc = scene.clone();
        if !edited {
            sc.layers[0].edits.clear();
        }
        let c = evaluate(
            &sc,
            &base,
            &Default::default(),
            &asperity_engine::core::NoProgress,
        )?;
        let tri = c.mesh.mesh.triangulate().with_computed_normals();
        let file = env.mesh(&format!("{stem}.ply"), &tri)?;
        let opts = RenderOptions {
            polylines: rings.clone(),
            ..env.view()
        };
        let pic = env.render(&format!("{stem}.png"), &tri, &opts)?;
        items.push(Item::new(
            title,
            Some(pic),
            vec![file],
            vec![fact(
                "CLI",
                "asperity subdiv crates/subdiv/scenes/edited_rock.toml -o e.glb",
            )],
        ));
    }
    Ok(items)
}

/// A red ring per edit: a great circle of the sphere through its centre with
/// the edit's radius in mean base-edge lengths, lifted off the relief.
fn edit_rings(
    base: &Creased,
    edits: &[asperity_engine::methods::subdiv::compose::Edit],
) -> Vec<Polyline> {
    let p = base.mesh.positions();
    let edges: Vec<f64> = base
        .mesh
        .faces()
        .flat_map(|f| (0..f.len()).map(move |k| (f[k], f[(k + 1) % f.len()])))
        .map(|(a, b)| dist(p[a as usize], p[b as usize]))
        .collect();
    let edge = edges.iter().sum::<f64>() / edges.len().max(1) as f64;
    edits
        .iter()
        .filter_map(|e| match e.at {
            Anchor::Point(c) => Some((c, e.radius * edge)),
            Anchor::Vertex(v) => p.get(v as usize).map(|&c| (c, e.radius * edge)),
        })
        .filter_map(|(c, r)| ring(c, r))
        .collect()
}

/// The circle of the sphere through `c` (centred at the origin) of geodesic
/// radius `r` around `c`, lifted 8 % off the surface so the relief does not
/// hide it.
fn ring(c: [f64; 3], r: f64) -> Option<Polyline> {
    let n = unit(c)?;
    let a = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = unit(sub(a, scale(n, dot(a, n))))?;
    let w = cross(n, u);
    let theta = r / norm(c);
    let lift = 1.08 * norm(c);
    let points = (0..96)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 96.0;
            let around = add(scale(u, t.cos()), scale(w, t.sin()));
            scale(add(scale(n, theta.cos()), scale(around, theta.sin())), lift)
        })
        .collect();
    Some(Polyline {
        points,
        color: [220, 30, 30, 255],
        closed: true,
    })
}

/// Figure 9: spurs placed at level 1 (a), at level 3 (b), at both (c).
fn figure_9(env: &Env) -> Result<Item> {
    let spurs = |levels: Vec<usize>| {
        one_feature(
            "s",
            Feature {
                procedure: Procedure::Spur(Spur { height: 2.5 }),
                seeds: Seeds::Poisson { spacing: 0.6 },
                levels: Some(levels),
            },
        )
    };
    let tri = row(
        env,
        [vec![1], vec![3], vec![1, 3]]
            .into_iter()
            .map(|ls| (4, spurs(ls))),
    )?;
    let (file, pic) = env.shaded_mesh("subdiv_fig9_spur_levels", &tri)?;
    Ok(Item::new(
        "Figure 9: spurs placed at level 1 (a), at level 3 (b), at both (c)",
        Some(pic),
        vec![file],
        vec![fact(
            "spur",
            "the seed vertex pushed 2.5 mean edge lengths of its level along n",
        )],
    ))
}
