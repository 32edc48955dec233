//! `convert`: height fields and meshes between formats, the up axis, repairs.

use super::*;

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
