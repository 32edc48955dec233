//! Bad files give one clear error naming the file, never a panic.

use std::path::Path;

use asperity_io::{IoError, WriteOptions};

use crate::fixtures::{height, octahedron};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn message(r: Result<impl Sized, IoError>) -> String {
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn truncated_ply() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.ply");
    asperity_io::write_mesh(&good, &octahedron(), &WriteOptions::default()).unwrap();
    let bytes = std::fs::read(&good).unwrap();
    for cut in [bytes.len() - 1, bytes.len() - 20, bytes.len() / 2, 30] {
        let p = write(dir.path(), "cut.ply", &bytes[..cut]);
        let m = message(asperity_io::read_mesh(&p));
        assert!(m.contains("cut.ply") && m.contains("PLY"), "{m}");
        assert!(
            m.contains("truncated") || m.contains("end_header"),
            "cut at {cut}: {m}"
        );
    }
}

#[test]
fn obj_with_bad_indices() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "bad.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
    );
    let m = message(asperity_io::read_mesh(&p));
    assert!(m.contains("bad.obj") && m.contains("out of bounds"), "{m}");
}

#[test]
fn missing_points_are_carried_where_a_format_can_and_infinity_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "inf.csv", b"1,2,3\n4,inf,6\n");
    let m = message(asperity_io::read_height(&p));
    assert!(
        m.contains("inf.csv") && m.contains("height 4 is not finite"),
        "{m}"
    );
    // NaN is a missing point: read as one.
    let p = write(dir.path(), "nan.csv", b"1,2,3\n4,nan,6\n");
    let h = asperity_io::read_height(&p).unwrap();
    assert_eq!(h.missing_count(), 1);
    assert!(h.get(1, 1).is_nan());
    let mut h = height();
    *h.get_mut(2, 3) = f64::NAN;
    *h.get_mut(0, 0) = f64::NAN;
    let k = [h.index(0, 0), h.index(2, 3)];
    for ext in ["npy", "exr", "gsf", "gwy", "x3p", "csv"] {
        let target = dir.path().join(format!("out.{ext}"));
        asperity_io::write_height(&target, &h, &WriteOptions::default()).unwrap();
        let back = asperity_io::read_height(&target).unwrap();
        let missing: Vec<usize> = (0..back.len())
            .filter(|&i| back.data()[i].is_nan())
            .collect();
        assert_eq!(missing, k, "{ext}: the same points missing");
    }
    // Meshes get holes; PNG and SDF cannot mark a point and refuse the field.
    let ply = dir.path().join("out.ply");
    asperity_io::write_height(&ply, &h, &WriteOptions::default()).unwrap();
    let mesh = asperity_io::read_mesh(&ply).unwrap();
    assert_eq!(mesh.positions().len(), h.len() - 2);
    for ext in ["png", "sdf"] {
        let target = dir.path().join(format!("out.{ext}"));
        let m = message(asperity_io::write_height(
            &target,
            &h,
            &WriteOptions::default(),
        ));
        assert!(
            m.contains("2 of") && m.contains("not measured"),
            "{ext}: {m}"
        );
        assert!(!target.exists(), "{ext}: nothing written");
    }
    let mut inf = height();
    *inf.get_mut(1, 1) = f64::INFINITY;
    for ext in ["npy", "png", "x3p", "ply"] {
        let target = dir.path().join(format!("inf.{ext}"));
        let m = message(asperity_io::write_height(
            &target,
            &inf,
            &WriteOptions::default(),
        ));
        assert!(m.contains("not finite"), "{ext}: {m}");
        assert!(!target.exists(), "{ext}: nothing written");
    }
}

