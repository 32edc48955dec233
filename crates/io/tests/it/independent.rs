//! Our writers read back by independent Rust readers (the `gltf` and `stl_io` crates).

use asperity_io::WriteOptions;

use crate::fixtures::{octahedron, rich_mesh};

#[test]
fn glb_validates_and_carries_every_attribute() {
    let m = rich_mesh();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.glb");
    asperity_io::write_mesh(&path, &m, &WriteOptions::default()).unwrap();
    // gltf::import validates the document, buffers and the embedded image.
    let (doc, buffers, images) = gltf::import(&path).expect("a valid glTF 2.0 binary");
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    let reader = prim.reader(|b| Some(&buffers[b.index()]));
    let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    assert_eq!(pos.len(), m.n_vertices());
    for (g, p) in pos.iter().zip(m.positions()) {
        // y-up: (x, y, z) → (x, z, −y)
        let want = [p[0], p[2], -p[1]];
        for k in 0..3 {
            assert!((g[k] as f64 - want[k]).abs() < 1e-6);
        }
    }
    let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    assert_eq!(
        idx,
        m.triangles().iter().flatten().copied().collect::<Vec<_>>()
    );
    let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    for n in &normals {
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((l - 1.0).abs() < 1e-5, "unit normals");
    }
    // COLOR_0 is linear (glTF 2.0 §3.7.2.1): the sRGB bytes through the sRGB
    // transfer function, 16-bit; back to sRGB they are the bytes again.
    let colors: Vec<[f32; 4]> = reader.read_colors(0).unwrap().into_rgba_f32().collect();
    for (g, c) in colors.iter().zip(m.colors().unwrap()) {
        for k in 0..3 {
            let lin = asperity_io::glb::srgb_to_linear(c[k]);
            assert!(
                (f64::from(g[k]) - lin).abs() < 1.0 / 65535.0,
                "{g:?} vs {c:?}"
            );
            assert_eq!(srgb_byte(g[k]), c[k]);
        }
        assert!((f64::from(g[3]) - f64::from(c[3]) / 255.0).abs() < 1e-4);
    }
    let uv: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
    for (g, t) in uv.iter().zip(m.uvs().unwrap()) {
        assert!((g[0] as f64 - t[0]).abs() < 1e-6 && (g[1] as f64 - (1.0 - t[1])).abs() < 1e-6);
    }
    assert_eq!(images.len(), 1);
    assert_eq!((images[0].width, images[0].height), (4, 4));
    let tex = &rgba(&images[0]);
    let px = |x: usize, y: usize| &tex[4 * (x + 4 * y)..4 * (x + 4 * y) + 4];
    assert_eq!(px(1, 2), &[0, 255, 0, 255]);
    assert_eq!(px(0, 0), &[200, 100, 50, 255]);
    let material = prim.material();
    assert!(
        material
            .pbr_metallic_roughness()
            .base_color_texture()
            .is_some()
    );
    assert!(
        prim.attributes()
            .any(|(s, _)| s.to_string() == "_CURVATURE")
    );
}

/// A decoded texture's pixels as RGBA bytes (an opaque texture is stored
/// as RGB).
fn rgba(image: &gltf::image::Data) -> Vec<u8> {
    match image.format {
        gltf::image::Format::R8G8B8A8 => image.pixels.clone(),
        gltf::image::Format::R8G8B8 => image
            .pixels
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect(),
        other => panic!("texture format {other:?}"),
    }
}

/// A linear value as the sRGB byte a viewer shows (the inverse transfer
/// function, written out here independently of the writer's).
fn srgb_byte(linear: f32) -> u8 {
    let l = f64::from(linear);
    let s = if l <= 0.0031308 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

#[test]
fn glb_pads_a_texture_to_powers_of_two_and_keeps_what_each_vertex_sees() {
    let mut tex = asperity_core::RgbaImage::filled(3, 5, [0, 0, 0, 255]);
    for y in 0..5 {
        for x in 0..3 {
            tex.put(x, y, [40 * x as u8, 50 * y as u8, 7, 255]);
        }
    }
    let m = octahedron();
    // each vertex addresses the centre of one texel (x, row y from the top)
    let texels: Vec<(u32, u32)> = (0..m.n_vertices() as u32).map(|k| (k % 3, k % 5)).collect();
    let uvs: Vec<[f64; 2]> = texels
        .iter()
        .map(|&(x, y)| [(f64::from(x) + 0.5) / 3.0, 1.0 - (f64::from(y) + 0.5) / 5.0])
        .collect();
    let m = m.with_uvs(uvs).unwrap().with_texture(tex.clone());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.glb");
    asperity_io::write_mesh(&path, &m, &WriteOptions::default()).unwrap();
    let (doc, buffers, images) = gltf::import(&path).unwrap();
    assert_eq!((images[0].width, images[0].height), (4, 8));
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    let reader = prim.reader(|b| Some(&buffers[b.index()]));
    let uv: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
    let px = &rgba(&images[0]);
    for (t, &(x, y)) in uv.iter().zip(&texels) {
        let (gx, gy) = ((t[0] * 4.0) as usize, (t[1] * 8.0) as usize);
        assert_eq!(
            &px[4 * (gx + 4 * gy)..4 * (gx + 4 * gy) + 4],
            &tex.get(x, y)
        );
    }
    // without a texture no TEXCOORD_0 is written (it would be unused)
    let bare = octahedron().with_uvs(vec![[0.5, 0.5]; 6]).unwrap();
    asperity_io::write_mesh(&path, &bare, &WriteOptions::default()).unwrap();
    let (doc, _, _) = gltf::import(&path).unwrap();
    let prim = doc.meshes().next().unwrap().primitives().next().unwrap();
    assert!(prim.get(&gltf::Semantic::TexCoords(0)).is_none());
}

#[test]
fn stl_is_read_by_stl_io() {
    let m = octahedron();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("o.stl");
    asperity_io::write_mesh(&path, &m, &WriteOptions::default()).unwrap();
    let mut f = std::fs::File::open(&path).unwrap();
    let other = stl_io::read_stl(&mut f).expect("stl_io reads our STL");
    assert_eq!(other.faces.len(), 8);
    assert_eq!(other.vertices.len(), 6, "stl_io welds to the 6 corners");
    for (face, tri) in other.faces.iter().zip(m.triangles()) {
        for (&vi, &ti) in face.vertices.iter().zip(tri) {
            let v = other.vertices[vi];
            let p = m.positions()[ti as usize];
            assert!((0..3).all(|a| (v[a] as f64 - p[a]).abs() < 1e-7));
        }
        // The stored normal is the outward face normal.
        let c = m.positions()[tri[0] as usize];
        let dot: f64 = (0..3).map(|a| face.normal[a] as f64 * c[a]).sum();
        assert!(dot > 0.0);
    }
}
