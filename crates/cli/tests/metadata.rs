//! The parameters every output file records (issue #36): the report's
//! `params` are in each file whose format has a place for them, `info` shows
//! them, `--params FILE` makes the same bytes again from them, and `convert`
//! keeps them.

use std::path::Path;
use std::process::Command;

use serde_json::Value;

/// `asperity --json ARGS` in `dir`: its report (panics on failure).
fn report(dir: &Path, args: &[&str]) -> Value {
    let o = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .arg("--json")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run asperity");
    assert!(
        o.status.success(),
        "asperity {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("a JSON report")
}

/// The parameters `path` records, read by the engine's reader.
fn recorded(path: &Path) -> Option<Value> {
    asperity_io::read_params(path).unwrap()
}

/// For each job and output: the report's params are in the file and make
/// the same bytes again through `--params FILE`.
#[test]
fn every_output_records_the_params_that_make_it_again() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "--seed", "5", "generate", "fbm", "--size", "32", "--hurst", "0.6",
            ],
            "gsf",
        ),
        (&["--seed", "5", "generate", "fbm", "--size", "32"], "x3p"),
        (&["--seed", "5", "generate", "fbm", "--size", "32"], "gwy"),
        (&["--seed", "5", "generate", "fbm", "--size", "32"], "exr"),
        (&["--seed", "5", "generate", "fbm", "--size", "32"], "csv"),
        (&["--seed", "5", "generate", "fbm", "--size", "32"], "png"),
        (
            &[
                "--seed",
                "4",
                "growth",
                "dla",
                "--dim",
                "2",
                "--size",
                "40",
                "--particles",
                "150",
            ],
            "ply",
        ),
        (
            &[
                "--seed", "4", "growth", "rdsr", "--size", "24", "--layers", "3",
            ],
            "obj",
        ),
        (
            &[
                "ifs",
                "surface",
                "--preset",
                "bezier-bicubic",
                "--depth",
                "4",
            ],
            "glb",
        ),
        (&["subdiv", "--levels", "1"], "ply"),
        (
            &[
                "ca", "run", "--rule", "224", "--size", "24x24", "--steps", "6",
            ],
            "gsf",
        ),
    ];
    for (k, (args, ext)) in cases.iter().enumerate() {
        let first = dir.join(format!("a{k}.{ext}"));
        let mut cmd: Vec<&str> = args.to_vec();
        let path = first.to_str().unwrap();
        cmd.extend(["-o", path]);
        let r = report(dir, &cmd);
        let want = r["params"].clone();
        assert!(want.is_object(), "{args:?}: the report has params");
        assert_eq!(recorded(&first).as_ref(), Some(&want), "{args:?} → .{ext}");
        // The job's name and the file are all `--params` needs.
        let job: Vec<&str> = args
            .iter()
            .copied()
            .skip_while(|a| a.starts_with("--seed") || a.parse::<u64>().is_ok())
            .take_while(|a| !a.starts_with("--"))
            .collect();
        let again = dir.join(format!("b{k}.{ext}"));
        let mut cmd = job.clone();
        cmd.extend(["--params", path, "-o", again.to_str().unwrap()]);
        let r2 = report(dir, &cmd);
        assert_eq!(r2["params"], want, "{job:?} --params {path}");
        assert_eq!(
            std::fs::read(&first).unwrap(),
            std::fs::read(&again).unwrap(),
            "{job:?}: the same bytes from the file's params"
        );
    }
}

#[test]
fn info_shows_the_record_and_convert_keeps_it() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let r = report(dir, &["generate", "fbm", "--size", "24", "-o", "h.gsf"]);
    let info = report(dir, &["info", "h.gsf"]);
    assert_eq!(info["measurements"]["made_with"], r["params"]);
    // A format change keeps the surface's recipe, not convert's own options.
    report(dir, &["convert", "h.gsf", "h.x3p"]);
    assert_eq!(recorded(&dir.join("h.x3p")), Some(r["params"].clone()));
    report(dir, &["convert", "h.gsf", "h.ply"]);
    assert_eq!(recorded(&dir.join("h.ply")), Some(r["params"].clone()));
    // A conversion that changes the surface keeps none: they would not make it.
    report(dir, &["convert", "h.gsf", "h2.gsf", "--spacing", "0.5"]);
    assert_eq!(recorded(&dir.join("h2.gsf")), None);
    report(dir, &["convert", "h.gsf", "pts.ply", "--as", "points"]);
    assert_eq!(recorded(&dir.join("pts.ply")), None);
    // Formats with no place for them, and files from elsewhere, have none.
    report(dir, &["convert", "h.gsf", "h.npy"]);
    assert_eq!(recorded(&dir.join("h.npy")), None);
    let info = report(dir, &["info", "h.npy"]);
    assert!(info["measurements"].get("made_with").is_none());
    let o = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["generate", "fbm", "--params", "h.npy", "-o", "x.gsf"])
        .current_dir(dir)
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("records no parameters"), "{e}");
    // Another job's file is refused by name.
    let o = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["growth", "dla", "--params", "h.gsf", "-o", "x.ply"])
        .current_dir(dir)
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("for \"generate fbm\""), "{e}");
}

/// A render's PNG records the render's params (not the surface's).
#[test]
fn a_render_records_its_own_params() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    report(dir, &["generate", "fbm", "--size", "24", "-o", "h.gsf"]);
    let r = report(dir, &["render", "h.gsf", "--size", "64x48", "-o", "r.png"]);
    assert_eq!(recorded(&dir.join("r.png")), Some(r["params"].clone()));
    assert_eq!(r["params"]["job"], "render");
}