#[test]
fn wrong_npy_dtype_and_shape() {
    let dir = tempfile::tempdir().unwrap();
    let mut f = b"\x93NUMPY\x01\x00".to_vec();
    let h = "{'descr': '<c8', 'fortran_order': False, 'shape': (2, 2), }\n";
    f.extend_from_slice(&(h.len() as u16).to_le_bytes());
    f.extend_from_slice(h.as_bytes());
    f.extend_from_slice(&[0u8; 32]);
    let p = write(dir.path(), "complex.npy", &f);
    let m = message(asperity_io::read_height(&p));
    assert!(
        m.contains("complex.npy") && m.contains("dtype \"<c8\" is not supported"),
        "{m}"
    );
    let p = dir.path().join("v.npy");
    asperity_io::write_points(&p, &crate::fixtures::points(), &WriteOptions::default()).unwrap();
    // A (20, 3) array is fine as points, and read_height refuses nothing about it
    // (it is a legal 3×20 grid); a 1-D array is a line scan (n × 1) and a 3-D
    // array is refused as a height field.
    let npy = |shape: &str, bytes: usize| {
        let mut f = b"\x93NUMPY\x01\x00".to_vec();
        let h = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}\n");
        f.extend_from_slice(&(h.len() as u16).to_le_bytes());
        f.extend_from_slice(h.as_bytes());
        f.extend_from_slice(&vec![0u8; bytes]);
        f
    };
    let p = write(dir.path(), "line.npy", &npy("(4,)", 32));
    assert_eq!(asperity_io::read_height(&p).unwrap().dims(), [4, 1]);
    let p = write(dir.path(), "cube.npy", &npy("(2, 2, 2)", 64));
    assert!(message(asperity_io::read_height(&p)).contains("needs a 2-D array"));
}

#[test]
fn missing_unknown_and_wrong_kind() {
    let dir = tempfile::tempdir().unwrap();
    let m = message(asperity_io::read_mesh(&dir.path().join("nope.ply")));
    assert!(m.contains("nope.ply") && m.contains("No such file"), "{m}");
    let m = message(asperity_io::read(&write(dir.path(), "x.docx", b"hi")));
    assert!(m.contains("unknown file type \"docx\""), "{m}");
    let m = message(asperity_io::write_mesh(
        &dir.path().join("m.png"),
        &octahedron(),
        &WriteOptions::default(),
    ));
    assert!(m.contains("cannot hold a mesh"), "{m}");
    let m = message(asperity_io::read_height(&write(dir.path(), "e.stl", b"")));
    assert!(m.contains("cannot hold a height field"), "{m}");
    let p = write(dir.path(), "empty.stl", b"");
    assert!(message(asperity_io::read_mesh(&p)).contains("too short"));
    let p = write(
        dir.path(),
        "g.gsf",
        b"Gwyddion Simple Field 1.0\nXRes = 4\nYRes = 4\n\0\0\0\0\0\0",
    );
    assert!(message(asperity_io::read_height(&p)).contains("truncated"));
    let p = write(dir.path(), "junk.exr", b"not an exr at all");
    assert!(message(asperity_io::read_height(&p)).contains("junk.exr"));
    let p = write(dir.path(), "junk.png", b"\x89PNG\r\n\x1a\nxx");
    assert!(message(asperity_io::read_height(&p)).contains("junk.png"));
    let p = write(dir.path(), "junk.x3p", b"PK\x03\x04 not a zip");
    let m = message(asperity_io::read_height(&p));
    assert!(
        m.contains("junk.x3p") && m.contains("not a zip archive"),
        "{m}"
    );
    let p = write(
        dir.path(),
        "junk.gwy",
        b"GWYPGwyContainer\0\xff\xff\xff\x00",
    );
    let m = message(asperity_io::read_height(&p));
    assert!(m.contains("junk.gwy") && m.contains("truncated"), "{m}");
}

#[test]
fn failed_write_keeps_existing_file() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("keep.npy");
    std::fs::write(&target, b"precious").unwrap();
    let mut h = height();
    *h.get_mut(0, 0) = f64::INFINITY;
    assert!(asperity_io::write_height(&target, &h, &WriteOptions::default()).is_err());
    assert_eq!(std::fs::read(&target).unwrap(), b"precious");
    // Writing into a directory that does not exist fails cleanly too.
    let m = message(asperity_io::write_height(
        &dir.path().join("no/such/dir/h.npy"),
        &height(),
        &WriteOptions::default(),
    ));
    assert!(m.contains("no/such/dir: the folder does not exist"), "{m}");
}

