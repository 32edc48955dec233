//! `analyze` and `generate`.

use super::*;

#[test]
fn analyze_and_generate() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(
        &[
            "--seed", "3", "generate", "fbm", "--size", "256", "--hurst", "0.7", "--rms", "0.5",
            "-o", "f.npy",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(&["--json", "analyze", "f.npy", "--level", "mean"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // The clock runs from before the reading: a 128² analysis takes a while.
    assert!(
        v["elapsed_s"].as_f64().unwrap() > 1e-4,
        "{}",
        v["elapsed_s"]
    );
    // The report's fields (their values are tested in the engine:
    // crates/engine/tests/engine/analyze.rs) and the flags' values in `params`.
    let m = &v["measurements"];
    for k in [
        "Sa", "Sq", "Sp", "Sv", "Sz", "Ssk", "Sku", "Sdq", "Sdr", "hurst",
    ] {
        assert!(m[k].is_number(), "{k} missing");
    }
    assert!(m["fractal_dimension"]["psd"]["D"].is_number());
    assert_eq!(v["params"]["level"], "mean");
    // PNG plots: decodable images of the right size, with content.
    let o = asperity(&["analyze", "f.npy", "--plot", "plots", "-q"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["psd.png", "hhcf.png", "heights.png"] {
        let img = asperity_io::read_height(&d.path().join("plots").join(name));
        assert!(img.is_ok(), "{name} is not a readable PNG");
        let bytes = std::fs::read(d.path().join("plots").join(name)).unwrap();
        assert!(
            bytes.starts_with(b"\x89PNG") && bytes.len() > 10_000,
            "{name}"
        );
    }
    // A mesh: its plots and report (values tested in the engine).
    let torus = asperity_engine::core::shapes::torus(1.0, 0.35, 48, 24);
    asperity_io::write_mesh(&d.path().join("torus.ply"), &torus, &Default::default()).unwrap();
    let o = asperity(
        &["analyze", "torus.ply", "--plot", "mplots", "-q"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.path().join("mplots/curvature_mean.png").exists());
    assert!(d.path().join("mplots/curvature_gaussian.png").exists());
    let o = asperity(&["--json", "analyze", "torus.ply"], d.path());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["genus"], 1);
    // The mesh of a height field: box counting is not 3 − H, and the report says so (#21).
    let o = asperity(&["convert", "f.npy", "f.ply"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(&["analyze", "f.ply"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("covering dimension"), "{}", stderr(&o));
    assert!(
        v["measurements"]["roughness_vs_smoothed"]["rms"]
            .as_f64()
            .unwrap()
            >= 0.0
    );
    // Bad input.
    std::fs::write(
        d.path().join("flat.csv"),
        "1,1,1,1\n1,1,1,1\n1,1,1,1\n1,1,1,1\n",
    )
    .unwrap();
    // A job's warning reaches stderr, the report stdout.
    let o = asperity(&["--json", "analyze", "flat.csv"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("constant (z = 1)"), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["Sq"].as_f64(), Some(0.0));
    fails(
        d.path(),
        &["analyze", "f.npy", "--fit-window", "5,1"],
        "QMIN,QMAX",
    );
    // A window above the Nyquist frequency holds no PSD point: no Hurst
    // exponent, but the rest of the report (#20).
    let o = asperity(&["analyze", "f.npy", "--fit-window", "1e6,2e6"], d.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("only 0 points in the fit window"),
        "{}",
        stderr(&o)
    );
    assert!(String::from_utf8_lossy(&o.stdout).contains("Sq"));
    fails(
        d.path(),
        &["generate", "fbm", "--hurst", "1.5", "-o", "x.npy"],
        "--hurst must be in (0, 1], got 1.5",
    );
}

/// An estimate that needs more data than the field has is `null` with a
/// warning; every other quantity is still reported, with exit code 0 (#20).
#[test]
fn analyze_reports_what_it_can() {
    let d = tempfile::tempdir().unwrap();
    // 4×4 samples of a tilted sine: ISO parameters are defined, the Hurst fit
    // (one PSD point) and the dimension fits (≥ 32 samples a side) are not.
    let mut text = String::new();
    for j in 0..4 {
        let row: Vec<String> = (0..4)
            .map(|i| format!("{}", (i as f64 * 0.9).sin() + (j as f64 * 0.4).cos()))
            .collect();
        text += &row.join(",");
        text.push('\n');
    }
    std::fs::write(d.path().join("small.csv"), text).unwrap();
    let o = asperity(&["--json", "analyze", "small.csv"], d.path());
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = &v["measurements"];
    assert!(m["Sq"].as_f64().unwrap() > 0.1, "{m}");
    assert!(m["hurst"].is_null(), "{m}");
    assert!(m["fractal_dimension"]["triangulation"].is_null(), "{m}");
    let warnings = v["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w.as_str().unwrap().starts_with("Hurst exponent")),
        "{warnings:?}"
    );
    assert!(
        stderr(&o).contains("warning: Hurst exponent"),
        "{}",
        stderr(&o)
    );
}
