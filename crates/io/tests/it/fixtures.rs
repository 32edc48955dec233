//! Shared test data.

use asperity_core::{Diagonal, HeightField, PointSet, RgbaImage, TriMesh};

/// A wavy 7×5 height field with non-unit spacing and a shifted origin.
pub fn height() -> HeightField {
    let (nx, ny) = (7, 5);
    let data = (0..nx * ny)
        .map(|k| {
            let (i, j) = ((k % nx) as f64, (k / nx) as f64);
            (0.7 * i).sin() * (0.9 * j).cos() + 0.01 * i * j - 0.3
        })
        .collect();
    HeightField::from_vec([nx, ny], data)
        .unwrap()
        .with_spacing([0.25, 0.5])
        .unwrap()
        .with_origin([-1.0, 2.0])
        .unwrap()
}

/// The height field as a mesh carrying every optional attribute.
pub fn rich_mesh() -> TriMesh {
    let h = height();
    let m = h.to_trimesh(Diagonal::Alternating).unwrap();
    let n = m.n_vertices();
    let colors = (0..n)
        .map(|i| {
            [
                (i * 37 % 256) as u8,
                (i * 91 % 256) as u8,
                (i * 13 % 256) as u8,
                255,
            ]
        })
        .collect();
    let mut tex = RgbaImage::filled(4, 4, [200, 100, 50, 255]);
    tex.put(1, 2, [0, 255, 0, 255]);
    m.with_computed_normals()
        .with_colors(colors)
        .unwrap()
        .with_scalar(
            "curvature",
            (0..n).map(|i| (i as f64 * 0.37).sin()).collect(),
        )
        .unwrap()
        .with_texture(tex)
}

/// A closed octahedron (χ = 2).
pub fn octahedron() -> TriMesh {
    let p = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let t = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    TriMesh::new(p, t).unwrap()
}

/// A small point cloud with an attribute.
pub fn points() -> PointSet {
    let mut p = PointSet::new(
        (0..20)
            .map(|i| [i as f64 * 0.1, (i as f64).sqrt(), -(i as f64) / 3.0])
            .collect(),
    );
    p.add_attribute("age", (0..20).map(f64::from).collect())
        .unwrap();
    p
}

pub fn assert_close(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert!((x - y).abs() <= tol, "{what}[{k}]: {x} vs {y} (tol {tol})");
    }
}

pub fn flat3(p: &[[f64; 3]]) -> Vec<f64> {
    p.iter().flatten().copied().collect()
}
