//! The commands' common ground: help, argument and input errors, formats, budgets.

use super::*;

#[test]
fn help_and_version() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(&["--help"], d.path());
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    for cmd in [
        "demo",
        "convert",
        "info",
        "formats",
        "--seed",
        "--threads",
        "--json",
        "--max-memory",
    ] {
        assert!(text.contains(cmd), "help lists {cmd}");
    }
    assert!(asperity(&["--version"], d.path()).status.success());
}

#[test]
fn bad_arguments_are_clear_errors() {
    let d = tempfile::tempdir().unwrap();
    fails(
        d.path(),
        &["formats", "--frobnicate"],
        "unexpected argument '--frobnicate'",
    );
    fails(
        d.path(),
        &["--seed", "abc", "formats"],
        "invalid value 'abc'",
    );
    fails(
        d.path(),
        &["--threads", "0", "formats"],
        "invalid value '0'",
    );
    fails(d.path(), &["--max-memory", "lots", "formats"], "not a size");
    fails(
        d.path(),
        &["convert", "missing.ply", "out.obj"],
        "error: missing.ply: No such file or directory",
    );
    fails(d.path(), &["convert", "a.ply"], "no output file");
    // A negative number is an option's value, not an unknown flag: it
    // reaches the parameter's bound.
    fails(
        d.path(),
        &["generate", "fbm", "--spacing", "-1", "-o", "f.npy"],
        "--spacing must be in (0, 1000000000000], got -1",
    );
    fails(
        d.path(),
        &[
            "surface-ca",
            "builtin:cube",
            "--app",
            "corrosion",
            "--k1",
            "-0.5",
            "-o",
            "v.ply",
        ],
        "--k1 must be in [0, 1000000], got -0.5",
    );
}

#[test]
fn malformed_inputs_through_the_cli() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("t.ply"), b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n").unwrap();
    fails(d.path(), &["convert", "t.ply", "t.obj"], "truncated");
    assert!(!d.path().join("t.obj").exists());
    std::fs::write(d.path().join("n.csv"), b"1,2\ninf,4\n").unwrap();
    fails(
        d.path(),
        &["convert", "n.csv", "n.npy"],
        "height 2 is not finite",
    );
    // NaN is a missing point: carried by .npy, refused by PNG with the count.
    std::fs::write(d.path().join("m.csv"), b"1,2\nnan,4\n").unwrap();
    fails(
        d.path(),
        &["convert", "m.csv", "m.png"],
        "1 of 4 points were not measured",
    );
    assert!(!d.path().join("m.png").exists());
    std::fs::write(
        d.path().join("b.obj"),
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n",
    )
    .unwrap();
    fails(d.path(), &["info", "b.obj"], "out of bounds");
    std::fs::write(d.path().join("e.ply"), b"").unwrap();
    fails(d.path(), &["info", "e.ply"], "magic");
}

#[test]
fn memory_limit_refuses_with_the_estimate() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(
        &["--max-memory", "32K", "demo", "--quick", "--out", "g"],
        d.path(),
    );
    assert_clean_failure(&o, "a 65×65 grid would need about 33.01 KiB");
    let o = asperity(
        &["--max-memory", "16K", "demo", "--quick", "--out", "g"],
        d.path(),
    );
    assert_clean_failure(
        &o,
        "but the memory limit is 16.00 KiB (as given; raise it with --max-memory)",
    );
    std::fs::write(d.path().join("big.xyz"), "1 2 3\n".repeat(1000)).unwrap();
    fails(
        d.path(),
        &["--max-memory", "1K", "info", "big.xyz"],
        "reading big.xyz would need",
    );
}

#[test]
fn formats_lists_everything() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(&["formats", "--json"], d.path());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let exts: Vec<&str> = v
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|f| {
            f["extensions"]
                .as_array()
                .unwrap()
                .iter()
                .map(|e| e.as_str().unwrap())
        })
        .collect();
    for e in [
        "ply", "obj", "stl", "glb", "xyz", "npy", "png", "exr", "gsf", "csv", "gwy", "x3p",
    ] {
        assert!(exts.contains(&e), "{e}");
    }
    // The README's format table names every extension `asperity formats` lists.
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../README.md")).unwrap();
    let rows: Vec<&str> = readme.lines().filter(|l| l.starts_with("| ")).collect();
    for e in exts {
        let cell = format!("`.{e}`");
        assert!(
            rows.iter().any(|r| r.contains(&cell)),
            "the README's format table lacks {cell}"
        );
    }
}

