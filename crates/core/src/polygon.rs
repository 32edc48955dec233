//! Triangles of one polygonal face, as a mesh file gives it (OBJ and PLY
//! faces of any number of corners): a fan from the first corner where the
//! face is convex (every mesh asperity itself writes, and most others: the
//! triangles are what they always were), else ear clipping in the face's
//! plane, so a non-convex face (a comb, a spiral) is covered exactly once —
//! a fan would lay triangles outside it and count its area wrongly.
//!
//! The plane is the face's Newell normal (Newell's method: the normal of
//! the best-fitting plane of a non-planar polygon, from the sum of its edges'
//! cross products). Ear clipping is the `earcut` crate (mapbox/earcut's
//! algorithm: z-order-hashed ear search, near-linear for large polygons);
//! its triangles are turned to the face's winding.

use crate::vec3::{cross, dot, norm, sub};

/// The triangles of the face `face` (indices into `positions`), in the
/// face's winding. A face with an index outside `positions` is fanned (the
/// mesh's constructor reports the index).
pub fn triangulate_face<'a>(positions: &[[f64; 3]], face: &'a [u32]) -> Triangles<'a> {
    let fan = Triangles::Fan { face, k: 1 };
    if face.len() <= 3 || face.iter().any(|&i| i as usize >= positions.len()) {
        return fan;
    }
    let corner = |k: usize| positions[face[k] as usize];
    let normal = newell_normal(face.len(), corner);
    if norm(normal) == 0.0 {
        return fan; // degenerate: no plane to clip in
    }
    let basis = plane_basis(normal);
    let flat = |k: usize| {
        let p = corner(k);
        [dot(p, basis[0]), dot(p, basis[1])]
    };
    if is_convex(face.len(), flat) {
        return fan;
    }
    let corners: Vec<[f64; 2]> = (0..face.len()).map(flat).collect();
    let mut local: Vec<u32> = Vec::with_capacity(3 * (face.len() - 2));
    earcut::Earcut::new().earcut(corners.iter().copied(), &[] as &[u32], &mut local);
    if local.len() < 3 {
        return fan; // earcut gave up (a self-intersecting face)
    }
    let tris: Vec<[u32; 3]> = local
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            let n = cross(sub(corner(b), corner(a)), sub(corner(c), corner(a)));
            if dot(n, normal) >= 0.0 {
                [face[a], face[b], face[c]]
            } else {
                [face[a], face[c], face[b]]
            }
        })
        .collect();
    Triangles::Clipped(tris.into_iter())
}

/// The triangles of one face: its fan, or the ears clipped from it.
pub enum Triangles<'a> {
    /// `[face[0], face[k], face[k + 1]]` for k from 1.
    Fan {
        /// The face's corners.
        face: &'a [u32],
        /// The next fan triangle's second corner.
        k: usize,
    },
    /// Ear-clipped triangles.
    Clipped(std::vec::IntoIter<[u32; 3]>),
}

impl Iterator for Triangles<'_> {
    type Item = [u32; 3];
    fn next(&mut self) -> Option<[u32; 3]> {
        match self {
            Triangles::Fan { face, k } => {
                let t = (*k + 1 < face.len()).then(|| [face[0], face[*k], face[*k + 1]]);
                *k += 1;
                t
            }
            Triangles::Clipped(it) => it.next(),
        }
    }
}

/// Newell's normal of a polygon of `n` corners (twice its vector area).
fn newell_normal(n: usize, corner: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for k in 0..n {
        let (p, q) = (corner(k), corner((k + 1) % n));
        sum[0] += (p[1] - q[1]) * (p[2] + q[2]);
        sum[1] += (p[2] - q[2]) * (p[0] + q[0]);
        sum[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    sum
}

/// Two unit vectors spanning the plane normal to `normal`, right-handed
/// with it (a polygon counter-clockwise about the normal stays so).
fn plane_basis(normal: [f64; 3]) -> [[f64; 3]; 2] {
    let unit = |v: [f64; 3]| {
        let l = norm(v);
        [v[0] / l, v[1] / l, v[2] / l]
    };
    let n = unit(normal);
    let helper = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = unit(cross(helper, n));
    [u, cross(n, u)]
}

/// Whether the polygon of `n` corners turns one way at every corner
/// (collinear corners allowed).
fn is_convex(n: usize, flat: impl Fn(usize) -> [f64; 2]) -> bool {
    let (mut left, mut right) = (false, false);
    for k in 0..n {
        let [a, b, c] = [flat(k), flat((k + 1) % n), flat((k + 2) % n)];
        let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        left |= turn > 0.0;
        right |= turn < 0.0;
        if left && right {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of the triangles in the z = 0 plane.
    fn area(p: &[[f64; 3]], tris: &[[u32; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| p[i as usize]);
                0.5 * cross(sub(b, a), sub(c, a))[2]
            })
            .sum()
    }

    /// A comb of `teeth` teeth: the shoelace area against the triangles', and
    /// every triangle counter-clockwise like the face.
    #[test]
    fn a_comb_is_covered_once() {
        let teeth = 5_000;
        let mut p = vec![[0.0, 0.0, 0.0], [teeth as f64, 0.0, 0.0]];
        for k in (0..teeth).rev() {
            let x = k as f64;
            p.extend([
                [x + 1.0, 1.0, 0.0],
                [x + 0.5, 1.0, 0.0],
                [x + 0.5, 0.2, 0.0],
                [x, 0.2, 0.0],
            ]);
        }
        p.pop();
        let face: Vec<u32> = (0..p.len() as u32).collect();
        let shoelace: f64 = 0.5
            * (0..p.len())
                .map(|k| {
                    let (a, b) = (p[k], p[(k + 1) % p.len()]);
                    a[0] * b[1] - b[0] * a[1]
                })
                .sum::<f64>();
        let tris: Vec<[u32; 3]> = triangulate_face(&p, &face).collect();
        assert_eq!(tris.len(), p.len() - 2);
        let covered = area(&p, &tris);
        assert!(
            (covered - shoelace).abs() <= 1e-9 * shoelace,
            "{covered} vs {shoelace}"
        );
        for t in &tris {
            assert!(area(&p, &[*t]) >= 0.0, "a triangle turned over");
        }
        // A fan from the first corner would count area outside the comb.
        let fan: Vec<[u32; 3]> = (1..face.len() - 1)
            .map(|k| [0, k as u32, k as u32 + 1])
            .collect();
        let fan_abs: f64 = fan.iter().map(|t| area(&p, &[*t]).abs()).sum();
        assert!(fan_abs > 1.01 * shoelace);
    }

    /// A convex face keeps its fan (the triangles every earlier version gave).
    #[test]
    fn a_convex_face_keeps_its_fan() {
        let p: Vec<[f64; 3]> = (0..7)
            .map(|k| {
                let t = k as f64 * std::f64::consts::TAU / 7.0;
                [t.cos(), t.sin(), 0.3 * t.cos()]
            })
            .collect();
        let face: Vec<u32> = (0..7).rev().collect();
        let fan: Vec<[u32; 3]> = (1..6).map(|k| [face[0], face[k], face[k + 1]]).collect();
        assert_eq!(triangulate_face(&p, &face).collect::<Vec<_>>(), fan);
    }
}
