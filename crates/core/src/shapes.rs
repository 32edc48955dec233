//! Built-in shapes for tests, demos and benchmarks.

use crate::{PolyMesh, TriMesh};

/// The smallest mesh that is not edge-manifold: three triangles on one edge
/// (a fin). Every reader, checker and command that needs a manifold mesh
/// must refuse it; the tests share this one.
pub fn fin() -> TriMesh {
    TriMesh::new(
        vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    )
    .expect("five vertices, three triangles")
}

/// `n` points spread evenly over the unit sphere: a Fibonacci lattice (z in
/// `n` even steps, longitude advanced by the golden angle π(3 − √5)).
pub fn fibonacci_sphere(n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            [s * t.cos(), s * t.sin(), z]
        })
        .collect()
}

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

/// A closed surface of revolution about the z axis: the `profile` (r, z) runs
/// from one point on the axis (r = 0) to another, and is swept through
/// `segments` angular steps. Poles become triangle fans; faces are oriented
/// outward when the profile goes up the outside (counter-clockwise in the r–z
/// half-plane seen with the axis on the left).
///
/// # Panics
/// Never for valid input; profiles that do not start and end on the axis, or
/// have fewer than three points or segments, give an empty mesh.
pub fn revolve(profile: &[[f64; 2]], segments: usize) -> TriMesh {
    let n = profile.len();
    if n < 3 || segments < 3 || profile[0][0] != 0.0 || profile[n - 1][0] != 0.0 {
        return TriMesh::default();
    }
    let mut pos = vec![[0.0, 0.0, profile[0][1]]];
    let ring = |k: usize| 1 + (k - 1) * segments;
    for p in &profile[1..n - 1] {
        for s in 0..segments {
            let a = std::f64::consts::TAU * s as f64 / segments as f64;
            pos.push([p[0] * a.cos(), p[0] * a.sin(), p[1]]);
        }
    }
    let top = pos.len() as u32;
    pos.push([0.0, 0.0, profile[n - 1][1]]);
    let mut tris = Vec::new();
    let seg = segments as u32;
    for s in 0..seg {
        let t = (s + 1) % seg;
        tris.push([0, 1 + t, 1 + s]);
    }
    for k in 1..n - 2 {
        let (a, b) = (ring(k) as u32, ring(k + 1) as u32);
        for s in 0..seg {
            let t = (s + 1) % seg;
            tris.push([a + s, a + t, b + t]);
            tris.push([a + s, b + t, b + s]);
        }
    }
    let last = ring(n - 2) as u32;
    for s in 0..seg {
        let t = (s + 1) % seg;
        tris.push([last + s, last + t, top]);
    }
    TriMesh::new(pos, tris).unwrap_or_default()
}

/// A cup like gobron-chiba's (Figure 2): a closed surface of revolution with an
/// outer wall, a rim and an inner wall, about 1.2 units tall.
pub fn cup(segments: usize) -> TriMesh {
    revolve(
        &[
            [0.0, 0.0],
            [0.42, 0.0],
            [0.5, 0.08],
            [0.56, 0.6],
            [0.62, 1.2],
            [0.58, 1.22],
            [0.54, 1.18],
            [0.48, 0.6],
            [0.42, 0.14],
            [0.0, 0.12],
        ],
        segments,
    )
}

/// The axis-aligned cube [−1, 1]³, each face split into `n × n` squares of two
/// triangles, oriented outward.
pub fn cube(n: usize) -> TriMesh {
    cube_quads(n).triangulate()
}

/// The axis-aligned cube [−1, 1]³ with each face split into `n × n` outward
/// quads and the shared edge vertices welded (a subdivided cube, or the base of a
/// quad sphere).
pub fn cube_quads(n: usize) -> PolyMesh {
    let n = n.max(1);
    let mut pos: Vec<[f64; 3]> = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut quads = Vec::new();
    let mut vid = |p: [f64; 3], pos: &mut Vec<[f64; 3]>| -> u32 {
        let key = p.map(|x| (x * 1e9).round() as i64);
        *index.entry(key).or_insert_with(|| {
            pos.push(p);
            pos.len() as u32 - 1
        })
    };
    // (normal axis, sign): the face spans the other two axes (u, v) with u × v = normal.
    for (axis, sign) in [
        (0, 1.0),
        (0, -1.0),
        (1, 1.0),
        (1, -1.0),
        (2, 1.0),
        (2, -1.0),
    ] {
        let (u, v) = match axis {
            0 => (1, 2),
            1 => (2, 0),
            _ => (0, 1),
        };
        let at = |i: usize, j: usize| {
            let mut p = [0.0; 3];
            p[axis] = sign;
            let a = -1.0 + 2.0 * i as f64 / n as f64;
            // Mirror u on the negative faces so they stay outward.
            p[u] = if sign > 0.0 { a } else { -a };
            p[v] = -1.0 + 2.0 * j as f64 / n as f64;
            p
        };
        for j in 0..n {
            for i in 0..n {
                let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                quads.push(q.map(|p| vid(p, &mut pos)));
            }
        }
    }
    PolyMesh::from_quads(pos, &quads).expect("valid cube")
}

