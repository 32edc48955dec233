//! Built-in base meshes (quads): cube, quad sphere, torus.

use asperity_core::PolyMesh;

/// The cube [−1, 1]³ as 6 outward quads.
pub fn cube() -> PolyMesh {
    let v: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            [
                2.0 * (i & 1) as f64 - 1.0,
                2.0 * ((i >> 1) & 1) as f64 - 1.0,
                2.0 * ((i >> 2) & 1) as f64 - 1.0,
            ]
        })
        .collect();
    let faces = [
        [0u32, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    PolyMesh::new(v, &faces).expect("valid cube")
}

/// A unit quad sphere: the cube with each face split n × n, pushed onto the sphere.
pub fn quad_sphere(n: usize) -> PolyMesh {
    let c = asperity_core::shapes::cube_quads(n);
    let pos = c
        .positions()
        .iter()
        .map(|p| {
            let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [p[0] / l, p[1] / l, p[2] / l]
        })
        .collect();
    c.with_positions(pos).expect("same vertex count")
}

/// A torus of radii `big` and `small` with `nu × nv` quads, outward.
pub fn torus(big: f64, small: f64, nu: usize, nv: usize) -> PolyMesh {
    let (nu, nv) = (nu.max(3), nv.max(3));
    let tau = std::f64::consts::TAU;
    let mut pos = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (tau * i as f64 / nu as f64, tau * j as f64 / nv as f64);
            let r = big + small * b.cos();
            pos.push([r * a.cos(), r * a.sin(), small * b.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let faces: Vec<[u32; 4]> = (0..nu)
        .flat_map(|i| {
            (0..nv).map(move |j| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)])
        })
        .collect();
    PolyMesh::new(pos, &faces).expect("valid torus")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bases_are_closed_and_outward() {
        for (m, chi) in [
            (cube(), 2),
            (quad_sphere(3), 2),
            (torus(1.0, 0.3, 12, 6), 0),
        ] {
            let t = m.triangulate();
            assert!(t.is_watertight() && t.is_consistently_oriented());
            assert_eq!(t.euler_characteristic(), chi);
            assert!(t.signed_volume() > 0.0);
        }
    }
}