#[test]
fn closed_stdout_is_not_a_crash() {
    let d = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["formats"])
        .current_dir(d.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

/// A 20000 × 20000 16-bit PNG of zeros (3.5 MB compressed, 800 MB of pixels),
/// written a row at a time.
fn big_png(path: &Path) {
    use std::io::Write as _;
    let n = 20_000;
    let file = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut encoder = png::Encoder::new(file, n, n);
    encoder.set_color(png::ColorType::Grayscale);
    encoder.set_depth(png::BitDepth::Sixteen);
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header().unwrap();
    let mut rows = writer.stream_writer().unwrap();
    let row = vec![0u8; 2 * n as usize];
    for _ in 0..n {
        rows.write_all(&row).unwrap();
    }
    rows.finish().unwrap();
}

/// Under `ulimit -v 8G` and no --max-memory, the budget follows the
/// address-space limit: a 20000² height field is refused with the estimate
/// and the limit that applied, instead of an abort on a failed allocation
/// (#37); the JSON report says which limit set the budget.
#[cfg(target_os = "linux")]
#[test]
fn an_address_space_limit_sets_the_budget() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    big_png(&dir.join("big.png"));
    let exe = env!("CARGO_BIN_EXE_asperity");
    for args in ["facet big.png -o big.ply", "render big.png -o shaded.png"] {
        let o = Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -v 8388608 && exec '{exe}' {args}"))
            .current_dir(dir)
            .output()
            .unwrap();
        assert_clean_failure(&o, "ulimit -v");
        assert!(stderr(&o).contains("--max-memory"), "{}", stderr(&o));
    }
    assert!(!dir.join("big.ply").exists() && !dir.join("shaded.png").exists());
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v 8388608 && exec '{exe}' --json generate fbm --size 32 -o f.npy"
        ))
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        v["memory_budget"]["from"], "rlimit_as",
        "{}",
        v["memory_budget"]
    );
    assert!(v["memory_budget"]["bytes"].as_u64().unwrap() < 8 << 30);
}

#[test]
fn runs_of_years_are_refused_before_any_work() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(dir.join("h.npy"), "precious").unwrap();
    fails(
        dir,
        &[
            "growth", "rdsr", "--runs", "1000000", "--layers", "1000000", "-o", "h.npy",
        ],
        "the deposition would take at least",
    );
    // Without a time limit, the ensemble's memory is estimated before any run.
    fails(
        dir,
        &[
            "growth",
            "rdsr",
            "--runs",
            "1000000",
            "--max-memory",
            "100M",
            "--max-time",
            "none",
            "-o",
            "h.npy",
        ],
        "width series of 1000000 runs",
    );
    fails(
        dir,
        &[
            "surface-ca",
            "builtin:cube",
            "--app",
            "corrosion",
            "--cells",
            "1000000",
            "--steps",
            "1000000000000",
            "-o",
            "c.ply",
        ],
        "years",
    );
    fails(
        dir,
        &[
            "ca", "run", "--rule", "450", "--steps", "1000000", "--init", "seed", "-o", "h.npy",
        ],
        "raise --max-time",
    );
    fails(
        dir,
        &[
            "--max-time",
            "1s",
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "100000000",
            "--size",
            "64x64",
            "-o",
            "h.npy",
        ],
        "over the time limit of 1 s",
    );
    fails(dir, &["--max-time", "soon", "formats"], "not a duration");
    // The surface-CA refusal comes before the cells are built: a mesh the
    // cell builder would refuse (an edge of three triangles) is never reached.
    write_fin(&dir.join("fin.obj"));
    fails(
        dir,
        &[
            "surface-ca",
            "fin.obj",
            "--app",
            "corrosion",
            "--cells",
            "1000000",
            "--steps",
            "1000000000000",
            "-o",
            "c.ply",
        ],
        "years",
    );
    fails(
        dir,
        &[
            "surface-ca",
            "builtin:cube",
            "--app",
            "corrosion",
            "--cells",
            "2000",
            "--steps",
            "1000000",
            "--frames",
            "1",
            "-o",
            "c.ply",
        ],
        "--frames would write 1000001 files",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("h.npy")).unwrap(),
        "precious"
    );
    // --max-time none lifts the limit (a small run passes either way).
    let o = asperity(
        &[
            "--max-time",
            "none",
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "3",
            "--init",
            "seed",
            "-o",
            "s.npy",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
}
