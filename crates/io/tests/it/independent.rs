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
    let colors: Vec<[u8; 4]> = reader.read_colors(0).unwrap().into_rgba_u8().collect();
    assert_eq!(colors, m.colors().unwrap());
    let uv: Vec<[f32; 2]> = reader.read_tex_coords(0).unwrap().into_f32().collect();
    for (g, t) in uv.iter().zip(m.uvs().unwrap()) {
        assert!((g[0] as f64 - t[0]).abs() < 1e-6 && (g[1] as f64 - (1.0 - t[1])).abs() < 1e-6);
    }
    assert_eq!(images.len(), 1);
    assert_eq!((images[0].width, images[0].height), (4, 4));
    let tex = &images[0].pixels;
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
