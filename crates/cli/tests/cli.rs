//! End-to-end tests of the `asperity` binary: exit codes, messages, outputs.

use std::path::Path;
use std::process::{Command, Output};

fn asperity(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run asperity")
}

/// A PLY file's bytes without its `comment asperity-params` header line.
fn without_params(bytes: &[u8]) -> Vec<u8> {
    let key = b"comment asperity-params ";
    match bytes.windows(key.len()).position(|w| w == key) {
        Some(at) => {
            let end = at + bytes[at..].iter().position(|&b| b == b'\n').unwrap() + 1;
            [&bytes[..at], &bytes[end..]].concat()
        }
        None => bytes.to_vec(),
    }
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `asperity ARGS` in `dir` fails cleanly with `needle` in its message.
fn fails(dir: &Path, args: &[&str], needle: &str) {
    assert_clean_failure(&asperity(args, dir), needle);
}

/// A failure: exit code 2, one `error:` line with the cause, never a panic.
fn assert_clean_failure(o: &Output, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "exit code; stderr: {e}");
    assert!(!e.contains("panicked"), "panic: {e}");
    assert!(e.contains(needle), "expected {needle:?} in: {e}");
    let line = e
        .lines()
        .find(|l| l.starts_with("error: "))
        .expect("an error line");
    let parts: Vec<&str> = line.split(": ").collect();
    for w in parts.windows(2) {
        assert!(w[0] != w[1], "a cause repeated in: {line}");
    }
}

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
fn convert_height_fields_and_meshes() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("h.csv"),
        b"# dx=0.5 dy=0.5\n0,1,2\n3,4,5\n6,7,8.25\n",
    )
    .unwrap();
    for (a, b) in [("h.csv", "h.gsf"), ("h.gsf", "h.npy"), ("h.npy", "h2.csv")] {
        let o = asperity(&["convert", a, b], d.path());
        assert!(o.status.success(), "{a} → {b}: {}", stderr(&o));
    }
    let back = std::fs::read_to_string(d.path().join("h2.csv")).unwrap();
    assert!(back.lines().nth(3) == Some("6,7,8.25"), "{back}");
    // Height field → mesh formats, then mesh → mesh.
    let o = asperity(
        &["convert", "h.csv", "h.ply", "--diagonal", "alternating"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(&["--json", "info", "h.ply"], d.path());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("info --json is JSON");
    assert_eq!(v["measurements"]["triangles"], 8);
    assert_eq!(v["measurements"]["euler_characteristic"], 1);
    // --f32: PLY positions and scalars as float, 16 bytes a vertex fewer
    // (x, y, z and the height), four header lines a letter shorter
    let o = asperity(&["convert", "h.ply", "h32.ply", "--f32"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let (full, single) = (
        std::fs::read(d.path().join("h.ply")).unwrap(),
        std::fs::read(d.path().join("h32.ply")).unwrap(),
    );
    assert_eq!(full.len() - single.len(), 9 * 16 + 4);
    assert!(String::from_utf8_lossy(&single).contains("property float height\n"));
    let o = asperity(&["--json", "convert", "h.ply", "-o", "h.stl"], d.path());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("convert --json is JSON");
    assert_eq!(v["outputs"][0]["bytes"], 84 + 50 * 8);
    assert!(
        v["warnings"][0]
            .as_str()
            .unwrap()
            .contains("scalar 'height'"),
        "{v}"
    );
    // A point set cannot become a height field without a method.
    let o = asperity(&["convert", "h.csv", "p.xyz"], d.path());
    assert!(o.status.success());
    fails(
        d.path(),
        &["convert", "p.xyz", "p.gsf"],
        "cannot hold a point set",
    );
}

/// `--up`: OBJ is y-up by default and read back unchanged; `--up z` takes its
/// coordinates as they are; `--up y` turns PLY (and the others) on both sides;
/// `--up-out` sets the written side alone.
#[test]
fn up_axis_on_read_and_write() {
    let d = tempfile::tempdir().unwrap();
    // a 3 × 3 field 1 wide and deep, heights 0…0.25: flat along z
    std::fs::write(
        d.path().join("h.csv"),
        b"# dx=0.5 dy=0.5\n0,0.1,0.2\n0,0.1,0.25\n0,0.1,0.2\n",
    )
    .unwrap();
    let bounds = |args: &[&str]| {
        let o = asperity(&[&["--json", "info"], args].concat(), d.path());
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let b = &v["measurements"]["bounds"];
        let f = |k: &str| -> Vec<f64> {
            b[k].as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        };
        (f("min"), f("max"))
    };
    let upright = (vec![0.0, 0.0, 0.0], vec![1.0, 1.0, 0.25]);
    for (flags, file) in [
        (&[][..], "h.obj"),
        (&["--up", "y"][..], "y.ply"),
        (&["--up", "z"][..], "z.obj"),
    ] {
        let o = asperity(&[flags, &["convert", "h.csv", file]].concat(), d.path());
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            bounds(&[flags, &[file]].concat()),
            upright,
            "{file} read as written"
        );
    }
    // as the files are: the OBJ and the y-up PLY hold (x, z, -y)
    let lying = (vec![0.0, 0.0, -1.0], vec![1.0, 0.25, 0.0]);
    assert_eq!(bounds(&["--up", "z", "h.obj"]), lying);
    assert_eq!(bounds(&["y.ply"]), lying);
    assert_eq!(bounds(&["z.obj"]), upright);
    assert!(
        !std::fs::read_to_string(d.path().join("z.obj"))
            .unwrap()
            .contains("# up: y")
    );
    fails(d.path(), &["--up", "x", "info", "h.obj"], "--up");
    // --up-out: read z-up (the PLY as it is), write y-up; reading it back y-up
    // gives the field upright again, read as it is it lies.
    let o = asperity(
        &["--up", "z", "--up-out", "y", "convert", "z.obj", "out.ply"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(bounds(&["--up", "y", "out.ply"]), upright);
    assert_eq!(bounds(&["out.ply"]), lying);
    fails(d.path(), &["--up-out", "w", "info", "h.obj"], "--up-out");
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
fn render_command() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("h.csv"),
        "0,1,2,3\n1,2,3,4\n2,3,4,5.5\n3,4,5,6\n",
    )
    .unwrap();
    let o = asperity(
        &[
            "render", "h.csv", "-o", "v.png", "--size", "160x120", "--view", "top", "--shader",
            "height",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = asperity_io::read_height(&d.path().join("v.png")).unwrap();
    assert_eq!(img.dims(), [160, 120]);
    let o = asperity(
        &["render", "h.csv", "-o", "m.png", "--view", "map"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(
        &[
            "render",
            "h.csv",
            "-o",
            "t.png",
            "--size",
            "64x48",
            "--turntable",
            "3",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..3 {
        assert!(d.path().join(format!("t_{k:03}.png")).exists());
    }
    fails(
        d.path(),
        &["render", "h.csv", "-o", "v.png", "--size", "0x10"],
        "invalid",
    );
    fails(
        d.path(),
        &["render", "h.csv", "-o", "v.png", "--size", "big"],
        "WIDTHxHEIGHT",
    );
    fails(d.path(), &["render", "h.csv", "-o", "v.jpg"], "PNG");
    fails(
        d.path(),
        &["render", "h.csv", "-o", "v.png", "--shader", "texture"],
        "UVs and a texture",
    );
    std::fs::write(d.path().join("p.xyz"), "0 0 0\n1 0 0\n0 1 1\n").unwrap();
    fails(
        d.path(),
        &["render", "p.xyz", "-o", "v.png", "--view", "map"],
        "need a height field",
    );
    let o = asperity(
        &["render", "p.xyz", "-o", "p.png", "--size", "100x80"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn bench_runs_every_workload() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(&["--json", "bench", "--quick", "--repeat", "1"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let w = v["measurements"]["workloads"].as_array().unwrap();
    assert_eq!(w.len(), 28);
    assert!(v["measurements"]["ca_bits_over_bytes"].as_f64().unwrap() > 1.0);
    assert!(
        w.iter()
            .all(|x| x["median_s"].as_f64().unwrap() > 0.0
                && x["per_second"].as_f64().unwrap() > 0.0)
    );
    fails(
        d.path(),
        &["bench", "--quick", "nothing-matches"],
        "no workload matches",
    );
    // --scaling: every method's doubling series, each point in its own process
    let o = asperity(
        &["--json", "bench", "--scaling", "all", "--quick"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let table = v["measurements"]["scaling"].as_array().unwrap();
    assert_eq!(table.len(), 9, "every method");
    for m in table {
        let points = m["points"].as_array().unwrap();
        assert!(points.len() >= 5, "{m}");
        let elements: Vec<f64> = points
            .iter()
            .map(|p| p["elements"].as_f64().unwrap())
            .collect();
        assert!(elements.windows(2).all(|w| w[1] > w[0]), "{m}");
        assert!(
            points
                .iter()
                .all(|p| p["seconds"].as_f64().unwrap() > 0.0
                    && p["peak_bytes"].as_f64().unwrap() > 1e6),
            "{m}"
        );
        assert!(m["time_slope"].as_f64().is_some(), "{m}");
    }
    fails(d.path(), &["bench", "--scaling", "nope"], "no such method");
    // --threads-scaling: 1, 2, 4 threads up to --threads, the speed-up over one.
    let o = asperity(
        &[
            "--json",
            "--threads",
            "5",
            "bench",
            "--threads-scaling",
            "--quick",
            "--repeat",
            "1",
            "core/fourier",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for w in v["measurements"]["workloads"].as_array().unwrap() {
        let rows = w["threads_scaling"].as_array().unwrap();
        let threads: Vec<u64> = rows
            .iter()
            .map(|r| r["threads"].as_u64().unwrap())
            .collect();
        assert_eq!(threads, [1, 2, 4, 5], "{w}");
        assert_eq!(rows[0]["speedup"], 1.0);
        for r in rows {
            let (s, e) = (
                r["speedup"].as_f64().unwrap(),
                r["efficiency"].as_f64().unwrap(),
            );
            let t = r["threads"].as_f64().unwrap();
            assert!(s > 0.0 && (e - s / t).abs() < 1e-12, "{r}");
        }
    }
}

#[test]
fn ca_commands() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(&["ca", "rule", "450"], d.path());
    assert!(String::from_utf8_lossy(&o.stdout).contains("0 1 1 1 0 0 0 0 1 0"));
    let o = asperity(
        &[
            "--json",
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "5",
            "--init",
            "seed",
            "-o",
            "h.npy",
            "--states-out",
            "s.npy",
            "--steps-png",
            "steps",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["size"], serde_json::json!([11, 11]));
    assert_eq!(v["measurements"]["boundary"], "infinite");
    // (T+1)·H·W bytes of states after the 128-byte .npy header.
    assert_eq!(
        std::fs::metadata(d.path().join("s.npy")).unwrap().len(),
        128 + 6 * 121
    );
    assert!(d.path().join("steps/step_005.png").exists());
    // The states file holds the run's steps as written (what they are is
    // tested in the engine: crates/engine/tests/engine/ca.rs).
    let h = asperity_io::read_height(&d.path().join("h.npy")).unwrap();
    let states = std::fs::read(d.path().join("s.npy")).unwrap();
    let sum: u32 = (0..6)
        .map(|t| states[128 + t * 121 + 5 * 11 + 5] as u32)
        .sum();
    assert_eq!(*h.get(5, 5), sum as f64);
    // Cyclic random run through a bit-sliced width, then facets with a circle and interpolation.
    let o = asperity(
        &[
            "ca",
            "run",
            "--rule",
            "B3/S23",
            "--family",
            "outer9",
            "--steps",
            "8",
            "--init",
            "random:0.4",
            "--size",
            "64x20",
            "-o",
            "life.gsf",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(
        &["facet", "h.npy", "-o", "m.obj", "--circle", "5,5,3"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        std::fs::read_to_string(d.path().join("m.obj"))
            .unwrap()
            .lines()
            .any(|l| l.starts_with("l "))
    );
    std::fs::write(d.path().join("pts.csv"), "5,5\n5.5,5.25\n99,0\n").unwrap();
    let o = asperity(&["interpolate", "h.npy", "--points", "pts.csv"], d.path());
    let text = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], format!("5,5,{}", h.get(5, 5)));
    assert_eq!(lines[2], "99,0,nan");
    let o = asperity(
        &[
            "ca",
            "gallery",
            "--rules",
            "8,480",
            "--inits",
            "random:0.3,random:0.6",
            "--steps",
            "3",
            "--size",
            "16x16",
            "--tile",
            "64x48",
            "-o",
            "g.png",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        asperity_io::read_height(&d.path().join("g.png"))
            .unwrap()
            .dims(),
        [128, 96]
    );
    // Bad input.
    fails(
        d.path(),
        &["ca", "run", "--rule", "1024", "--steps", "5", "-o", "x.npy"],
        "out of range",
    );
    fails(
        d.path(),
        &["ca", "run", "--rule", "450", "--steps", "0", "-o", "x.npy"],
        "at least 1",
    );
    fails(
        d.path(),
        &[
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "3",
            "--size",
            "0x5",
            "--init",
            "random:0.5",
            "-o",
            "x.npy",
        ],
        "zero side",
    );
    fails(
        d.path(),
        &[
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "3",
            "--init",
            "missing.npy",
            "-o",
            "x.npy",
        ],
        "missing.npy",
    );
    fails(
        d.path(),
        &[
            "ca", "run", "--rule", "300000", "--family", "outer9", "--steps", "3", "-o", "x.npy",
        ],
        "out of range",
    );
    fails(
        d.path(),
        &[
            "ca", "run", "--rule", "450", "--steps", "3", "--init", "random:2", "--size", "8x8",
            "-o", "x.npy",
        ],
        "density",
    );
    assert!(!d.path().join("x.npy").exists());
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

/// The growth commands' wiring: flags to parameters, the report's fields, the
/// outputs and the messages. What the jobs compute is tested in the engine
/// (`crates/engine/tests/engine/growth.rs`).
#[test]
fn growth_commands_as_documented() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The contract: a height field and a JSON report with the width series and β.
    let o = asperity(
        &[
            "growth", "rdsr", "--size", "64", "--layers", "200", "--seed", "7", "-o", "h.npy",
            "--json",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = &v["measurements"];
    assert!(m["width_series"].as_array().unwrap().len() > 10);
    assert!(m["beta"].as_f64().is_some(), "{m}");
    assert_eq!(v["params"]["size"], 64);
    assert_eq!(v["params"]["layers"], 200.0);
    let h = asperity_io::read_height(&d.join("h.npy")).unwrap();
    assert_eq!(h.dims(), [64, 64]);
    // 1+1D gives a 1-D array.
    let o = asperity(
        &[
            "growth", "rd", "--dim", "1", "--size", "100", "--layers", "5", "-o", "r.npy",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(d.join("r.npy")).unwrap();
    assert!(String::from_utf8_lossy(&bytes[..128]).contains("'shape': (100,)"));
    // DLA's lattice size as NXxNYxNZ, the cluster as a point set.
    let o = asperity(
        &[
            "growth",
            "dla",
            "--seed-shape",
            "plane",
            "--size",
            "32x32x64",
            "--particles",
            "3000",
            "--stick",
            "0.5",
            "-o",
            "pts.ply",
            "--json",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["particles"], 3000);
    assert_eq!(v["params"]["size"], serde_json::json!([32, 32, 64]));
    let p = asperity_io::read_points(&d.join("pts.ply")).unwrap();
    assert_eq!(p.len(), 32 * 32 + 3000);
    // A curved deposit needs a point-set output.
    let o = asperity(
        &[
            "growth",
            "rdsr",
            "--substrate",
            "sphere",
            "--radius",
            "8",
            "--layers",
            "3",
            "-o",
            "s.ply",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_clean_failure(
        &asperity(
            &["growth", "rdsr", "--substrate", "sphere", "-o", "s.npy"],
            d,
        ),
        "point set",
    );
    // --plot writes the job's plots.
    let o = asperity(
        &[
            "growth",
            "dla",
            "--particles",
            "2000",
            "--plot",
            "plots",
            "-o",
            "c.xyz",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.join("plots/gyration.svg").exists());
    // --walkers: the same cluster, the concurrency reported, not recorded.
    let o = asperity(
        &[
            "--json",
            "growth",
            "dla",
            "--particles",
            "2000",
            "--walkers",
            "5",
            "-o",
            "c5.xyz",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["walkers"]["walkers"], 5);
    assert!(v["params"].get("walkers").is_none(), "{}", v["params"]);
    assert_eq!(
        std::fs::read(d.join("c.xyz")).unwrap(),
        std::fs::read(d.join("c5.xyz")).unwrap()
    );
    assert_clean_failure(
        &asperity(&["growth", "dla", "--walkers", "0", "-o", "x.xyz"], d),
        "--walkers must be at least 1",
    );
    // The job's warnings reach stderr.
    let o = asperity(
        &[
            "growth",
            "dla",
            "--seed-shape",
            "sphere",
            "--particles",
            "2000",
            "-o",
            "s.xyz",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("grow more particles"), "{}", stderr(&o));
    // Bad input: one-line errors in the CLI's spelling, and no output left.
    let o = asperity(&["growth", "dla", "--stick", "0", "-o", "x.ply"], d);
    assert_clean_failure(&o, "(0, 1]");
    assert!(stderr(&o).contains("--stick"), "{}", stderr(&o));
    assert_clean_failure(
        &asperity(&["growth", "dla", "--size", "0x4x4", "-o", "x.ply"], d),
        "zero",
    );
    let o = asperity(
        &[
            "growth",
            "rd",
            "--size",
            "4096",
            "--layers",
            "10",
            "--points",
            "p.ply",
            "--max-memory",
            "1M",
            "-o",
            "x.npy",
        ],
        d,
    );
    assert_clean_failure(&o, "memory");
    assert!(stderr(&o).contains("--max-memory"), "{}", stderr(&o));
    assert!(!d.join("x.ply").exists() && !d.join("x.npy").exists());
}

/// The level-set commands' wiring: `reconstruct … --json` with grid, spacing,
/// per-stage timings and counts, snapshots named by step; the two pipelines
/// and their flags; clear errors on bad files. What the surfaces are is
/// tested in the engine (`crates/engine/tests/engine/reconstruct.rs`).
#[test]
fn reconstruct_and_pipelines_as_documented() {
    let d = tempfile::tempdir().unwrap();
    // Points on a sphere of radius 1 as an ASCII XYZ file.
    let mut text = String::new();
    for [x, y, z] in asperity_engine::core::shapes::fibonacci_sphere(4000) {
        text.push_str(&format!("{x} {y} {z}\n"));
    }
    std::fs::write(d.path().join("pts.xyz"), text).unwrap();
    let o = asperity(
        &[
            "reconstruct",
            "pts.xyz",
            "--resolution",
            "32",
            "--offset",
            "0.2",
            "--iterations",
            "20",
            "--save-every",
            "10",
            "--curvature",
            "-o",
            "mesh.ply",
            "--json",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = &v["measurements"];
    assert_eq!(m["grid"].as_array().unwrap().len(), 3);
    assert!(m["spacing"].as_f64().unwrap() > 0.0);
    for stage in [
        "distance",
        "tagging",
        "evolution",
        "marching_cubes",
        "total",
    ] {
        assert!(
            m["timings_s"][stage].as_f64().is_some(),
            "timings_s.{stage}"
        );
    }
    for fact in [
        "vertices",
        "triangles",
        "euler_characteristic",
        "watertight",
    ] {
        assert!(!m[fact].is_null(), "{fact}");
    }
    assert_eq!(m["iterations"], 20);
    for step in [
        "mesh_step0000.ply",
        "mesh_step0010.ply",
        "mesh_step0020.ply",
    ] {
        assert!(d.path().join(step).exists(), "{step}");
    }
    let mesh = std::fs::read(d.path().join("mesh.ply")).unwrap();
    assert!(String::from_utf8_lossy(&mesh[..2000]).contains("mean_curvature"));
    // ε in grid cells, as the paper gives it (#22): --offset 3h is 3 × the spacing.
    let o = asperity(
        &[
            "reconstruct",
            "pts.xyz",
            "--resolution",
            "32",
            "--offset",
            "3h",
            "--iterations",
            "5",
            "-o",
            "cells.ply",
            "--json",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let (eps, h) = (
        v["measurements"]["offset"].as_f64().unwrap(),
        v["measurements"]["spacing"].as_f64().unwrap(),
    );
    assert!((eps - 3.0 * h).abs() < 1e-12, "ε {eps}, h {h}");
    assert_clean_failure(
        &asperity(
            &["reconstruct", "pts.xyz", "--offset", "3x", "-o", "x.ply"],
            d.path(),
        ),
        "3h (grid cells)",
    );

    let o = asperity(
        &[
            "generate",
            "dla-terrain",
            "--size",
            "24x24x24",
            "--particles",
            "800",
            "--seed",
            "5",
            "-o",
            "terrain.glb",
            "--json",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["sides"], "walls");
    assert_eq!(v["params"]["particles"], 800);
    assert!(d.path().join("terrain.glb").exists());
    // Paper mode: the paper's settings (ε = 3h, 30 steps); periodic sides are
    // cut by the bounded reconstruction, and a warning says so.
    let o = asperity(
        &[
            "generate",
            "dla-terrain",
            "--paper",
            "--size",
            "24x24x24",
            "--particles",
            "500",
            "--sides",
            "periodic",
            "-o",
            "paper.glb",
            "--json",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["iterations"], 30);
    let (h, eps) = (
        v["measurements"]["spacing"].as_f64().unwrap(),
        v["measurements"]["offset"].as_f64().unwrap(),
    );
    assert!((eps - 3.0 * h).abs() < 1e-9);
    assert!(
        v["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .any(|w| w.as_str().unwrap().contains("periodic sides")),
        "{}",
        v["warnings"]
    );

    let o = asperity(
        &[
            "generate",
            "rdsr-sphere",
            "--radius",
            "8",
            "--layers",
            "4",
            "--seed",
            "5",
            "-o",
            "sphere.glb",
            "--json",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["params"]["radius"], 8.0);
    assert!(d.path().join("sphere.glb").exists());

    // Bad input: empty file, NaN, identical points, memory, a non-mesh output.
    std::fs::write(d.path().join("nan.xyz"), "0 0 0\n1 nan 0\n").unwrap();
    std::fs::write(d.path().join("same.xyz"), "1 1 1\n1 1 1\n1 1 1\n").unwrap();
    std::fs::write(d.path().join("empty.xyz"), "").unwrap();
    for (file, needle) in [
        ("nan.xyz", "finite"),
        ("same.xyz", "identical"),
        ("empty.xyz", ""),
    ] {
        let o = asperity(&["reconstruct", file, "-o", "x.ply"], d.path());
        assert_clean_failure(&o, needle);
        assert!(!d.path().join("x.ply").exists());
    }
    let o = asperity(
        &[
            "--max-memory",
            "1M",
            "reconstruct",
            "pts.xyz",
            "--resolution",
            "400",
            "-o",
            "x.ply",
        ],
        d.path(),
    );
    assert_clean_failure(&o, "memory limit");
    let o = asperity(&["reconstruct", "pts.xyz", "-o", "x.npy"], d.path());
    assert_clean_failure(&o, "cannot hold a mesh");
}

#[test]
fn ifs_commands_as_documented() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let ok = |args: &[&str]| {
        let o = asperity(args, dir);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    // The contract: a surface from the curve preset with --w, depth, any mesh format.
    ok(&[
        "ifs",
        "surface",
        "--preset",
        "takagi-landsberg",
        "--w",
        "0.7071",
        "--depth",
        "5",
        "-o",
        "t.ply",
        "-q",
    ]);
    let m = asperity_io::read_mesh(&dir.join("t.ply")).unwrap();
    assert_eq!(m.n_vertices(), 33 * 33);
    ok(&[
        "ifs",
        "surface",
        "--preset",
        "takagi-landsberg-surface",
        "--depth",
        "4",
        "-o",
        "s.ply",
        "--control-net",
        "net.obj",
        "-q",
    ]);
    let m = asperity_io::read_mesh(&dir.join("s.ply")).unwrap();
    assert!(m.scalar("gaussian_max").is_some() && m.scalar("mean_min").is_some());
    assert!(
        std::fs::read_to_string(dir.join("net.obj"))
            .unwrap()
            .contains("\nl ")
    );

    // Curvature JSON: control points, one entry per operator with its class and ranges.
    let out = ok(&[
        "ifs",
        "curvature",
        "--preset",
        "bezier-bicubic",
        "--at",
        "0.5,0.25",
        "--json",
    ]);
    // (the values against closed forms: crates/engine/tests/engine/ifs.rs)
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["control_points"].as_array().unwrap().len(), 4);
    let ops = v["operators"].as_array().unwrap();
    assert_eq!(ops.len(), 4);
    for o in ops {
        assert!(o["fixed_point"].is_array() && o["alpha"].is_array() && o["mean"].is_array());
    }
    assert_eq!(v["at"][0]["quadrants"].as_array().unwrap().len(), 4);

    let out = ok(&[
        "ifs",
        "curvature",
        "--preset",
        "takagi-landsberg",
        "--w",
        "0.5",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        v["operators"][0]["class"], "non-diagonalisable",
        "--w reaches the model"
    );
    // The table names each tensor operator's spectrum, Jordan blocks included.
    let out = ok(&[
        "ifs",
        "curvature",
        "--preset",
        "takagi-landsberg-surface",
        "--w",
        "0.5",
    ]);
    assert!(
        out.contains(
            "spectrum 1, 0.5 ×4 (Jordan: 2 eigenvectors), 0.25 ×4 (Jordan: 2 eigenvectors)"
        ),
        "{out}"
    );

    // Presets as editable files, edited and moved.
    ok(&["ifs", "preset", "bezier-quadratic", "-o", "q.json"]);
    let text = std::fs::read_to_string(dir.join("q.json")).unwrap();
    std::fs::write(
        dir.join("q.json"),
        text.replace("\"name\": \"bezier-quadratic\"", "\"name\": \"mine\""),
    )
    .unwrap();
    let out = ok(&[
        "ifs",
        "curvature",
        "--ifs",
        "q.json",
        "--move",
        "2=2,2",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["model"], "mine");
    assert_eq!(v["control_points"][2], serde_json::json!([2.0, 2.0]));
    std::fs::write(dir.join("ctl.csv"), "x,y\n0,0\n1,0\n1,1\n").unwrap();
    let out = ok(&[
        "ifs",
        "curvature",
        "--ifs",
        "q.json",
        "--control",
        "ctl.csv",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        v["control_points"][2],
        serde_json::json!([1.0, 1.0]),
        "--control is read"
    );

    // Curves, DCFs and SDCFs in their formats.
    ok(&[
        "ifs",
        "curve",
        "--preset",
        "takagi-landsberg",
        "--depth",
        "8",
        "-o",
        "c.csv",
        "-q",
    ]);
    assert_eq!(
        std::fs::read_to_string(dir.join("c.csv"))
            .unwrap()
            .lines()
            .count(),
        258
    );
    ok(&[
        "ifs",
        "curve",
        "--preset",
        "bezier-cubic",
        "-o",
        "c.svg",
        "-q",
    ]);
    ok(&[
        "ifs",
        "dcf",
        "--preset",
        "takagi-landsberg",
        "--bound",
        "upper",
        "-o",
        "d.svg",
        "-q",
    ]);
    assert!(
        std::fs::read_to_string(dir.join("d.svg"))
            .unwrap()
            .contains("<svg")
    );
    ok(&[
        "ifs",
        "dcf",
        "--preset",
        "takagi-landsberg",
        "--operator",
        "1",
        "-o",
        "d.obj",
        "-q",
    ]);
    ok(&[
        "ifs",
        "sdcf",
        "--preset",
        "takagi-landsberg-surface",
        "--resolution",
        "16",
        "--with-attractor",
        "4",
        "-o",
        "sd.ply",
        "-q",
    ]);
    let m = asperity_io::read_mesh(&dir.join("sd.ply")).unwrap();
    assert_eq!(m.n_vertices(), 17 * 17 * 2);

    // Bad input: clear errors, no panics, nothing half-written.
    let o = asperity(&["ifs", "surface", "--preset", "nope", "-o", "x.ply"], dir);
    assert_clean_failure(&o, "known: bezier-quadratic");
    let o = asperity(
        &[
            "ifs",
            "curvature",
            "--preset",
            "takagi-landsberg",
            "--at",
            "0.3",
        ],
        dir,
    );
    assert_clean_failure(&o, "not a dyadic");
    let o = asperity(
        &[
            "ifs",
            "surface",
            "--preset",
            "bezier-bicubic",
            "--depth",
            "30",
            "-o",
            "x.ply",
        ],
        dir,
    );
    assert_clean_failure(&o, "depth");
    let o = asperity(
        &[
            "ifs",
            "surface",
            "--preset",
            "bezier-bicubic",
            "--depth",
            "12",
            "--max-memory",
            "10M",
            "-o",
            "x.ply",
        ],
        dir,
    );
    assert_clean_failure(&o, "memory");
    let o = asperity(
        &["ifs", "curve", "--preset", "bezier-bicubic", "-o", "x.csv"],
        dir,
    );
    assert_clean_failure(&o, "is a surface");
    let o = asperity(
        &[
            "ifs",
            "curvature",
            "--preset",
            "bezier-cubic",
            "--move",
            "9=1,1",
        ],
        dir,
    );
    assert_clean_failure(&o, "does not exist");
    std::fs::write(dir.join("bad.json"), text.replace("0.25", "0.3")).unwrap();
    let o = asperity(&["ifs", "curvature", "--ifs", "bad.json"], dir);
    assert_clean_failure(&o, "barycentric constraint");
    let o = asperity(
        &[
            "ifs",
            "surface",
            "--preset",
            "bezier-cubic",
            "--w",
            "0.3",
            "-o",
            "x.ply",
        ],
        dir,
    );
    assert_clean_failure(&o, "--w applies");
    assert!(!dir.join("x.ply").exists() && !dir.join("x.csv").exists());
}

#[test]
fn surface_ca_as_documented() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let o = asperity(
        &[
            "surface-ca",
            "builtin:sphere",
            "--app",
            "voronoi",
            "--sites",
            "5",
            "--cells",
            "5000",
            "--seed",
            "3",
            "-o",
            "out.glb",
            "--labels-out",
            "labels.ply",
            "--stats-out",
            "steps.csv",
            "--plot",
            "steps.png",
            "--json",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let m = &v["measurements"];
    let cells = m["cells"].as_u64().unwrap() as usize;
    assert!(cells > 4000 && cells < 6000, "{cells}");
    let steps = m["steps"].as_u64().unwrap() as usize;
    assert_eq!(m["changed_fraction"].as_array().unwrap().len(), steps);
    assert_eq!(m["sites"].as_array().unwrap().len(), 5);
    assert!(std::fs::metadata(dir.join("out.glb")).unwrap().len() > 10_000);
    let header = std::fs::read(dir.join("labels.ply")).unwrap();
    let text = String::from_utf8_lossy(&header[..2000]);
    assert!(text.contains("property int label") && text.contains("property double area"));
    let pts = asperity_io::read_points(&dir.join("labels.ply")).unwrap();
    assert_eq!(pts.len(), cells);
    let csv = std::fs::read_to_string(dir.join("steps.csv")).unwrap();
    assert_eq!(csv.lines().count(), steps + 1);
    assert!(dir.join("steps.png").exists());
    // `--pairing paper`, as the README documents it (what it does: the engine's tests).
    let o = asperity(
        &[
            "surface-ca",
            "builtin:sphere",
            "--cells",
            "5000",
            "--pairing",
            "paper",
            "-o",
            "paper.glb",
            "--json",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["cell_structure"]["pairing"], "paper");

    // Corrosion, as documented.
    let o = asperity(
        &[
            "surface-ca",
            "builtin:cup",
            "--app",
            "corrosion",
            "--cells",
            "20000",
            "--steps",
            "150",
            "--seed",
            "3",
            "-o",
            "patina.glb",
            "--json",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["steps"], 150);
    assert!(v["measurements"]["corroded"].as_u64().unwrap() > 0);
    assert!(std::fs::metadata(dir.join("patina.glb")).unwrap().len() > 10_000);
    assert_clean_failure(
        &asperity(
            &[
                "surface-ca",
                "builtin:cup",
                "--app",
                "corrosion",
                "--max-attacked",
                "9",
                "-o",
                "x.glb",
            ],
            dir,
        ),
        "max-attacked",
    );
    // --site-points and --seed-rate reach the job (what they do is tested in
    // the engine: crates/engine/tests/engine/surfca.rs).
    std::fs::write(dir.join("site.xyz"), "0.3 0.2 5\n").unwrap();
    let o = asperity(
        &[
            "surface-ca",
            "builtin:cube",
            "--app",
            "corrosion",
            "--cells",
            "3000",
            "--steps",
            "40",
            "--seed-rate",
            "0",
            "--site-points",
            "site.xyz",
            "-o",
            "site.ply",
            "--json",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["params"]["seed_rate"], 0.0);
    assert!(v["measurements"]["corroded"].as_u64().unwrap() > 0);
    // The corrosion mesh carries both layers: render --patina lights each, then mixes.
    let o = asperity(
        &[
            "render", "site.ply", "--patina", "-o", "site.png", "--size", "120x90",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let m = asperity_io::read_mesh(&dir.join("site.ply")).unwrap();
    assert!(m.scalar("oxide").is_some() && m.scalar("metal").is_some());
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert_clean_failure(
        &asperity(&["render", "tri.obj", "--patina", "-o", "x.png"], dir),
        "scalar 'oxide'",
    );
    // OBJ: the original mesh with the cells as a texture atlas (.mtl + PNG).
    let o = asperity(
        &[
            "surface-ca",
            "builtin:cube",
            "--cells",
            "3000",
            "-o",
            "atlas.obj",
            "-q",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("atlas_texture.png").exists() && dir.join("atlas.mtl").exists());
    let cube = asperity_io::read_mesh(&dir.join("atlas.obj")).unwrap();
    assert_eq!(
        cube.n_faces(),
        asperity_engine::core::shapes::cube(4).n_faces()
    );
    assert!(cube.uvs().is_some());
    // A third application, sites from a file, animation frames.
    let o = asperity(
        &[
            "surface-ca",
            "builtin:sphere",
            "--app",
            "gray-scott",
            "--cells",
            "4000",
            "--steps",
            "200",
            "--frames",
            "100",
            "-o",
            "rd.ply",
            "-q",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        asperity_io::read_mesh(&dir.join("rd.ply"))
            .unwrap()
            .scalar("activator")
            .is_some()
    );
    assert!(dir.join("rd_step0100.ply").exists() && dir.join("rd_step0200.ply").exists());
    std::fs::write(dir.join("sites.xyz"), "0 0 1\n0 0 -1\n1 0 0\n").unwrap();
    let o = asperity(
        &[
            "surface-ca",
            "builtin:sphere",
            "--site-points",
            "sites.xyz",
            "--cells",
            "4000",
            "-o",
            "s.ply",
            "--json",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["measurements"]["sites"].as_array().unwrap().len(), 3);
    assert_clean_failure(
        &asperity(
            &[
                "surface-ca",
                "builtin:cube",
                "--app",
                "gray-scott",
                "--feed",
                "0.9",
                "-o",
                "x.glb",
            ],
            dir,
        ),
        "feed",
    );
    for (args, needle) in [
        (
            vec!["surface-ca", "builtin:teapot", "-o", "x.glb"],
            "known: sphere, cube, cylinder, cup",
        ),
        (
            vec!["surface-ca", "builtin:cube", "--sites", "0", "-o", "x.glb"],
            "--sites",
        ),
        (
            vec![
                "surface-ca",
                "builtin:cube",
                "--diagonal-p",
                "2",
                "-o",
                "x.glb",
            ],
            "diagonal-p",
        ),
        (
            vec!["surface-ca", "builtin:cube", "-o", "x.npy"],
            "cannot hold a mesh",
        ),
        (
            vec!["surface-ca", "builtin:cube", "--cells", "0", "-o", "x.glb"],
            "cells",
        ),
        (
            vec!["surface-ca", "missing.obj", "-o", "x.glb"],
            "missing.obj",
        ),
    ] {
        assert_clean_failure(&asperity(&args, dir), needle);
    }
    assert!(!dir.join("x.glb").exists());
}

#[test]
fn subdiv_as_documented() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let o = asperity(
        &[
            "subdiv", "--base", "cube", "--levels", "2", "-o", "cc.ply", "--json",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let levels = v["measurements"]["levels"].as_array().unwrap();
    assert_eq!(levels[1]["vertices"], 26);
    assert_eq!(levels[2]["faces"], 96);
    assert_eq!(v["measurements"]["euler_characteristic"], 2);
    // (the surface itself, one behaviour a test: crates/engine/tests/engine/subdiv.rs)
    let m = asperity_io::read_mesh(&dir.join("cc.ply")).unwrap();
    assert_eq!(m.n_faces(), 192);
    let run = |args: &[&str]| {
        let o = asperity(args, dir);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    };
    run(&[
        "subdiv",
        "--base",
        "torus",
        "--levels",
        "2",
        "--detail",
        "rock:amplitude=0.05,decay=0.5",
        "--seed",
        "3",
        "-o",
        "rock.obj",
        "-q",
    ]);
    // Several details, creases, limit positions and normals.
    run(&[
        "subdiv",
        "--base",
        "cylinder",
        "--levels",
        "3",
        "--detail",
        "berry:radius=0.3",
        "--detail",
        "spur:height=2,levels=2",
        "--crease",
        "0-1:inf",
        "--limit",
        "-o",
        "many.glb",
        "-q",
    ]);
    // Animation: θ runs over the frames.
    run(&[
        "subdiv",
        "--base",
        "sphere",
        "--levels",
        "3",
        "--detail",
        "tentacle:length=0.05,theta=0..3",
        "--frames",
        "3",
        "-o",
        "t.ply",
        "-q",
    ]);
    let f0 = std::fs::read(dir.join("t_0000.ply")).unwrap();
    let f2 = std::fs::read(dir.join("t_0002.ply")).unwrap();
    assert!(dir.join("t_0001.ply").exists());
    assert_ne!(f0, f2, "the frames differ");
    // Details exported and re-applied reproduce the surface; on an edited base they follow it.
    run(&[
        "subdiv",
        "--base",
        "cube",
        "--levels",
        "3",
        "--detail",
        "rock:amplitude=0.1",
        "--export-details",
        "d.json",
        "-o",
        "a.ply",
        "-q",
    ]);
    run(&[
        "subdiv",
        "--base",
        "cube",
        "--levels",
        "3",
        "--apply-details",
        "d.json",
        "-o",
        "b.ply",
        "-q",
    ]);
    // The same mesh; the recorded parameters differ (b names d.json).
    assert_eq!(
        without_params(&std::fs::read(dir.join("a.ply")).unwrap()),
        without_params(&std::fs::read(dir.join("b.ply")).unwrap())
    );
    let mut obj = String::new();
    for i in 0..8 {
        let c = |b: usize| if i >> b & 1 == 1 { 2.0 } else { -1.0 };
        obj += &format!("v {} {} {}\n", c(0), c(1), c(2));
    }
    obj += "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
    std::fs::write(dir.join("edited.obj"), obj).unwrap();
    run(&[
        "subdiv",
        "--base",
        "edited.obj",
        "--levels",
        "3",
        "--apply-details",
        "d.json",
        "-o",
        "c.ply",
        "-q",
    ]);
    // --analyze and --export-details reach the engine (which rebuilds the
    // fine mesh: crates/engine/tests/engine/subdiv.rs).
    run(&[
        "subdiv",
        "--base",
        "cube",
        "--levels",
        "3",
        "--analyze",
        "a.ply",
        "--export-details",
        "e.json",
        "-o",
        "back.ply",
        "-q",
    ]);
    assert!(dir.join("back.ply").exists() && dir.join("e.json").exists());
    let fa = asperity_io::read_mesh(&dir.join("a.ply")).unwrap();
    // A captured surface (a.ply) as a layer, blended with fresh rock: with the
    // plane far away (α = 0 everywhere) the result is the captured surface.
    for (offset, same) in [(100.0, true), (0.0, false)] {
        std::fs::write(
            dir.join("cap.toml"),
            format!(
                "base = \"cube\"\nlevels = 3\n[[surface]]\nlayer = \"scan\"\nfile = \"a.ply\"\n\
                 [[detail]]\ntype = \"rock\"\nlayer = \"new\"\namplitude = 0.3\n\
                 [blend]\na = \"scan\"\nb = \"new\"\nwidth = 0.5\n\
                 plane = {{ normal = [1, 0, 0], offset = {offset} }}\n"
            ),
        )
        .unwrap();
        run(&["subdiv", "cap.toml", "-o", "cap.ply", "-q"]);
        let c = asperity_io::read_mesh(&dir.join("cap.ply")).unwrap();
        let close = fa
            .positions()
            .iter()
            .zip(c.positions())
            .all(|(p, q)| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-12));
        assert_eq!(close, same, "offset {offset}");
    }
    // A blend by an alpha-map file (one value per base vertex: 26 on the sphere).
    let map: String = (0..26).map(|i| format!("{}\n", f64::from(i % 2))).collect();
    std::fs::write(dir.join("alpha.txt"), &map).unwrap();
    std::fs::write(dir.join("short.txt"), "0.5\n0.5\n").unwrap();
    let mapped = |file: &str| {
        format!(
            "base = \"sphere\"\nlevels = 2\n[[detail]]\ntype = \"rock\"\nlayer = \"a\"\n\
             [[detail]]\ntype = \"berry\"\nlayer = \"b\"\n\
             [blend]\na = \"a\"\nb = \"b\"\nwidth = 0.5\nalpha_map = \"{file}\"\n"
        )
    };
    std::fs::write(dir.join("map.toml"), mapped("alpha.txt")).unwrap();
    std::fs::write(dir.join("short.toml"), mapped("short.txt")).unwrap();
    run(&["subdiv", "map.toml", "-o", "map.ply", "-q"]);
    assert_clean_failure(
        &asperity(&["subdiv", "short.toml", "-o", "x.ply"], dir),
        "the alpha map has 2 values",
    );
    // Painted alpha (§6): the base exported, painted per vertex (here in
    // reverse vertex order, as exporters may reorder), read back by colour
    // luminance or by a named scalar — the same blend as the text map.
    run(&[
        "subdiv", "--base", "sphere", "--levels", "0", "-o", "base.ply", "-q",
    ]);
    let base = asperity_io::read_mesh(&dir.join("base.ply")).unwrap();
    let n = base.n_vertices() as u32;
    assert_eq!(n, 26);
    let flip = |v: u32| n - 1 - v;
    let positions: Vec<[f64; 3]> = (0..n).map(|v| base.positions()[flip(v) as usize]).collect();
    let triangles = base.triangles().iter().map(|t| t.map(flip)).collect();
    let alpha = |v: u32| f64::from(flip(v) % 2);
    let painted = asperity_engine::core::TriMesh::new(positions, triangles)
        .unwrap()
        .with_colors((0..n).map(|v| [(255.0 * alpha(v)) as u8; 4]).collect())
        .unwrap()
        .with_scalar("mask", (0..n).map(alpha).collect())
        .unwrap();
    asperity_io::write_mesh(&dir.join("painted.ply"), &painted, &Default::default()).unwrap();
    std::fs::write(dir.join("paint.toml"), mapped("painted.ply")).unwrap();
    let by_scalar = mapped("painted.ply") + "alpha_from = \"mask\"\n";
    std::fs::write(dir.join("paint_mask.toml"), by_scalar).unwrap();
    let unknown = mapped("painted.ply") + "alpha_from = \"wetness\"\n";
    std::fs::write(dir.join("paint_bad.toml"), unknown).unwrap();
    // (the same mesh; the recorded scenes differ)
    let text_map = without_params(&std::fs::read(dir.join("map.ply")).unwrap());
    for scene in ["paint.toml", "paint_mask.toml"] {
        run(&["subdiv", scene, "-o", "painted_out.ply", "-q"]);
        assert!(
            without_params(&std::fs::read(dir.join("painted_out.ply")).unwrap()) == text_map,
            "{scene}: not the text map's blend"
        );
    }
    assert_clean_failure(
        &asperity(&["subdiv", "paint_bad.toml", "-o", "x.ply"], dir),
        "no scalar \"wetness\" (its scalars: mask)",
    );
    // Scenes: an example scene, byte-identical at 1 and 2 threads.
    let scene = dir.join("berry.toml");
    std::fs::write(
        &scene,
        "base = \"sphere\"\nlevels = 3\nseed = 4\n[[detail]]\ntype = \"berry\"\nradius = 0.4\n\
         [[edit]]\nat = [0, 0, 1]\nradius = 1\nlevels = [2, 3]\nfactor = 2.0\n",
    )
    .unwrap();
    run(&[
        "subdiv",
        "berry.toml",
        "--threads",
        "1",
        "-o",
        "s1.glb",
        "-q",
    ]);
    run(&[
        "subdiv",
        "berry.toml",
        "--threads",
        "2",
        "-o",
        "s2.glb",
        "-q",
    ]);
    assert_eq!(
        std::fs::read(dir.join("s1.glb")).unwrap(),
        std::fs::read(dir.join("s2.glb")).unwrap()
    );
    // The blended planet (scalar mode + shader) writes vertex colours.
    let planet = concat!(env!("CARGO_MANIFEST_DIR"), "/../subdiv/scenes/planet.toml");
    let text = std::fs::read_to_string(planet)
        .unwrap()
        .replace("levels = 6", "levels = 3");
    std::fs::write(dir.join("planet.toml"), text).unwrap();
    run(&["subdiv", "planet.toml", "-o", "planet.ply", "-q"]);
    let p = asperity_io::read_mesh(&dir.join("planet.ply")).unwrap();
    assert!(p.colors().is_some());
    // Bad input.
    std::fs::write(
        dir.join("bad.toml"),
        "[[detail]]\ntype = \"rock\"\namplitud = 1\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("fin.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    for (args, needle) in [
        (
            vec!["subdiv", "--detail", "lava", "-o", "x.ply"],
            "unknown detail type",
        ),
        (
            vec!["subdiv", "--detail", "berry:radius=-1", "-o", "x.ply"],
            "radius must be > 0",
        ),
        (vec!["subdiv", "bad.toml", "-o", "x.ply"], "amplitud"),
        (
            vec!["subdiv", "missing.toml", "-o", "x.ply"],
            "missing.toml",
        ),
        (
            vec!["subdiv", "--base", "nothing.obj", "-o", "x.ply"],
            "nothing.obj",
        ),
        (
            vec!["subdiv", "--base", "fin.obj", "-o", "x.ply"],
            "non-manifold edge",
        ),
        (
            vec!["subdiv", "--crease", "0-7:1", "-o", "x.ply"],
            "not an edge",
        ),
        (
            vec![
                "subdiv",
                "--base",
                "sphere",
                "--apply-details",
                "d.json",
                "-o",
                "x.ply",
            ],
            "belong to a base",
        ),
        (
            vec![
                "subdiv",
                "--levels",
                "9",
                "--max-memory",
                "10M",
                "-o",
                "x.ply",
            ],
            "memory",
        ),
    ] {
        assert_clean_failure(&asperity(&args, dir), needle);
    }
    assert!(!dir.join("x.ply").exists());
}

/// A PNG chunk: length, type, data, CRC-32.
fn png_chunk(kind: &[u8], data: &[u8]) -> Vec<u8> {
    let mut crc_input = kind.to_vec();
    crc_input.extend_from_slice(data);
    let mut out = (data.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(&crc_input);
    out.extend_from_slice(&crc32(&crc_input).to_be_bytes());
    out
}
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 == 1 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG that declares 100000 × 100000 pixels in 60 bytes (a decompression bomb).
fn png_bomb(path: &Path) {
    let chunk = png_chunk;
    let mut ihdr = 100_000u32.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&100_000u32.to_be_bytes());
    ihdr.extend_from_slice(&[16, 0, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(chunk(b"IHDR", &ihdr));
    png.extend(chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ));
    png.extend(chunk(b"IEND", &[]));
    std::fs::write(path, png).unwrap();
}

/// A 1×1 16-bit grey PNG recording the height range [lo, hi] in asperity's
/// tEXt keys (the IDAT is a stored, uncompressed zlib block).
fn png_1x1_with_range(lo: f64, hi: f64) -> Vec<u8> {
    let raw = [0u8, 0x80, 0x00]; // filter byte, one 16-bit sample
    let (mut a, mut b) = (1u32, 0u32);
    for &x in &raw {
        a = (a + x as u32) % 65521;
        b = (b + a) % 65521;
    }
    let mut idat = vec![0x78, 0x01, 0x01, 3, 0, 0xfc, 0xff];
    idat.extend_from_slice(&raw);
    idat.extend_from_slice(&((b << 16) | a).to_be_bytes());
    let mut ihdr = 1u32.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&1u32.to_be_bytes());
    ihdr.extend_from_slice(&[16, 0, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(png_chunk(b"IHDR", &ihdr));
    png.extend(png_chunk(
        b"tEXt",
        format!("asperity:z_min\0{lo}").as_bytes(),
    ));
    png.extend(png_chunk(
        b"tEXt",
        format!("asperity:z_max\0{hi}").as_bytes(),
    ));
    png.extend(png_chunk(b"IDAT", &idat));
    png.extend(png_chunk(b"IEND", &[]));
    png
}

/// Hostile inputs found by hand (#20): each gets one clean error, no panic,
/// no abort, and nothing is written.
#[test]
fn hostile_inputs_are_refused_cleanly() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    png_bomb(&dir.join("bomb.png"));
    for args in [
        vec!["info", "bomb.png"],
        vec!["convert", "bomb.png", "x.npy"],
        vec!["analyze", "bomb.png"],
        vec!["render", "bomb.png", "-o", "x.png"],
        vec!["facet", "bomb.png", "-o", "x.ply"],
        vec![
            "growth",
            "dla",
            "--seed-shape",
            "image",
            "--image",
            "bomb.png",
            "-o",
            "x.ply",
        ],
        vec![
            "ca", "run", "--rule", "450", "--steps", "2", "--init", "bomb.png", "-o", "x.npy",
        ],
    ] {
        let mut all = vec!["--max-memory", "1G"];
        all.extend(args);
        fails(dir, &all, "would need about");
    }
    // n² overflowed before the budget check (a panic) or wrapped to a small
    // number (a hang).
    for size in ["4294967296", "18446744073709551615"] {
        fails(
            dir,
            &["generate", "fbm", "--size", size, "-o", "f.npy"],
            "would need about",
        );
    }
    // A welded STL triangle that repeats a corner, as a subdivision base.
    std::fs::write(
        dir.join("deg.stl"),
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
    )
    .unwrap();
    fails(
        dir,
        &["subdiv", "--base", "deg.stl", "-o", "s.ply"],
        "degenerate",
    );
    // Faces of fewer than 3 corners are refused, not dropped.
    std::fs::write(
        dir.join("two.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\nf 1 2 3\n",
    )
    .unwrap();
    fails(
        dir,
        &["info", "two.obj"],
        "line 4: a face needs at least 3 corners",
    );
    // Cameras that cannot be.
    std::fs::write(dir.join("t.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    fails(
        dir,
        &["render", "t.obj", "-o", "r.png", "--fov", "0"],
        "--fov must be in (0, 180), got 0",
    );
    fails(
        dir,
        &["render", "t.obj", "-o", "r.png", "--fov", "nan"],
        "--fov must be a finite number",
    );
    fails(
        dir,
        &[
            "render", "t.obj", "-o", "r.png", "--eye", "1,1,1", "--target", "1,1,1",
        ],
        "same point",
    );
    fails(
        dir,
        &["render", "t.obj", "-o", "r.png", "--scalar", "nosuch"],
        "no scalar 'nosuch'",
    );
    // Header values that cannot be: negative lengths, an inverted height range.
    let mut gsf =
        b"Gwyddion Simple Field 1.0\nXRes = 2\nYRes = 2\nXReal = -1\nYReal = 1\n".to_vec();
    gsf.resize(gsf.len().div_ceil(4) * 4 + 16, 0);
    std::fs::write(dir.join("neg.gsf"), gsf).unwrap();
    fails(
        dir,
        &["info", "neg.gsf"],
        "XReal and YReal must be positive",
    );
    std::fs::write(dir.join("inverted.png"), png_1x1_with_range(1.0, 0.0)).unwrap();
    fails(dir, &["info", "inverted.png"], "height range is inverted");
    std::fs::write(dir.join("ok.png"), png_1x1_with_range(0.0, 1.0)).unwrap();
    let o = asperity(&["info", "ok.png"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    // Grids refused before anything is allocated.
    fails(
        dir,
        &[
            "--max-memory",
            "1G",
            "ca",
            "gallery",
            "--rules",
            "450",
            "--inits",
            "seed",
            "--tile",
            "100000x100000",
            "-o",
            "g.png",
        ],
        "--tile must be",
    );
    fails(
        dir,
        &[
            "--max-memory",
            "1G",
            "ca",
            "gallery",
            "--rules",
            "450,30,90",
            "--inits",
            "seed,random:0.5",
            "--tile",
            "16000x16000",
            "-o",
            "g.png",
        ],
        "the gallery image would need about",
    );
    // Counts of zero that meant nothing.
    fails(
        dir,
        &[
            "growth",
            "rdsr",
            "--size",
            "16",
            "--layers",
            "2",
            "--samples-per-decade",
            "0",
            "-o",
            "g.npy",
        ],
        "at least 1",
    );
    fails(
        dir,
        &["surface-ca", "builtin:cube", "--frames", "0", "-o", "c.ply"],
        "--frames",
    );
    // A missing folder is named, not the temporary file beside it.
    let o = asperity(
        &["generate", "fbm", "--size", "64", "-o", "nosuch/f.npy"],
        dir,
    );
    assert_clean_failure(&o, "nosuch: the folder does not exist");
    assert!(!stderr(&o).contains(".tmp"), "{}", stderr(&o));
    for f in ["x.npy", "x.png", "x.ply", "f.npy", "s.ply", "r.png"] {
        assert!(!dir.join(f).exists(), "{f} was written");
    }
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

/// Every output of a command lands together or not at all; an interrupted run
/// leaves no temporary file (#20).
#[test]
fn outputs_land_together_and_interruptions_leave_nothing() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(dir.join("h.npy"), "precious").unwrap();
    // The secondary output's folder is missing: the primary must not replace
    // the existing file.
    fails(
        dir,
        &[
            "ca",
            "run",
            "--rule",
            "450",
            "--steps",
            "3",
            "--init",
            "seed",
            "-o",
            "h.npy",
            "--states-out",
            "nosuch/s.npy",
        ],
        "nosuch: the folder does not exist",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("h.npy")).unwrap(),
        "precious"
    );
    // A parameter refused after the first output was computed.
    fails(
        dir,
        &[
            "growth",
            "rdsr",
            "--size",
            "32",
            "--layers",
            "5",
            "--alpha-sizes",
            "8,16",
            "-o",
            "h.npy",
        ],
        "needs at least 3 sizes",
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("h.npy")).unwrap(),
        "precious"
    );

    // SIGTERM in the middle of writing animation frames.
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../subdiv/scenes/tentacle.toml");
    let mut child = Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(["--quiet", "subdiv"])
        .arg(&scene)
        .args(["--frames", "2000", "-o", "t.glb"])
        .current_dir(dir)
        .spawn()
        .unwrap();
    // Wait until frames are being written (their temporaries appear).
    let start = std::time::Instant::now();
    while !std::fs::read_dir(dir)
        .unwrap()
        .any(|e| e.unwrap().file_name().to_string_lossy().ends_with(".tmp"))
    {
        assert!(start.elapsed().as_secs() < 60, "no frame was started");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let left: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp") || n.starts_with("t_"))
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

#[test]
fn a_killed_run_s_temporary_is_named_and_left_alone() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let leftover = dir.join(".h.npy.Ab12Cd.tmp");
    std::fs::write(&leftover, "half a file").unwrap();
    let o = asperity(&["generate", "fbm", "--size", "16", "-o", "h.npy"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: .h.npy.Ab12Cd.tmp was left by an interrupted run"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read_to_string(&leftover).unwrap(), "half a file");
}

#[test]
fn dash_o_dash_writes_one_file_to_stdout_on_success_only() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let o = asperity(
        &[
            "generate", "fbm", "--size", "32", "-o", "-", "--format", "npy",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.starts_with(b"\x93NUMPY"), "an .npy on stdout");
    assert_eq!(o.stdout.len(), 128 + 32 * 32 * 8);
    assert!(stderr(&o).contains("wrote stdout"), "{}", stderr(&o));
    // The same bytes as a file.
    assert!(
        asperity(&["generate", "fbm", "--size", "32", "-o", "f.npy"], dir)
            .status
            .success()
    );
    assert_eq!(std::fs::read(dir.join("f.npy")).unwrap(), o.stdout);
    fails(
        dir,
        &["generate", "fbm", "-o", "-"],
        "needs the format: add --format npy",
    );
    fails(
        dir,
        &["generate", "fbm", "-o", "x.npy", "--format", "npy"],
        "--format names the format of -o -",
    );
    fails(
        dir,
        &["--json", "generate", "fbm", "-o", "-", "--format", "npy"],
        "--json prints its report on stdout",
    );
    fails(
        dir,
        &["generate", "fbm", "-o", "-", "--format", "doc"],
        "--format doc",
    );
    // A command that would write several files sends nothing.
    let frames = asperity(
        &[
            "render",
            "f.npy",
            "--turntable",
            "2",
            "--size",
            "32x32",
            "-o",
            "-",
            "--format",
            "png",
        ],
        dir,
    );
    assert_clean_failure(
        &frames,
        "sends one file to stdout, but this command wrote 2",
    );
    assert!(frames.stdout.is_empty());
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
        &["growth", "rdsr", "--runs", "1000000000", "-o", "h.npy"],
        "the deposition would take at least",
    );
    // Without a time limit, the ensemble's memory is estimated before any run.
    fails(
        dir,
        &[
            "growth",
            "rdsr",
            "--runs",
            "1000000000",
            "--max-memory",
            "1G",
            "--max-time",
            "none",
            "-o",
            "h.npy",
        ],
        "width series of 1000000000 runs",
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
            "18446744073709551615",
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
    std::fs::write(
        dir.join("fin.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
    )
    .unwrap();
    fails(
        dir,
        &[
            "surface-ca",
            "fin.obj",
            "--app",
            "corrosion",
            "--cells",
            "2000",
            "--steps",
            "18446744073709551615",
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

#[test]
fn every_surface_command_refuses_a_bowtie_alike_and_convert_repairs_it() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    std::fs::write(
        dir.join("bowtie.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n",
    )
    .unwrap();
    let needle = "vertex 0 joins 2 separate fans of faces (a non-manifold vertex)";
    fails(
        dir,
        &["surface-ca", "bowtie.obj", "--cells", "500", "-o", "v.ply"],
        needle,
    );
    fails(
        dir,
        &["subdiv", "--base", "bowtie.obj", "-o", "s.ply"],
        needle,
    );
    let o = asperity(&["convert", "--repair", "bowtie.obj", "fixed.obj"], dir);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("1 vertices split"), "{}", stderr(&o));
    let o = asperity(
        &[
            "subdiv",
            "--base",
            "fixed.obj",
            "--levels",
            "1",
            "-o",
            "s.ply",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(
        &[
            "surface-ca",
            "fixed.obj",
            "--cells",
            "500",
            "--sites",
            "2",
            "-o",
            "v.ply",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // A closed substrate is needed for growth on a mesh: the same wording.
    fails(
        dir,
        &[
            "growth",
            "bd",
            "--substrate",
            "mesh",
            "--mesh",
            "fixed.obj",
            "--layers",
            "1",
            "-o",
            "c.ply",
        ],
        "it is not closed",
    );
}
