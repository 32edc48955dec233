//! write → read → equal, for every reader/writer pair, by our own reader.

use asperity_core::{HeightField, TriMesh, strategies};
use asperity_io::{NpyDtype, PlyEncoding, Surface, WriteOptions};
use proptest::prelude::*;

use crate::fixtures::{assert_close, flat3, height, octahedron, points, rich_mesh};

fn mesh_roundtrip(ext: &str, opts: &WriteOptions, m: &TriMesh) -> TriMesh {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("m.{ext}"));
    asperity_io::write_mesh(&path, m, opts).unwrap();
    asperity_io::read_mesh(&path).unwrap()
}

fn height_roundtrip(ext: &str, opts: &WriteOptions, h: &HeightField) -> HeightField {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("h.{ext}"));
    asperity_io::write_height(&path, h, opts).unwrap();
    asperity_io::read_height(&path).unwrap()
}

#[test]
fn ply_keeps_everything_but_the_texture() {
    let m = rich_mesh();
    for enc in [PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii] {
        let opts = WriteOptions {
            ply_encoding: enc,
            ..Default::default()
        };
        let r = mesh_roundtrip("ply", &opts, &m);
        assert_eq!(
            r.positions(),
            m.positions(),
            "{enc:?}: f64 positions are exact"
        );
        assert_eq!(r.triangles(), m.triangles());
        assert_eq!(r.colors(), m.colors());
        assert_close(
            r.scalar("curvature").unwrap(),
            m.scalar("curvature").unwrap(),
            0.0,
            "scalar",
        );
        assert_close(
            &flat3(r.normals().unwrap()),
            &flat3(m.normals().unwrap()),
            1e-7,
            "normals (f32)",
        );
        let uv = |m: &TriMesh| {
            m.uvs()
                .unwrap()
                .iter()
                .flatten()
                .copied()
                .collect::<Vec<_>>()
        };
        assert_close(&uv(&r), &uv(&m), 1e-7, "uvs (f32)");
    }
}

#[test]
fn float32_ply_holds_positions_and_scalars_rounded_to_f32() {
    let m = rich_mesh();
    for enc in [PlyEncoding::BinaryLittleEndian, PlyEncoding::Ascii] {
        let dir = tempfile::tempdir().unwrap();
        let (single, double) = (dir.path().join("s.ply"), dir.path().join("d.ply"));
        let opts = WriteOptions {
            ply_encoding: enc,
            ply_float32: true,
            ..Default::default()
        };
        asperity_io::write_mesh(&single, &m, &opts).unwrap();
        let double_opts = WriteOptions {
            ply_encoding: enc,
            ..Default::default()
        };
        asperity_io::write_mesh(&double, &m, &double_opts).unwrap();
        let text = String::from_utf8_lossy(&std::fs::read(&single).unwrap()).into_owned();
        for property in [
            "property float x\n",
            "property float z\n",
            "property float curvature\n",
        ] {
            assert!(text.contains(property), "{enc:?}: {property}");
        }
        assert!(!text.contains("double"), "{enc:?}: no double left");
        let r = asperity_io::read_mesh(&single).unwrap();
        // the same f32 (ASCII prints the shortest text of the f32, which
        // reads back as the nearest f64, so both sides are compared as f32)
        let rounded = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<_>>();
        assert_eq!(
            rounded(&flat3(r.positions())),
            rounded(&flat3(m.positions())),
            "{enc:?}"
        );
        assert_eq!(
            rounded(r.scalar("curvature").unwrap()),
            rounded(m.scalar("curvature").unwrap()),
            "{enc:?}"
        );
        assert_eq!(r.triangles(), m.triangles());
        assert_eq!(r.colors(), m.colors());
        if enc == PlyEncoding::BinaryLittleEndian {
            // x, y, z and one scalar: 16 bytes a vertex fewer, and four
            // header lines one letter shorter ("float" for "double")
            let saved = std::fs::metadata(&double).unwrap().len()
                - std::fs::metadata(&single).unwrap().len();
            assert_eq!(saved, 16 * m.n_vertices() as u64 + 4);
        }
    }
}

