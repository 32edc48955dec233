//! The projected-IFS curvature report's values against closed forms
//! (poull-gentil §4), tested here rather than through the CLI (issue #36).

use asperity_engine::ifs::{IfsCurvatureParams, IfsModelParams};
use serde_json::Value;

fn report(model: IfsModelParams) -> Value {
    IfsCurvatureParams {
        model,
        at: Vec::new(),
    }
    .report()
    .expect("a report")
    .2
}

fn preset(name: &str) -> IfsModelParams {
    IfsModelParams {
        preset: Some(name.into()),
        ..IfsModelParams::DEFAULT
    }
}

fn first_curvature(doc: &Value) -> f64 {
    doc["operators"][0]["curvature"][0]
        .as_f64()
        .expect("a curvature")
}

/// The Takagi–Landsberg curve at w = 1/√2: the curvature range of T₀ starts
/// at −(6 − 4√2).
#[test]
fn takagi_landsberg_curvature_at_the_default_w() {
    let doc = report(preset("takagi-landsberg"));
    assert!((first_curvature(&doc) + (6.0 - 4.0 * 2f64.sqrt())).abs() < 1e-9);
    assert_eq!(doc["control_points"][1], serde_json::json!([1.0, 0.0]));
}

/// At w = 1/2 the operator is not diagonalisable: no curvature.
#[test]
fn takagi_landsberg_at_a_half_has_no_curvature() {
    let doc = report(IfsModelParams {
        w: Some(0.5),
        ..preset("takagi-landsberg")
    });
    assert_eq!(doc["operators"][0]["class"], "non-diagonalisable");
    assert!(doc["operators"][0]["curvature"].is_null());
}

/// A quadratic Bézier's end curvature κ(0) = 2·|ΔP₀ × ΔP₁|·(n−1)/n / |ΔP₀|³:
/// 1 for (0,0),(1,0),(2,2) (a control point moved), 1/2 for (0,0),(1,0),(1,1)
/// (control points from a CSV file).
#[test]
fn bezier_end_curvature_is_the_closed_form() {
    let moved = report(IfsModelParams {
        r#move: vec!["2=2,2".into()],
        ..preset("bezier-quadratic")
    });
    assert_eq!(moved["control_points"][2], serde_json::json!([2.0, 2.0]));
    assert!((first_curvature(&moved) - 1.0).abs() < 1e-12);
    let d = tempfile::tempdir().unwrap();
    let csv = d.path().join("ctl.csv");
    std::fs::write(&csv, "x,y\n0,0\n1,0\n1,1\n").unwrap();
    let from_file = report(IfsModelParams {
        control: Some(csv),
        ..preset("bezier-quadratic")
    });
    assert!((first_curvature(&from_file) - 0.5).abs() < 1e-12);
}

/// The bicubic Bézier patch: four finite operators, each with a single
/// Gaussian curvature value (its range's two ends equal), and each 𝒯ᵢⱼ's own
/// spectrum in the document: 2^{−k} with multiplicity #{a + b = k : a, b ≤ 3}.
#[test]
fn the_bicubic_patch_has_four_finite_operators() {
    let doc = report(preset("bezier-bicubic"));
    let ops = doc["operators"].as_array().unwrap();
    assert_eq!(ops.len(), 4);
    for o in ops {
        assert_eq!(o["class"], "finite");
        let g = o["gaussian"].as_array().unwrap();
        assert!((g[0].as_f64().unwrap() - g[1].as_f64().unwrap()).abs() < 1e-12);
        let spectrum = o["tensor_spectrum"].as_array().unwrap();
        let multiplicities: Vec<u64> = spectrum
            .iter()
            .map(|p| p["multiplicity"].as_u64().unwrap())
            .collect();
        assert_eq!(multiplicities, [1, 2, 3, 4, 3, 2, 1]);
        for (k, p) in spectrum.iter().enumerate() {
            assert!((p["value"].as_f64().unwrap() - 0.5f64.powi(k as i32)).abs() < 1e-9);
            assert_eq!(p["eigenvectors"], p["multiplicity"]);
        }
    }
}

/// Fig. 4's yellow curve: the DCF of 𝒯00 from 𝒯00's own spectrum (1/√2 and ½
/// each twice or more) runs along the SDCF's diagonal s = t, vertex for vertex.
#[test]
fn the_tensor_dcf_lies_on_the_sdcf_diagonal() {
    use asperity_engine::core::MemoryBudget;
    use asperity_engine::ifs::{sdcf_for, tensor_dcf_for};
    use asperity_engine::methods::ifs::sdcf::Start;
    use asperity_engine::methods::ifs::{FamilyOptions, Model, PresetParams, preset};
    let Model::Surface(s) = preset("takagi-landsberg-surface", &PresetParams::default())
        .unwrap()
        .build()
        .unwrap()
    else {
        panic!("a surface")
    };
    let opts = FamilyOptions::default();
    let starts = (Start::Parameter(1.0), Start::Parameter(1.0));
    let res = 16;
    let mesh = sdcf_for(&s, &opts, (0, 0), starts, res, &MemoryBudget::default()).unwrap();
    let line = tensor_dcf_for(&s, &opts, (0, 0), starts, res).unwrap();
    assert_eq!(line.len(), res + 1);
    for (k, p) in line.iter().enumerate() {
        let v = mesh.positions()[k * (res + 1) + k];
        let d = (0..3).map(|c| (p[c] - v[c]).abs()).fold(0.0, f64::max);
        assert!(d < 1e-12, "t = {k}/{res}: {p:?} vs {v:?}");
    }
}
