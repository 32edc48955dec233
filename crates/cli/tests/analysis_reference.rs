//! `asperity analyze` against SurfaceTopography (issue #21): the battery of
//! `python/tests/reference/check_analysis.py` — surfaces of known Hurst exponent made by
//! SurfaceTopography's `fourier_synthesis`, periodic and cropped, tilted, 256² to
//! 2048², and line scans — run through the real binary; and against surfalize's
//! ISO 25178-2 parameters (issue #56, `check_iso.py`: a generated battery and the
//! SurfaceTopography example files). The checks, their tolerances and the documented
//! exceptions are in the scripts' docstrings. Slow tier: `cargo test -- --ignored`.

use std::process::Command;

use asperity_fixtures::{python::python, workspace};

/// Runs a reference script with the binary, a work folder and `more` arguments.
fn reference_script(name: &str, more: &[&std::path::Path]) {
    let dir = tempfile::tempdir().unwrap();
    let script = workspace().join("python/tests/reference").join(name);
    let out = Command::new(python())
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_asperity"))
        .arg(dir.path())
        .args(more)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{name} failed (see above)");
    assert!(stdout.contains("OK: every check passed"));
}

#[test]
#[ignore = "slow tier: the SurfaceTopography battery, ~2 min (cargo test -- --ignored)"]
fn analyze_agrees_with_surface_topography_and_recovers_known_exponents() {
    reference_script("check_analysis.py", &[]);
}

#[test]
#[ignore = "slow tier: the surfalize comparison, ~10 s (cargo test -- --ignored)"]
fn iso_parameters_agree_with_surfalize() {
    let data = workspace().join("tests/data/surfacetopography");
    reference_script("check_iso.py", &[&data]);
}
