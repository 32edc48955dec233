//! The Khronos glTF validator (npm `gltf-validator`, `tests/gltf`) on every
//! `.glb` that `asperity demo --quick` writes: no errors, warnings, infos or
//! hints (issue #24). `npm ci` installs the validator into `tests/gltf` on
//! first use (the npm registry once); `.ci/run` does it up front. Set
//! `ASPERITY_SKIP_NODE=1` on a machine without Node.js; CI never sets it.

use std::path::{Path, PathBuf};
use std::process::Command;

fn checker() -> Option<PathBuf> {
    if std::env::var_os("ASPERITY_SKIP_NODE").is_some() {
        eprintln!("skipped: ASPERITY_SKIP_NODE is set");
        return None;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/gltf");
    if !dir.join("node_modules/gltf-validator").exists() {
        let ok = Command::new("npm")
            .args(["ci", "--silent", "--no-audit", "--no-fund"])
            .current_dir(&dir)
            .status()
            .is_ok_and(|s| s.success());
        assert!(
            ok,
            "could not install the glTF validator: run `npm ci` in tests/gltf"
        );
    }
    Some(dir.join("validate.mjs"))
}

#[test]
fn every_demo_glb_is_validator_clean() {
    let Some(script) = checker() else { return };
    let d = tempfile::tempdir().unwrap();
    let out = d.path().join("g");
    let o = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--quiet", "demo", "--quick", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut glbs: Vec<PathBuf> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "glb"))
        .collect();
    glbs.sort();
    let names: Vec<_> = glbs.iter().map(|p| p.file_name().unwrap()).collect();
    // the textured cup, the coloured planets, the torus: every kind of .glb
    for want in ["surfca_voronoi_cup.glb", "subdiv_planet.glb", "torus.glb"] {
        assert!(names.iter().any(|n| *n == want), "{want} in {names:?}");
    }
    let v = Command::new("node")
        .arg(&script)
        .args(&glbs)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&v.stdout);
    assert!(
        v.status.success(),
        "the validator found messages:\n{text}{}",
        String::from_utf8_lossy(&v.stderr)
    );
    assert_eq!(
        text.matches("0 errors, 0 warnings, 0 infos, 0 hints")
            .count(),
        glbs.len(),
        "{text}"
    );
}
