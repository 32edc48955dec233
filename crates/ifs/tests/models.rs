//! Model files, presets and the errors bad models get.

use asperity_ifs::model::{bezier_operators, takagi_operators};
use asperity_ifs::{Constraint, IfsError, ModelFile, Pifs, PresetParams, preset, preset_names};
use nalgebra::DMatrix;

fn constraint(r: Result<impl std::fmt::Debug, IfsError>) -> (Constraint, String) {
    match r {
        Err(IfsError::Violated { constraint, detail }) => (constraint, detail),
        other => panic!("expected a violated constraint, got {other:?}"),
    }
}

#[test]
fn shipped_preset_files_equal_the_generator() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
    for (name, _) in preset_names() {
        let path = dir.join(format!("{name}.json"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; regenerate with `asperity ifs preset {name} -o {}`",
                path.display(),
                path.display()
            )
        });
        let file = ModelFile::from_json(&text).unwrap();
        let generated = preset(name, &PresetParams::default()).unwrap();
        assert_eq!(
            file,
            generated,
            "{} differs from the generator; regenerate with `asperity ifs preset {name} -o {}`",
            path.display(),
            path.display()
        );
        // And the JSON round trip is exact.
        assert_eq!(
            ModelFile::from_json(&generated.to_json()).unwrap(),
            generated
        );
        generated.build().unwrap();
    }
}

#[test]
fn bad_models_name_the_violated_constraint() {
    let m = |rows: &[&[f64]]| DMatrix::from_fn(rows.len(), rows.len(), |r, c| rows[r][c]);
    let b = bezier_operators(2);
    let t0 = DMatrix::from_fn(3, 3, |r, c| b[0][r][c]);
    let t1 = DMatrix::from_fn(3, 3, |r, c| b[1][r][c]);

    let (c, d) = constraint(Pifs::new(vec![t0.clone()]));
    assert_eq!(c, Constraint::Shape);
    assert!(d.contains("exactly 2"), "{d}");

    let (c, d) = constraint(Pifs::new(vec![t0.clone(), DMatrix::identity(2, 2)]));
    assert_eq!(c, Constraint::Shape);
    assert!(d.contains("T1"), "{d}");

    let (c, _) = constraint(Pifs::new(vec![t0.clone(), DMatrix::zeros(3, 2)]));
    assert_eq!(c, Constraint::Shape);

    let mut bad = t1.clone();
    bad[(0, 2)] = 0.1;
    let (c, d) = constraint(Pifs::new(vec![t0.clone(), bad]));
    assert_eq!(c, Constraint::Barycentric);
    assert!(d.contains("column 2 of T1"), "{d}");

    let mut nan = t0.clone();
    nan[(1, 1)] = f64::NAN;
    let (c, _) = constraint(Pifs::new(vec![nan, t1.clone()]));
    assert_eq!(c, Constraint::Finite);

    // Expanding: eigenvalue 1.5 on the vector space.
    let grow = m(&[&[1.0, -0.5, -0.5], &[0.0, 1.5, 0.0], &[0.0, 0.0, 1.5]]);
    let (c, d) = constraint(Pifs::new(vec![grow, t1.clone()]));
    assert_eq!(c, Constraint::Contractivity);
    assert!(d.contains("T0") && d.contains("1.5"), "{d}");

    // The identity fixes everything.
    let (c, _) = constraint(Pifs::new(vec![t0.clone(), DMatrix::identity(3, 3)]));
    assert_eq!(c, Constraint::Contractivity);

    // Both maps with the same fixed point: the attractor is a point.
    let (c, d) = constraint(Pifs::new(vec![t0.clone(), t0.clone()]));
    assert_eq!(c, Constraint::Adjacency);
    assert!(d.contains("single point"), "{d}");

    // T1 moved so that its piece no longer starts where T0's ends: T0·c1 ≠ T1·c0.
    let mut moved = t1.clone();
    moved[(0, 0)] += 0.1;
    moved[(1, 0)] -= 0.1;
    let (c, d) = constraint(Pifs::new(vec![t0.clone(), moved]));
    assert_eq!(c, Constraint::Adjacency);
    assert!(d.contains("T0·c1"), "{d}");

    // Takagi's T1 has a negative entry: affine, not convex, combinations are fine.
    let tk = takagi_operators(0.6);
    Pifs::from_rows(&tk).unwrap();
    let ragged = vec![vec![vec![1.0, 0.0], vec![0.0]], tk[1].clone()];
    assert_eq!(constraint(Pifs::from_rows(&ragged)).0, Constraint::Shape);
}

#[test]
fn bad_files_and_parameters_are_clear() {
    let err = |r: Result<ModelFile, IfsError>| r.unwrap_err().to_string();
    assert!(err(preset("nope", &PresetParams::default())).contains("known: bezier-quadratic"));
    let w = |w| PresetParams {
        w: Some(w),
        ..Default::default()
    };
    assert!(err(preset("takagi-landsberg", &w(1.2))).contains("(−1, 1)"));
    assert!(err(preset("takagi-landsberg", &w(f64::NAN))).contains("w"));
    assert!(err(preset("bezier-cubic", &w(0.5))).contains("--w applies"));
    assert!(ModelFile::from_json("{").is_err());
    let e = ModelFile::from_json(r#"{"name": "x", "curv": {}}"#).unwrap_err();
    assert!(e.to_string().contains("unknown field"), "{e}");
    let neither = ModelFile::from_json(r#"{"name": "x"}"#).unwrap();
    assert!(
        neither
            .build()
            .unwrap_err()
            .to_string()
            .contains("exactly one")
    );
    // Wrong number of control points.
    let mut f = preset("bezier-quadratic", &PresetParams::default()).unwrap();
    f.curve.as_mut().unwrap().control_points.pop();
    let e = f.build().unwrap_err().to_string();
    assert!(e.contains("3 control points"), "{e}");
    // Non-dyadic and out-of-range parameters.
    let e = asperity_ifs::curvature::dyadic(1.0 / 3.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a dyadic"), "{e}");
    assert!(asperity_ifs::curvature::dyadic(1.5).is_err());
    assert!(asperity_ifs::curvature::dyadic(f64::NAN).is_err());
    assert_eq!(asperity_ifs::curvature::dyadic(0.375).unwrap(), (3, 3));
}