#[test]
fn empty_meshes_and_point_sets() {
    let dir = tempfile::tempdir().unwrap();
    let empty = asperity_core::TriMesh::new(vec![[0.0; 3]], vec![]).unwrap();
    for ext in ["ply", "obj", "stl", "glb"] {
        let target = dir.path().join(format!("e.{ext}"));
        let m = message(asperity_io::write_mesh(
            &target,
            &empty,
            &WriteOptions::default(),
        ));
        assert!(m.contains("the mesh (no triangles) is empty"), "{ext}: {m}");
        assert!(!target.exists());
    }
    let m = message(asperity_io::write_points(
        &dir.path().join("e.xyz"),
        &asperity_core::PointSet::new(vec![]),
        &WriteOptions::default(),
    ));
    assert!(m.contains("the point set is empty"), "{m}");
    // A PLY with a face element but no faces, and an OBJ with no faces, are not meshes.
    let p = write(dir.path(), "nofaces.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n");
    assert!(message(asperity_io::read_mesh(&p)).contains("has no faces"));
    let p = write(dir.path(), "nofaces.obj", b"v 0 0 0\n");
    assert!(message(asperity_io::read_mesh(&p)).contains("has no faces"));
}

/// Every prefix of a valid SDF, Digital Surf, TrueMap, BCR, MetroPro, Alicona and
/// WSxM file that ends before its data does is refused with a message (truncation),
/// never read short.
#[test]
fn truncated_instrument_files_are_refused() {
    let seeds = asperity_fixtures::workspace().join("fuzz/seeds");
    for (dir, name) in [
        ("sdf", "sdf-1.sdf"),
        ("sdf", "binary_int16.sdf"),
        ("sur", "s4x3.sur"),
        ("tmd", "t3x2.tmd"),
        ("bcr", "b3x2.bcrf"),
        ("metropro", "m3x2.dat"),
        ("al3d", "a3x2.al3d"),
        ("wsxm", "w3x2.top"),
    ] {
        let whole = std::fs::read(seeds.join(dir).join(name)).unwrap();
        // A text SDF's data ends at its second `*` line; the trailer after it
        // is optional.
        let data_end = if whole.starts_with(b"aISO") {
            let stars: Vec<usize> = whole
                .windows(3)
                .enumerate()
                .filter(|(_, w)| w == b"\n*\n")
                .map(|(k, _)| k)
                .collect();
            stars[1] + 2
        } else {
            whole.len()
        };
        let tmp = tempfile::tempdir().unwrap();
        for cut in 0..data_end {
            let p = write(tmp.path(), &format!("cut.{dir}"), &whole[..cut]);
            let m = message(asperity_io::read_height(&p));
            assert!(m.contains("cut."), "{name} cut at {cut}: {m}");
        }
    }
}

/// Every format the registry reads, from its fuzz seeds (small valid files,
/// `fuzz/seeds/KEY/`, at least one each): each seed cut at 64 places and
/// bit-flipped at 64, each read as that format under a 64 MiB budget,
/// answers with a value or an error naming the file, never a panic.
#[test]
fn every_format_s_seeds_cut_and_flipped_are_answered() {
    use asperity_io::{Format, decode};
    let seeds = asperity_fixtures::workspace().join("fuzz/seeds");
    let budget = asperity_core::MemoryBudget::new(64 << 20);
    let label = Path::new("mangled");
    for &format in Format::ALL {
        let info = format.info();
        if !(info.mesh.can_read() || info.points.can_read() || info.height.can_read()) {
            continue;
        }
        let dir = seeds.join(format.key());
        let files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("no seed of {} in {}: {e}", info.name, dir.display()))
            .map(|f| f.unwrap().path())
            .collect();
        assert!(
            !files.is_empty(),
            "no seed of {} in {}",
            info.name,
            dir.display()
        );
        for file in files {
            let whole = std::fs::read(&file).unwrap();
            let n = whole.len();
            let cuts = (0..64).map(|k| k * n / 64);
            let flips = (0..64).map(|k| n + k * n / 64);
            for m in cuts.chain(flips) {
                let bytes = if m < n {
                    whole[..m].to_vec()
                } else {
                    let mut b = whole.clone();
                    if n > 0 {
                        b[(m - n) % n] ^= 0x5A;
                    }
                    b
                };
                if let Err(e) = decode(label, format, &bytes, &budget) {
                    let e = e.to_string();
                    assert!(e.starts_with("mangled"), "{} ({m}): {e}", file.display());
                }
            }
        }
    }
}
