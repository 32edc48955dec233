//! `asperity analyze` against SurfaceTopography (issue #21): the battery of
//! `python/tests/reference/check_analysis.py` — surfaces of known Hurst exponent made by
//! SurfaceTopography's `fourier_synthesis`, periodic and cropped, tilted, 256² to
//! 2048², and line scans — run through the real binary. The checks and their
//! tolerances are in the script's docstring. Slow tier: `cargo test -- --ignored`.

use std::process::Command;

use asperity_fixtures::{python::python, workspace};

#[test]
#[ignore = "slow tier: the SurfaceTopography battery, ~2 min (cargo test -- --ignored)"]
fn analyze_agrees_with_surface_topography_and_recovers_known_exponents() {
    let dir = tempfile::tempdir().unwrap();
    let script = workspace().join("python/tests/reference/check_analysis.py");
    let out = Command::new(python())
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_asperity"))
        .arg(dir.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "check_analysis.py failed (see above)");
    assert!(stdout.contains("OK: every check passed"));
}
