//! `ifs`, as the README documents it.

use super::*;

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
