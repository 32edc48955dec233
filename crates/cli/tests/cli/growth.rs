//! `growth` and `reconstruct` with the pipelines, as the README documents them.

use super::*;

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
