//! Built-in shapes for tests, demos and benchmarks.

use crate::TriMesh;

/// An icosphere of `radius` around the origin: the icosahedron with every
/// triangle split in four `level` times and the vertices pushed onto the sphere
/// (no poles, near-uniform faces, outward orientation). 20·4^level triangles.
pub fn icosphere(level: u32, radius: f64) -> TriMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .to_vec();
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let unit = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|c| c / l)
    };
    p.iter_mut().for_each(|v| *v = unit(*v));
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut split = |a: u32, b: u32, p: &mut Vec<[f64; 3]>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (u, v) = (p[a as usize], p[b as usize]);
                p.push(unit([u[0] + v[0], u[1] + v[1], u[2] + v[2]]));
                (p.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(4 * f.len());
        for &[a, b, c] in &f {
            let (ab, bc, ca) = (
                split(a, b, &mut p),
                split(b, c, &mut p),
                split(c, a, &mut p),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    TriMesh::new(p.into_iter().map(|v| v.map(|c| c * radius)).collect(), f)
        .expect("indices in range")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_is_a_closed_outward_sphere() {
        let s = icosphere(3, 2.0);
        assert_eq!(s.n_faces(), 20 * 64);
        assert!(s.is_watertight());
        assert_eq!(s.euler_characteristic(), 2);
        assert!(
            s.positions()
                .iter()
                .all(|p| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 2.0).abs() < 1e-12)
        );
        let v = s.signed_volume();
        assert!(
            v > 0.0 && (v - 4.0 / 3.0 * std::f64::consts::PI * 8.0).abs() < 0.02 * v,
            "{v}"
        );
    }
}
