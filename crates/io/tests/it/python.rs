//! Every writer read back by Python's reference readers: numpy, plyfile, trimesh,
//! Pillow and OpenEXR (`python/tests/reference/check_formats.py`).
//!
//! The interpreter: `asperity_fixtures::python`.

use std::process::Command;

use asperity_fixtures::{python::python, workspace};

use asperity_io::{NpyDtype, PlyEncoding, WriteOptions};
use serde_json::json;

use crate::fixtures::{flat3, height, octahedron, points, rich_mesh};

#[test]
fn python_reference_readers_accept_every_writer() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let h = height();
    let mesh = rich_mesh();
    let closed = octahedron();
    let pts = points();
    // Every file records parameters (with non-ASCII and XML/JSON-special
    // characters), which no reference reader may stumble on.
    let params =
        json!({"job": "test", "schema_version": 1, "seed": 3, "title": "µm <&> \"=\" 表面"});
    let def = WriteOptions {
        params: Some(params.clone()),
        ..Default::default()
    };
    let ascii = WriteOptions {
        ply_encoding: PlyEncoding::Ascii,
        ..def.clone()
    };
    let f32opt = WriteOptions {
        npy_dtype: NpyDtype::Float32,
        ..def.clone()
    };
    for (name, opts) in [
        ("h.npy", &def),
        ("h32.npy", &f32opt),
        ("h.csv", &def),
        ("h.png", &def),
        ("h.exr", &def),
        ("h.gsf", &def),
    ] {
        asperity_io::write_height(&d.join(name), &h, opts).unwrap();
    }
    asperity_io::write_mesh(&d.join("m.ply"), &mesh, &def).unwrap();
    asperity_io::write_mesh(&d.join("m_ascii.ply"), &mesh, &ascii).unwrap();
    asperity_io::write_mesh(&d.join("m.obj"), &mesh, &def).unwrap();
    asperity_io::write_mesh(&d.join("m.glb"), &mesh, &def).unwrap();
    asperity_io::write_mesh(&d.join("c.stl"), &closed, &def).unwrap();
    let states: Vec<u8> = (0..24).map(|k| (k % 3) as u8).collect();
    asperity_io::write_npy_u8(&d.join("s.npy"), &[2, 3, 4], &states).unwrap();
    let line = vec![vec![[0.0, 0.0, 1.0], [0.5, 0.5, 1.5], [1.0, 0.0, 2.0]]];
    asperity_io::write_mesh_with_polylines(&d.join("l.ply"), &closed, &line, &def).unwrap();
    asperity_io::write_mesh_with_polylines(&d.join("l.obj"), &closed, &line, &def).unwrap();
    for name in ["p.npy", "p.xyz", "p.ply"] {
        asperity_io::write_points(&d.join(name), &pts, &def).unwrap();
    }
    // Polygons kept as they are: a quad and a pentagon.
    let poly_faces: Vec<Vec<u32>> = vec![vec![0, 1, 2, 3], vec![1, 4, 5, 6, 2]];
    let poly = asperity_core::PolyMesh::new(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.1],
            [2.5, 1.0, 0.2],
            [1.5, 1.5, 0.3],
        ],
        &poly_faces,
    )
    .unwrap();
    let attrs = poly.triangulate().with_computed_normals();
    for name in ["q.ply", "q.obj"] {
        asperity_io::write_poly_mesh(&d.join(name), &poly, &attrs, &def).unwrap();
    }
    let (lo, hi) = h.min_max();
    let manifest = json!({
        "height": {"nx": h.nx(), "ny": h.ny(), "data": h.data(), "spacing": h.spacing(), "origin": h.origin(), "min": lo, "max": hi},
        "mesh": {
            "positions": flat3(mesh.positions()),
            "triangles": mesh.triangles(),
            "colors": mesh.colors(),
            "curvature": mesh.scalar("curvature"),
            "uvs": mesh.uvs(),
            "area": mesh.area(),
        },
        "closed": {"positions": flat3(closed.positions()), "n_faces": closed.n_faces(), "volume": closed.signed_volume()},
        "points": {"positions": flat3(pts.positions()), "age": pts.attribute("age")},
        "poly": {"positions": flat3(poly.positions()), "faces": poly_faces},
        "params": params,
    });
    std::fs::write(d.join("manifest.json"), manifest.to_string()).unwrap();
    let script = workspace().join("python/tests/reference/check_formats.py");
    let out = Command::new(python())
        .arg(&script)
        .arg(d)
        .output()
        .expect("run python");
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "python readers disagree:\n{text}");
    // The script prints one OK line per file it checked.
    assert_eq!(text.matches("OK ").count(), 20, "{text}");
}
