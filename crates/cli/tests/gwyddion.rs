//! Gwyddion itself (Debian's `gwyddion`, `--convert-to-gwy` needs no display)
//! reads asperity's `.gsf` and 16-bit `.png` height fields with the right
//! sizes, extents, offsets, units (none, or metres for a field in µm/nm) and the
//! heights (issue #24): the checks of
//! `tests/python/check_gwyddion.py`, read back with the `gwyfile` package.
//! `.ci/run` installs Gwyddion; set `ASPERITY_SKIP_GWYDDION=1` on a machine
//! without it (CI never sets it).

use std::process::Command;

#[path = "../../../tests/python/python_env.rs"]
mod python_env;

#[test]
fn gwyddion_reads_our_gsf_and_png() {
    if python_env::skipped() || std::env::var_os("ASPERITY_SKIP_GWYDDION").is_some() {
        eprintln!("skipped");
        return;
    }
    let found = Command::new("gwyddion").arg("--version").output().is_ok();
    assert!(
        found,
        "gwyddion is not installed (apt-get install gwyddion), or set ASPERITY_SKIP_GWYDDION=1"
    );
    let dir = tempfile::tempdir().unwrap();
    let script = python_env::workspace().join("tests/python/check_gwyddion.py");
    let out = Command::new(python_env::python())
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_asperity"))
        .arg(dir.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "check_gwyddion.py failed (see above)");
    assert_eq!(stdout.matches("ok   ").count(), 30, "every check ran");
}