/// Equal geometry up to vertex renumbering (OBJ readers number by first use):
/// every triangle's corners have the same positions and colours, in order.
fn assert_same_corners(r: &TriMesh, m: &TriMesh) {
    assert_eq!(r.n_faces(), m.n_faces());
    for (a, b) in r.triangles().iter().zip(m.triangles()) {
        for k in 0..3 {
            assert_eq!(r.positions()[a[k] as usize], m.positions()[b[k] as usize]);
            if let (Some(ca), Some(cb)) = (r.colors(), m.colors()) {
                assert_eq!(ca[a[k] as usize], cb[b[k] as usize]);
            }
        }
    }
    assert_eq!(r.colors().is_some(), m.colors().is_some());
}

#[test]
fn obj_keeps_geometry_colours_uvs_and_writes_texture_sidecars() {
    let m = rich_mesh();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rock.obj");
    asperity_io::write_mesh(&path, &m, &WriteOptions::default()).unwrap();
    assert!(dir.path().join("rock.mtl").exists() && dir.path().join("rock_texture.png").exists());
    let r = asperity_io::read_mesh(&path).unwrap();
    assert_same_corners(&r, &m);
    assert!(r.uvs().is_some() && r.normals().is_some());
}

#[test]
fn stl_welds_back_to_a_closed_mesh() {
    let m = octahedron();
    let r = mesh_roundtrip("stl", &WriteOptions::default(), &m);
    assert_eq!((r.n_vertices(), r.n_faces()), (6, 8));
    assert!(r.is_watertight());
    assert_eq!(r.euler_characteristic(), 2);
    assert!((r.signed_volume() - m.signed_volume()).abs() < 1e-6);
}

#[test]
fn height_formats_roundtrip_within_their_precision() {
    let h = height();
    let (lo, hi) = h.min_max();
    let cases = [
        ("npy", 0.0, true),
        ("csv", 0.0, true),
        ("gsf", 1e-6, true),
        ("gwy", 0.0, true),
        ("x3p", 0.0, true),
        ("exr", 1e-6, true),
        ("png", (hi - lo) / 65535.0 * 0.5 + 1e-12, true),
    ];
    for (ext, tol, geometry) in cases {
        let r = height_roundtrip(ext, &WriteOptions::default(), &h);
        assert_eq!(r.dims(), h.dims(), "{ext}");
        assert_close(r.data(), h.data(), tol, ext);
        if geometry && ext != "npy" {
            assert_close(&r.spacing(), &h.spacing(), 1e-12, &format!("{ext} spacing"));
            assert_close(&r.origin(), &h.origin(), 1e-12, &format!("{ext} origin"));
        }
    }
    let r = height_roundtrip(
        "npy",
        &WriteOptions {
            npy_dtype: NpyDtype::Float32,
            ..Default::default()
        },
        &h,
    );
    assert_close(r.data(), h.data(), 1e-6, "npy f32");
}

#[test]
fn point_formats_roundtrip() {
    let p = points();
    let dir = tempfile::tempdir().unwrap();
    for ext in ["ply", "xyz", "npy"] {
        let path = dir.path().join(format!("p.{ext}"));
        asperity_io::write_points(&path, &p, &WriteOptions::default()).unwrap();
        let r = asperity_io::read_points(&path).unwrap();
        assert_eq!(r.positions(), p.positions(), "{ext}");
        if ext == "ply" {
            assert_eq!(r.attribute("age"), p.attribute("age"));
            assert!(matches!(
                asperity_io::read(&path).unwrap(),
                Surface::Points(_)
            ));
        }
    }
}

