//! Hostile files: decompression bombs, huge headers, ranges that overflow.

use super::*;

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
    // number (a hang): now past the size's bound; the largest size allowed is
    // refused by the memory estimate.
    for size in ["4294967296", "18446744073709551615"] {
        fails(
            dir,
            &["generate", "fbm", "--size", size, "-o", "f.npy"],
            "--size must be in [2, 1048576]",
        );
    }
    fails(
        dir,
        &["generate", "fbm", "--size", "1048576", "-o", "f.npy"],
        "would need about",
    );
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
        "--samples-per-decade must be in [1, 1000], got 0",
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
