//! The built-in example scenes, as every front end reaches them:
//! `scene = "example:NAME"` and the add-on's text with knobs.

use asperity_engine::subdiv::{Source, SubdivParams, example_text, examples};

#[test]
fn every_example_is_a_scene_by_name() {
    let list = examples();
    let names: Vec<&str> = list
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["rock", "berry", "tentacle", "mushroom", "spur"]);
    for name in names {
        let p = SubdivParams {
            scene: Some(format!("example:{name}").into()),
            ..Default::default()
        };
        let Source::Scene { text, .. } = p.source().unwrap() else {
            panic!("{name}: a scene")
        };
        assert!(text.contains("[[detail]]"), "{name}");
    }
    let unknown = SubdivParams {
        scene: Some("example:pebble".into()),
        ..Default::default()
    };
    let e = unknown.source().unwrap_err().to_string();
    assert!(
        e.contains("no example scene \"pebble\"") && e.contains("rock, berry"),
        "{e}"
    );
}

#[test]
fn the_knobs_set_levels_seed_size_and_spacing() {
    let text = example_text("tentacle", Some(3), Some(9), Some(0.3), Some(1.1)).unwrap();
    assert!(
        text.contains("levels = 3") && text.contains("seed = 9"),
        "{text}"
    );
    assert!(
        text.contains("length = 0.3") && text.contains("spacing = 1.1"),
        "{text}"
    );
    let e = example_text("rock", None, None, None, Some(1.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("places no detail by spacing"), "{e}");
}