#[test]
fn height_field_to_mesh_formats_triangulates() {
    let h = height();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("h.ply");
    asperity_io::write_height(&path, &h, &WriteOptions::default()).unwrap();
    let m = asperity_io::read_mesh(&path).unwrap();
    assert_eq!(m.n_faces(), 2 * 6 * 4);
    assert_eq!(m.scalar("height").unwrap(), h.data());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn any_mesh_roundtrips_through_ply_and_obj(m in strategies::tri_mesh(30, 40)) {
        let r = mesh_roundtrip("ply", &WriteOptions::default(), &m);
        prop_assert_eq!(r.triangles(), m.triangles());
        prop_assert_eq!(r.positions(), m.positions());
        assert_same_corners(&mesh_roundtrip("obj", &WriteOptions::default(), &m), &m);
        let opts = WriteOptions { ply_encoding: PlyEncoding::Ascii, ..Default::default() };
        let r = mesh_roundtrip("ply", &opts, &m);
        prop_assert_eq!(r.positions(), m.positions());
    }

    #[test]
    fn any_height_field_roundtrips(h in strategies::height_field(12)) {
        for ext in ["npy", "csv", "gsf", "gwy", "x3p", "exr", "png"] {
            let r = height_roundtrip(ext, &WriteOptions::default(), &h);
            let (lo, hi) = h.min_max();
            let tol = match ext { "npy" | "csv" | "gwy" | "x3p" => 0.0, "png" => (hi - lo) / 65535.0, _ => 1e-4 };
            prop_assert_eq!(r.dims(), h.dims());
            for (a, b) in r.data().iter().zip(h.data()) {
                prop_assert!((a - b).abs() <= tol, "{}: {} vs {}", ext, a, b);
            }
        }
    }
}

#[test]
fn height_units_survive_every_format_that_has_a_place_for_them() {
    use asperity_core::{LengthUnit, Units};
    let units = Units {
        xy: LengthUnit::Um,
        z: LengthUnit::Nm,
    };
    let h = crate::fixtures::height().with_units(units);
    let dir = tempfile::tempdir().unwrap();
    for ext in ["csv", "png", "exr"] {
        let path = dir.path().join(format!("u.{ext}"));
        asperity_io::write_height(&path, &h, &WriteOptions::default()).unwrap();
        let back = asperity_io::read_height(&path).unwrap();
        assert_eq!(back.units(), units, "{ext}");
        assert_eq!(back.spacing(), h.spacing(), "{ext}");
    }
    // GSF holds base units (Gwyddion's specification): metres, numbers scaled.
    let path = dir.path().join("u.gsf");
    asperity_io::write_height(&path, &h, &WriteOptions::default()).unwrap();
    let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
    assert!(text.contains("XYUnits = m\n") && text.contains("ZUnits = m\n"));
    let back = asperity_io::read_height(&path).unwrap();
    assert_eq!(
        back.units(),
        Units {
            xy: LengthUnit::M,
            z: LengthUnit::M
        }
    );
    assert!((back.spacing()[0] - h.spacing()[0] * 1e-6).abs() < 1e-15);
    let (z, zb) = (h.data()[7], back.data()[7]);
    assert!((zb - z * 1e-9).abs() <= 1e-6 * (z * 1e-9).abs().max(1e-15));
    // a unitless field stays unitless and says nothing about units
    let plain = crate::fixtures::height();
    asperity_io::write_height(&path, &plain, &WriteOptions::default()).unwrap();
    let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
    assert!(!text.contains("Units"));
    assert!(asperity_io::read_height(&path).unwrap().units().is_none());
}