/// The cube [−1, 1]³ as 8 vertices and 6 outward quads: vertex i sits at
/// (±1, ±1, ±1) with bit 0 of i giving x, bit 1 y and bit 2 z (the classic
/// Catmull–Clark cage; `--crease 0-1:2` and the subdivision tests name its
/// vertices by these numbers).
pub fn cube_cage() -> PolyMesh {
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

/// A torus around the z axis of radii `big` (to the tube's centre) and `small`
/// (the tube's) with `nu × nv` outward quads (at least 3 × 3): vertex
/// (i, j) is `i·nv + j` at angles u = 2πi/nu around z and v = 2πj/nv around
/// the tube.
pub fn torus_quads(big: f64, small: f64, nu: usize, nv: usize) -> PolyMesh {
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

/// [`torus_quads`] with every quad (a, b, c, d) split into (a, b, c) and
/// (a, c, d): closed, outward, genus 1.
pub fn torus(big: f64, small: f64, nu: usize, nv: usize) -> TriMesh {
    torus_quads(big, small, nu, nv).triangulate()
}

/// An open grid of (n − 1)² quads on n × n vertices: vertex i + n·j at
/// (i, j, z(i, j)) in index units, quads counter-clockwise seen from +z (a
/// height-field patch, e.g. for checking subdivision against B-splines).
pub fn grid_quads(n: usize, z: impl Fn(usize, usize) -> f64) -> PolyMesh {
    let n = n.max(2);
    let pos = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            [i as f64, j as f64, z(i, j)]
        })
        .collect();
    let mut faces = Vec::with_capacity((n - 1) * (n - 1));
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let v = (j * n + i) as u32;
            faces.push([v, v + 1, v + n as u32 + 1, v + n as u32]);
        }
    }
    PolyMesh::new(pos, &faces).expect("valid grid")
}

/// A stand-in for Fig. 7's scanned bunny (the Stanford scan ships under no
/// licence a registry package states): a synthetic bunny of five ellipsoids
/// — body, head, two ears, tail — sampled on the boundary of their union
/// (`n` samples per ellipsoid before the hidden ones are dropped), with
/// scanner-like jitter of 0.2 % of its size. It has what the figure needs: a
/// concave neck and ear gaps that a far offset surface (ε = 17 cells) spans
/// and the flow must carve back out over 100 and 200 steps.
pub fn synthetic_bunny(seed: u64, n: usize) -> Vec<[f64; 3]> {
    // (centre, semi-axes) of body, head, ears and tail.
    let parts: [([f64; 3], [f64; 3]); 5] = [
        ([0.0, 0.0, 0.0], [1.0, 0.7, 0.65]),
        ([0.85, 0.0, 0.55], [0.42, 0.38, 0.4]),
        ([0.8, 0.16, 1.15], [0.1, 0.06, 0.38]),
        ([0.8, -0.16, 1.15], [0.1, 0.06, 0.38]),
        ([-1.0, 0.0, 0.15], [0.18, 0.18, 0.18]),
    ];
    let inside = |q: [f64; 3], (c, r): ([f64; 3], [f64; 3])| {
        (0..3).map(|a| ((q[a] - c[a]) / r[a]).powi(2)).sum::<f64>() < 1.0
    };
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut state = seed ^ 0x2545_f491_4f6c_dd1d;
    let mut jitter = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.008
    };
    let mut points = Vec::new();
    for (k, &(c, r)) in parts.iter().enumerate() {
        for i in 0..n {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            let q = [
                c[0] + r[0] * s * t.cos(),
                c[1] + r[1] * s * t.sin(),
                c[2] + r[2] * z,
            ];
            let hidden = parts
                .iter()
                .enumerate()
                .any(|(j, &part)| j != k && inside(q, part));
            if !hidden {
                points.push(q.map(|x| x + jitter()));
            }
        }
    }
    points
}

#[cfg(test)]
mod tests {

    #[test]
    fn cube_and_cup_are_closed_and_outward() {
        let c = cube(3);
        assert!(c.is_watertight() && c.is_consistently_oriented());
        assert_eq!(c.euler_characteristic(), 2);
        assert!((c.signed_volume() - 8.0).abs() < 1e-12);
        assert!((c.area() - 24.0).abs() < 1e-12);
        let k = cup(48);
        assert!(k.is_watertight() && k.is_consistently_oriented());
        assert_eq!(k.euler_characteristic(), 2);
        assert!(k.signed_volume() > 0.0);
        // A cylinder by revolve: volume πr²h within the polygon's deficit.
        let cyl = revolve(&[[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0]], 256);
        let v = cyl.signed_volume();
        assert!((v / (2.0 * std::f64::consts::PI) - 1.0).abs() < 1e-3, "{v}");
        assert!(revolve(&[[1.0, 0.0], [0.0, 1.0]], 8).n_faces() == 0);
    }
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
