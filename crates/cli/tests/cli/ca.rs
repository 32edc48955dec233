//! `ca` (peridier's planar automata) and `surfca` (gobron-chiba's on meshes).

use super::*;

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
        "--size must be in [1, 1048576], got 0",
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
