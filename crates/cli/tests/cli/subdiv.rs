//! `subdiv`, as the README documents it.

use super::*;

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
    write_fin(&dir.join("fin.obj"));
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
