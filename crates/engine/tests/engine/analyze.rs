//! The `analyze` job's behaviour, tested here rather than through the CLI
//! (issue #36): one behaviour per test, through `AnalyzeParams` as every
//! front end builds them, against closed forms (Gauss–Bonnet, the rms the
//! surface was scaled to, the Hurst exponent it was synthesised with). The
//! estimators against SurfaceTopography are in `asperity-analysis` and the
//! CLI's `analysis_reference` test.

use asperity_engine::analyze::{AnalyzeParams, analyze};
use asperity_engine::core::{HeightField, MemoryBudget, shapes};
use asperity_engine::io::Surface;
use asperity_engine::synthesis::{FbmParams, fbm};
use serde_json::{Value, json};

fn report(s: &Surface, v: Value) -> (Value, Vec<String>) {
    let p: AnalyzeParams = serde_json::from_value(v).expect("valid parameters");
    let a = analyze(s, "test", &p.options(false)).unwrap();
    (serde_json::to_value(&a.facts).unwrap(), a.warnings)
}

fn fbm_surface() -> Surface {
    let p = FbmParams {
        size: 256,
        hurst: 0.7,
        rms: 0.5,
        ..FbmParams::DEFAULT
    };
    Surface::Height(fbm(&p, 3, &MemoryBudget::unlimited()).unwrap())
}

/// The surface was scaled to Sq = 0.5 after removing its mean, and its
/// spectrum has H = 0.7.
#[test]
fn a_synthesised_surface_gives_back_its_rms_and_hurst_exponent() {
    let (m, _) = report(&fbm_surface(), json!({"level": "mean"}));
    for k in ["Sa", "Sq", "Sp", "Sv", "Sz", "Ssk", "Sku", "Sdq", "Sdr"] {
        assert!(m[k].is_number(), "{k} missing");
    }
    assert!(
        (m["Sq"].as_f64().unwrap() - 0.5).abs() < 1e-9,
        "{}",
        m["Sq"]
    );
    let h = m["hurst"].as_f64().unwrap();
    assert!((h - 0.7).abs() < 0.05, "H = {h}");
    let q = m["psd"]["q"].as_array().unwrap();
    assert_eq!(q.len(), m["psd"]["C"].as_array().unwrap().len());
}

/// A torus has genus 1 and, by Gauss–Bonnet, total Gaussian curvature
/// 2πχ = 0; as a smooth surface its box-counting dimension is 2.
#[test]
fn a_torus_has_genus_one_and_no_total_gaussian_curvature() {
    let torus = Surface::Mesh(shapes::torus(1.0, 0.35, 96, 48));
    let (m, warnings) = report(&torus, json!({}));
    assert_eq!(m["genus"], 1);
    let k = m["curvature"]["total_gaussian"].as_f64().unwrap();
    assert!(k.abs() < 1e-9, "∫K = {k}");
    let d = m["fractal_dimension"]["box_counting"]["D"]
        .as_f64()
        .unwrap();
    assert!((d - 2.0).abs() < 0.15, "D = {d}");
    assert!(!warnings.iter().any(|w| w.contains("covering dimension")));
}

/// A constant field is analysed, not refused: zeros where the numbers are
/// defined, null where not (skewness and kurtosis divide by Sq), and a
/// warning.
#[test]
fn a_constant_field_gives_zeros_nulls_and_a_warning() {
    let flat = Surface::Height(HeightField::filled([4, 4], 1.0));
    let (m, warnings) = report(&flat, json!({}));
    assert_eq!((m["Sa"].as_f64(), m["Sq"].as_f64()), (Some(0.0), Some(0.0)));
    assert!(m["Ssk"].is_null() && m["Sku"].is_null() && m["hurst"].is_null());
    assert!(
        warnings.iter().any(|w| w.contains("constant (z = 1)")),
        "{warnings:?}"
    );
}

/// A fit window above the Nyquist frequency holds no PSD point: no Hurst
/// exponent, the rest of the report, and a warning saying so (#20).
#[test]
fn a_fit_window_past_nyquist_leaves_hurst_out_and_says_why() {
    let (m, warnings) = report(&fbm_surface(), json!({"fit_window": [1e6, 2e6]}));
    assert!(m["hurst"].is_null());
    assert!(m["Sq"].is_number());
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("only 0 points in the fit window")),
        "{warnings:?}"
    );
}

#[test]
fn a_reversed_fit_window_is_refused_naming_its_form() {
    let e = serde_json::from_value::<AnalyzeParams>(json!({"fit_window": [5.0, 1.0]}))
        .map(|p| asperity_engine::params::validate(&p))
        .map_or_else(|e| e.to_string(), |r| r.unwrap_err().to_string());
    assert!(e.contains("QMIN,QMAX") || e.contains("fit_window"), "{e}");
}

/// `hurst = "psd"` runs the PSD fit alone: the same H as every estimator's
/// report, no other estimate and no model-based dimension; `all` has them.
#[test]
fn one_estimator_is_paid_for_alone() {
    let s = fbm_surface();
    let (all, _) = report(&s, json!({}));
    let (psd, _) = report(&s, json!({"hurst": "psd"}));
    assert_eq!(psd["hurst"], all["hurst"]);
    let names = |m: &Value| -> Vec<String> {
        m["hurst_estimates"]
            .as_object()
            .unwrap()
            .keys()
            .cloned()
            .collect()
    };
    assert_eq!(names(&psd), ["psd_2d"]);
    assert_eq!(names(&all).len(), 5, "{:?}", names(&all));
    assert!(psd["fractal_dimension"]["triangulation"].is_null());
    assert!(all["fractal_dimension"]["triangulation"].is_object());
    let (sf, _) = report(&s, json!({"hurst": "structure-function"}));
    assert_eq!(names(&sf), ["psd_2d", "structure_function"]);
    assert_eq!(
        sf["hurst_estimates"]["structure_function"],
        all["hurst_estimates"]["structure_function"]
    );
}

/// The estimates run at once on every core, each on its own: the report is
/// the same on one thread and on three.
#[test]
fn the_report_is_the_same_at_any_thread_count() {
    let s = fbm_surface();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| report(&s, json!({})))
    };
    assert_eq!(on(1), on(3));
}
