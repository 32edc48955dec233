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
    assert!(err(preset("bezier-cubic", &w(0.5))).contains("⟨w⟩ applies"));
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

/// The 4-point Takagi P-IFS over the square (the paper's set-up of Figs. 2–3)
/// draws the same curve as the 3-point one, y = Σ wⁿ dist(2ⁿx, ℤ), checked at
/// the dyadic points against the closed sum; moving (1,1) to (1,−1) (Fig. 3)
/// bends it down by exactly 2x²; and T0 keeps the exponent α₂ = 2.
#[test]
fn the_square_takagi_draws_the_takagi_curve_and_bends_with_its_fourth_point() {
    use asperity_ifs::Model;
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let takagi = |x: f64| {
        (0..60)
            .map(|n| {
                let t = 2f64.powi(n) * x;
                w.powi(n) * (t - t.round()).abs()
            })
            .sum::<f64>()
    };
    let curve = |name: &str| match preset(name, &PresetParams::default())
        .unwrap()
        .build()
        .unwrap()
    {
        Model::Curve(c) => c,
        Model::Surface(_) => panic!("{name} is a curve"),
    };
    let mut square = curve("takagi-square");
    let pts = square.attractor(8).unwrap();
    assert!(pts.len() > 200);
    // The depth-8 attractor is within 10⁻⁶ of the closed sum, and equal to the
    // 3-point P-IFS's point for point.
    let three = curve("takagi-landsberg").attractor(8).unwrap();
    assert_eq!(three.len(), pts.len());
    for (p, q) in pts.iter().zip(&three) {
        assert!(
            (p[1] - takagi(p[0])).abs() < 1e-6,
            "{p:?} vs {}",
            takagi(p[0])
        );
        assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
    }
    square.move_point(2, [1.0, -1.0, 0.0]).unwrap();
    for p in square.attractor(8).unwrap() {
        let bent = takagi(p[0]) - 2.0 * p[0] * p[0];
        assert!((p[1] - bent).abs() < 1e-6, "{p:?} vs {bent}");
    }
    let an = asperity_ifs::DirectionAnalysis::new(&square.pifs, &Default::default());
    let alpha = an.operators[0].spectrum.alpha().unwrap();
    assert_eq!(&alpha[..3], &[0.0, 1.0, 2.0]);
}