#[test]
fn up_axis_override_writes_and_reads_every_mesh_format_back_unchanged() {
    use asperity_io::{UpAxis, reorient};
    let m = crate::fixtures::octahedron();
    // positions in a fixed order (OBJ and STL readers renumber vertices)
    let sorted = |mut v: Vec<[f64; 3]>| {
        v.sort_by(|a, b| {
            a.iter()
                .zip(b)
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        v
    };
    let tall = |s: &Surface| match s {
        Surface::Mesh(r) => sorted(r.positions().to_vec()),
        _ => unreachable!(),
    };
    let dir = tempfile::tempdir().unwrap();
    for ext in ["obj", "ply", "stl"] {
        for up in [None, Some(UpAxis::Y), Some(UpAxis::Z)] {
            let path = dir.path().join(format!("u.{ext}"));
            let opts = WriteOptions {
                up,
                ..Default::default()
            };
            asperity_io::write_mesh(&path, &m, &opts).unwrap();
            let read = asperity_io::read(&path).unwrap();
            // what the file holds, as a program that takes it as it is sees it
            let raw = tall(&reorient(read.clone(), &path, UpAxis::Z).unwrap());
            let y_up = up == Some(UpAxis::Y) || (up.is_none() && ext == "obj");
            let expected: Vec<[f64; 3]> = m
                .positions()
                .iter()
                .map(|p| if y_up { [p[0], p[2], -p[1]] } else { *p })
                .collect();
            let expected = sorted(expected);
            assert_eq!(raw, expected, "{ext} {up:?}: the file's frame");
            // and read with the same --up (or none, for the defaults) it is the original
            let back = match up {
                Some(u) => reorient(read, &path, u).unwrap(),
                None => read,
            };
            assert_eq!(
                tall(&back),
                sorted(m.positions().to_vec()),
                "{ext} {up:?}: back unchanged"
            );
        }
    }
}

/// Every format with a place for metadata gives back the parameters it was
/// written with, unchanged, and the data reads back as without them; the
/// others record none.
#[test]
fn recorded_parameters_read_back_from_every_format_that_holds_them() {
    let params = serde_json::json!({
        "job": "fbm", "schema_version": 1, "seed": 9, "rms": 1e-5,
        "note": "µm <&> \"a=b\" # ; 表面 🙂", "size": [64, 32]
    });
    let with = WriteOptions {
        params: Some(params.clone()),
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let (h, m) = (height(), rich_mesh());
    for ext in ["png", "exr", "gsf", "gwy", "x3p", "csv", "npy"] {
        let path = dir.path().join(format!("h.{ext}"));
        asperity_io::write_height(&path, &h, &with).unwrap();
        let want = (ext != "npy").then(|| params.clone());
        assert_eq!(asperity_io::read_params(&path).unwrap(), want, "{ext}");
        let plain = height_roundtrip(ext, &WriteOptions::default(), &h);
        assert_eq!(
            asperity_io::read_height(&path).unwrap().data(),
            plain.data(),
            "{ext}"
        );
    }
    for ext in ["ply", "obj", "glb", "stl"] {
        let path = dir.path().join(format!("m.{ext}"));
        let mesh = if ext == "stl" {
            octahedron()
        } else {
            m.clone()
        };
        asperity_io::write_mesh(&path, &mesh, &with).unwrap();
        let want = (ext != "stl").then(|| params.clone());
        assert_eq!(asperity_io::read_params(&path).unwrap(), want, "{ext}");
        if ext != "glb" {
            let read = asperity_io::read_mesh(&path).unwrap();
            assert_eq!(read.n_faces(), mesh.n_faces(), "{ext}");
        }
    }
    for (ext, want) in [("ply", Some(params.clone())), ("xyz", None)] {
        let path = dir.path().join(format!("p.{ext}"));
        asperity_io::write_points(&path, &points(), &with).unwrap();
        assert_eq!(
            asperity_io::read_params(&path).unwrap(),
            want,
            "points .{ext}"
        );
    }
    let png = dir.path().join("render.png");
    let img = asperity_core::RgbaImage::filled(3, 2, [128, 64, 32, 255]);
    asperity_io::write_png_with(&png, &img, &with).unwrap();
    assert_eq!(
        asperity_io::read_params(&png).unwrap(),
        Some(params.clone())
    );
    // Written without parameters, a file records none.
    let bare = dir.path().join("bare.gsf");
    asperity_io::write_height(&bare, &h, &WriteOptions::default()).unwrap();
    assert_eq!(asperity_io::read_params(&bare).unwrap(), None);
}

/// The same surface, units and parameters give the same bytes every time
/// (the EXR writer's attributes sit in hash maps, written in random order).
#[test]
fn every_height_writer_gives_the_same_bytes_twice() {
    let h = height().with_units(asperity_core::Units {
        xy: asperity_core::LengthUnit::Um,
        z: asperity_core::LengthUnit::Nm,
    });
    let opts = WriteOptions {
        params: Some(serde_json::json!({"job": "fbm", "seed": 1})),
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    for ext in ["png", "exr", "gsf", "gwy", "x3p", "csv", "npy"] {
        let bytes: Vec<Vec<u8>> = (0..4)
            .map(|k| {
                let path = dir.path().join(format!("h{k}.{ext}"));
                asperity_io::write_height(&path, &h, &opts).unwrap();
                std::fs::read(&path).unwrap()
            })
            .collect();
        assert!(bytes.windows(2).all(|w| w[0] == w[1]), "{ext}");
    }
}

/// SDF keeps every f64 exactly, in metres, with its parameters.
#[test]
fn sdf_keeps_heights_exactly_in_metres() {
    let h = height();
    let params = serde_json::json!({"job": "test", "seed": 3});
    let opts = WriteOptions {
        params: Some(params.clone()),
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("h.sdf");
    asperity_io::write_height(&path, &h, &opts).unwrap();
    let back = asperity_io::read_height(&path).unwrap();
    let (fx, fz) = h.units().metre_factors();
    assert_eq!(back.dims(), h.dims());
    assert_eq!(back.spacing(), h.spacing().map(|d| d * fx));
    for (b, z) in back.data().iter().zip(h.data()) {
        assert_eq!(*b, z * fz);
    }
    assert_eq!(
        asperity_io::metadata::read_params(&path).unwrap().unwrap()["seed"],
        3
    );
}

/// A file whose extension names no format is read by the magic it starts with
/// (instruments' own extensions, or none).
#[test]
fn unknown_extensions_are_read_by_their_content() {
    let h = height();
    let dir = tempfile::tempdir().unwrap();
    for ext in ["sdf", "npy", "gsf", "png"] {
        let named = dir.path().join(format!("h.{ext}"));
        asperity_io::write_height(&named, &h, &WriteOptions::default()).unwrap();
        let odd = dir.path().join(format!("{ext}-data.instrument"));
        std::fs::rename(&named, &odd).unwrap();
        let back = asperity_io::read_height(&odd).unwrap();
        assert_eq!(back.dims(), h.dims(), "{ext}");
        assert!(
            matches!(asperity_io::read(&odd), Ok(Surface::Height(_))),
            "{ext}"
        );
    }
    let text = dir.path().join("notes.instrument");
    std::fs::write(&text, "not a surface").unwrap();
    let e = asperity_io::read_height(&text).unwrap_err().to_string();
    assert!(e.contains("unknown file type"), "{e}");
}

/// PCL's compressed scan (`tests/data/scans/pcl-milk.pcd`, LZF) read by our
/// PCD reader gives, point for point, the positions a separate Python LZF
/// decoder wrote to `pcl-milk.ply` (see that folder's README).
#[test]
fn pcd_is_read_as_an_independent_decoder_read_it() {
    let dir = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/scans"
    ));
    let pcd = asperity_io::read_points(&dir.join("pcl-milk.pcd")).unwrap();
    let ply = asperity_io::read_points(&dir.join("pcl-milk.ply")).unwrap();
    assert_eq!(pcd.len(), 12_575);
    assert_eq!(pcd.positions(), ply.positions());
    assert!(pcd.colors().is_some());
}
