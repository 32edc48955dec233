//! Properties over random input: scene text and detail specs never panic
//! (they parse or give an error, and parsed scenes evaluate or give an
//! error), and subdivision of perturbed meshes with random creases keeps the
//! Euler characteristic and finite positions.

use asperity_core::NoProgress;
use asperity_subdiv::base;
use asperity_subdiv::catmull_clark::{Boundary, Creased, subdivide};
use asperity_subdiv::evaluate::{Inputs, evaluate};
use asperity_subdiv::scene::{feature_from_spec, parse};
use proptest::prelude::*;

/// Scenes of random [[detail]] and [[edit]] tables: each detail has a type and
/// a random set of keys with values of every kind, good and bad.
fn scene_text() -> impl Strategy<Value = String> {
    let key = prop::sample::select(vec![
        "amplitude",
        "decay",
        "law",
        "coords",
        "frequency",
        "radius",
        "ratio",
        "children",
        "height",
        "length",
        "theta",
        "alternate",
        "twist",
        "levels",
        "at",
        "vertices",
        "spacing",
    ]);
    let value = prop::sample::select(vec![
        "\"fractal\"",
        "\"morphogenic\"",
        "\"independent\"",
        "\"extrinsic\"",
        "0",
        "1",
        "2",
        "3",
        "-1",
        "0.3",
        "0.9",
        "1e9",
        "nan",
        "inf",
        "[0, 2]",
        "[1, 2, 3]",
        "[]",
        "[[0, 0, 1]]",
        "[[0, 0]]",
        "[2]",
        "[99]",
        "[1, 3]",
        "true",
        "\"x\"",
    ]);
    let kind = prop::sample::select(vec![
        "rock", "fbm", "berry", "tentacle", "mine", "mushroom", "spur",
    ]);
    let detail = (kind, prop::collection::btree_map(key, value, 0..5)).prop_map(|(t, kv)| {
        let body: String = kv.iter().map(|(k, v)| format!("{k} = {v}\n")).collect();
        format!("[[detail]]\ntype = \"{t}\"\n{body}")
    });
    let edit = (
        prop::sample::select(vec!["at = [0, 0, 1]", "vertex = 3", "vertex = 999"]),
        prop::sample::select(vec!["0.5", "2", "-1", "nan"]),
        prop::sample::select(vec!["[1, 2]", "[2, 1]", "[0, 3]", "[1, 9]"]),
        prop::sample::select(vec!["0", "3", "-2"]),
    )
        .prop_map(|(at, r, l, f)| {
            format!("[[edit]]\n{at}\nradius = {r}\nlevels = {l}\nfactor = {f}\n")
        });
    (
        prop::sample::select(vec!["cube", "sphere", "plane"]),
        0usize..3,
        prop::collection::vec(detail, 0..4),
        prop::option::of(edit),
        prop::sample::select(vec!["", "mode = \"scalar\"\n", "limit = true\n"]),
    )
        .prop_map(|(b, l, details, edit, mode)| {
            format!(
                "base = \"{b}\"\nlevels = {l}\n{mode}{}{}",
                details.concat(),
                edit.unwrap_or_default()
            )
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn scene_text_never_panics(text in "\\PC{0,200}") {
        let _ = parse(&text, 0.5);
    }

    #[test]
    fn detail_specs_never_panic(spec in "[a-z]{0,9}(:[a-z]{0,9}=[-0-9.;a-z]{0,6}(,[a-z]{0,9}=[-0-9.;a-z]{0,6}){0,3})?") {
        let _ = feature_from_spec(&spec, 0.3);
    }

    #[test]
    fn parsed_scenes_evaluate_or_refuse(text in scene_text()) {
        if let Ok(scene) = parse(&text, 0.5) {
            let mesh = match scene.base.as_str() {
                "sphere" => base::quad_sphere(1),
                "plane" => base::plane(2),
                _ => base::cube(),
            };
            let _ = evaluate(&scene, &Creased::smooth(mesh), &Inputs::default(), &NoProgress);
        }
    }

    #[test]
    fn perturbed_meshes_with_creases_keep_euler(
        which in 0usize..3,
        jitter in prop::collection::vec(-0.2f64..0.2, 300),
        sharp in prop::collection::vec(prop::option::of(0.0f64..4.0), 40),
    ) {
        let (m, chi) = match which {
            0 => (base::cube(), 2),
            1 => (base::torus(1.0, 0.4, 6, 5), 0),
            _ => (base::cylinder(0.5, 1.0, 6), 2),
        };
        let pos: Vec<[f64; 3]> = m
            .positions()
            .iter()
            .enumerate()
            .map(|(i, p)| [p[0] + jitter[(3 * i) % 300], p[1] + jitter[(3 * i + 1) % 300], p[2] + jitter[(3 * i + 2) % 300]])
            .collect();
        let mut c = Creased::smooth(m.with_positions(pos).unwrap());
        let edges: Vec<(u32, u32)> = c
            .mesh
            .faces()
            .flat_map(|f| (0..f.len()).map(move |k| (f[k].min(f[(k + 1) % f.len()]), f[k].max(f[(k + 1) % f.len()]))))
            .collect();
        for (e, s) in edges.iter().zip(&sharp) {
            if let Some(s) = s {
                c.creases.insert(*e, *s);
            }
        }
        for _ in 0..2 {
            c = subdivide(&c, Boundary::EdgeOnly).unwrap();
            prop_assert_eq!(c.mesh.euler_characteristic(), chi);
            prop_assert!(c.mesh.positions().iter().flatten().all(|x| x.is_finite()));
        }
    }
}
