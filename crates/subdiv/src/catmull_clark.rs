//! Catmull–Clark subdivision in f64 on any manifold polygon mesh (the base of
//! velho-perlin §2's multiresolution surfaces): quads, triangles, n-gons and
//! extraordinary vertices; boundaries; tagged sharp and semi-sharp creases; limit
//! positions.
//!
//! Written here rather than taken from a crate: no Rust crate offers f64
//! Catmull–Clark with creases and a documented vertex order, and the
//! multiresolution hierarchy needs exactly that order.
//!
//! **Output order.** Level k + 1 has the face points of level k first (one per
//! face, in face order), then the edge points (one per edge, in the order the
//! edges first appear walking the faces' corners), then the vertex points (one
//! per vertex, in vertex order). Face f with corners v₀…v_{m−1} becomes m quads
//! (V(vᵢ), E(vᵢ, vᵢ₊₁), F(f), E(vᵢ₋₁, vᵢ)), keeping its orientation.
//!
//! **Rules** (Catmull & Clark 1978; creases after DeRose, Kass & Truong 1998):
//! - face point: the centroid of the face;
//! - edge point: (v₀ + v₁ + F₀ + F₁)/4 for a smooth interior edge; the midpoint
//!   for a boundary edge or a crease of sharpness ≥ 1; a linear blend of the two
//!   for sharpness s ∈ (0, 1); the children of a crease have sharpness s − 1;
//! - vertex point with fewer than two sharp edges: (Q + 2R + (n − 3)v)/n, with Q
//!   the mean of the adjacent face points and R the mean of the incident edge
//!   midpoints; with exactly two: (a + 6v + b)/8 along the crease; with more
//!   (a corner): v. Boundary edges count as infinitely sharp (OpenSubdiv's
//!   EDGE_ONLY); with [`Boundary::EdgeAndCorner`] a boundary vertex with only two
//!   edges is also a corner. A vertex whose sharp edges have mean sharpness σ < 1
//!   blends the smooth and sharp rules by σ.
//!
//! **Limit positions** (Halstead et al. 1993), on a mesh of quads (after one
//! step): (n²v + 4Σeⱼ + Σdⱼ)/(n(n + 5)) for a smooth vertex of valence n with
//! edge neighbours eⱼ and diagonal neighbours dⱼ; (a + 4v + b)/6 on a crease or
//! boundary; v at a corner.

//!
//! **Limit normals** (Halstead et al. 1993; the tangent masks of Loop &
//! Schaefer 2008): at a smooth vertex of valence n with edge neighbours eⱼ and
//! face neighbours dⱼ in ring order, t₁ = Σ Aₙcos(2πj/n)eⱼ + (cos(2πj/n) +
//! cos(2π(j+1)/n))dⱼ, t₂ the same mask turned by one step, Aₙ = 1 + cos(2π/n) +
//! cos(π/n)√(2(9 + cos(2π/n))), n = t₁ × t₂ — exact. On a crease or boundary
//! the tangent along it is b − a (exact, the cubic B-spline's), and the tangent
//! across is the difference of the next row's limit and this one's (exact on a
//! regular boundary of a B-spline patch, an approximation elsewhere); at a
//! corner the mean face normal.
//!
//! **Speed.** A level's connectivity ([`Topology`], module
//! [`crate::topology`]) is built once; every stage (points, frames) runs in
//! parallel with rayon, writing each result at its own index — the output does
//! not depend on the thread count.

use asperity_core::vec3::{cross, sub};
use asperity_core::{CoreError, PolyMesh};
use rayon::prelude::*;

pub use crate::topology::{Creased, NONE, Topology};

/// How open boundaries behave.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Boundary {
    /// Boundary edges are sharp; boundary vertices follow the crease rule.
    #[default]
    EdgeOnly,
    /// As `EdgeOnly`, and boundary vertices with two edges stay fixed (corners).
    EdgeAndCorner,
}

/// Values that subdivide linearly: positions, scalars, (scalar, weight) pairs.
pub trait Lin: Copy + Send + Sync {
    /// The zero value.
    fn zero() -> Self;
    /// Sum.
    fn plus(self, o: Self) -> Self;
    /// Product with a number.
    fn times(self, s: f64) -> Self;
}

impl Lin for f64 {
    fn zero() -> Self {
        0.0
    }
    fn plus(self, o: Self) -> Self {
        self + o
    }
    fn times(self, s: f64) -> Self {
        self * s
    }
}

impl<const N: usize> Lin for [f64; N] {
    fn zero() -> Self {
        [0.0; N]
    }
    fn plus(self, o: Self) -> Self {
        std::array::from_fn(|k| self[k] + o[k])
    }
    fn times(self, s: f64) -> Self {
        std::array::from_fn(|k| self[k] * s)
    }
}

fn lerp<T: Lin>(a: T, b: T, t: f64) -> T {
    // a + t(b − a), written with plus/times only.
    a.plus(b.plus(a.times(-1.0)).times(t))
}

impl Topology {
    /// One Catmull–Clark step of values living on the vertices (positions,
    /// scalars): face points, edge points, vertex points (see the module docs).
    pub fn subdivide_values<T: Lin>(&self, fv: &[u32], p: &[T], boundary: Boundary) -> Vec<T> {
        let (nf, ne) = (self.n_faces(), self.edges.len());
        let mut out = vec![T::zero(); nf + ne + p.len()];
        let (face_pts, rest) = out.split_at_mut(nf);
        let (edge_pts, vert_pts) = rest.split_at_mut(ne);
        face_pts.par_iter_mut().enumerate().for_each(|(f, out)| {
            let c = &fv[self.offsets[f] as usize..self.offsets[f + 1] as usize];
            let s = c.iter().fold(T::zero(), |acc, &v| acc.plus(p[v as usize]));
            *out = s.times(1.0 / c.len() as f64);
        });
        let face_pts = &*face_pts;
        edge_pts.par_iter_mut().enumerate().for_each(|(e, out)| {
            let [a, b] = self.edges[e];
            let (pa, pb) = (p[a as usize], p[b as usize]);
            let s = self.sharpness[e];
            *out = if self.is_boundary(e) || s >= 1.0 {
                pa.plus(pb).times(0.5)
            } else {
                let [f0, f1] = self.edge_faces[e];
                let smooth = pa
                    .plus(pb)
                    .plus(face_pts[f0 as usize].plus(face_pts[f1 as usize]))
                    .times(0.25);
                if s > 0.0 {
                    lerp(smooth, pa.plus(pb).times(0.5), s)
                } else {
                    smooth
                }
            };
        });
        vert_pts
            .par_iter_mut()
            .enumerate()
            .for_each(|(v, out)| *out = self.vertex_point(v, fv, p, face_pts, boundary));
        out
    }

    fn vertex_point<T: Lin>(
        &self,
        v: usize,
        fv: &[u32],
        p: &[T],
        face_pts: &[T],
        boundary: Boundary,
    ) -> T {
        let pv = p[v];
        if !self.any_sharp {
            // Fast path without creases: an interior vertex's edges are the
            // outgoing edges of its corners.
            let corners = self.v_corners.of(v);
            let mut q = T::zero();
            let mut e = T::zero();
            let mut interior = true;
            for &c in corners {
                let c = c as usize;
                interior &= self.twin[c] != NONE;
                q = q.plus(face_pts[self.face_of(c) as usize]);
                e = e.plus(p[fv[self.next(c)] as usize]);
            }
            if interior && !corners.is_empty() {
                let n = corners.len() as f64;
                // R = (v + mean neighbour)/2, so 2R = v + Σe/n.
                return q
                    .times(1.0 / n)
                    .plus(pv.plus(e.times(1.0 / n)))
                    .plus(pv.times(n - 3.0))
                    .times(1.0 / n);
            }
        }
        let mut n_edges = 0usize;
        let mut sharp = [0usize; 2];
        let mut n_sharp = 0;
        let mut n_boundary = 0;
        for e in self.vertex_edges(v) {
            n_edges += 1;
            if self.is_sharp(e) {
                if n_sharp < 2 {
                    sharp[n_sharp] = e;
                }
                n_sharp += 1;
            }
            n_boundary += usize::from(self.is_boundary(e));
        }
        if n_edges == 0 {
            return pv;
        }
        let n = n_edges as f64;
        let smooth_rule = || {
            let corners = self.v_corners.of(v);
            let q = corners.iter().fold(T::zero(), |acc, &c| {
                acc.plus(face_pts[self.face_of(c as usize) as usize])
            });
            let q = q.times(1.0 / corners.len() as f64);
            let r = self.vertex_edges(v).fold(T::zero(), |acc, e| {
                let [a, b] = self.edges[e];
                acc.plus(p[a as usize].plus(p[b as usize]).times(0.5))
            });
            let r = r.times(1.0 / n);
            q.plus(r.times(2.0)).plus(pv.times(n - 3.0)).times(1.0 / n)
        };
        let corner =
            n_sharp > 2 || (boundary == Boundary::EdgeAndCorner && n_boundary == 2 && n_edges == 2);
        if corner {
            return pv;
        }
        if n_sharp == 2 {
            let (a, b) = (self.other(sharp[0], v), self.other(sharp[1], v));
            let crease = p[a].plus(p[b]).plus(pv.times(6.0)).times(1.0 / 8.0);
            // Boundary edges are infinitely sharp; mean sharpness of tagged ones.
            let sigma = sharp
                .iter()
                .map(|&e| {
                    if self.is_boundary(e) {
                        f64::INFINITY
                    } else {
                        self.sharpness[e]
                    }
                })
                .sum::<f64>()
                / 2.0;
            if sigma >= 1.0 {
                return crease;
            }
            return lerp(smooth_rule(), crease, sigma);
        }
        smooth_rule()
    }
}

/// One Catmull–Clark step (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for a non-manifold edge or a negative or
/// NaN crease sharpness.
pub fn subdivide(m: &Creased, boundary: Boundary) -> Result<Creased, CoreError> {
    let topo = Topology::new(m)?;
    refine_with(m, &topo, boundary)
}

/// One step with the connectivity of `m` already built.
///
/// # Errors
/// As [`PolyMesh::from_csr`] (not expected for a valid topology).
pub fn refine_with(m: &Creased, topo: &Topology, boundary: Boundary) -> Result<Creased, CoreError> {
    let fv = m.mesh.face_vertices();
    let positions = topo.subdivide_values(fv, m.mesh.positions(), boundary);
    let (offsets, quads, creases) = topo.refine(fv);
    let mesh = PolyMesh::from_csr(positions, offsets, quads)?;
    Ok(Creased { mesh, creases })
}

fn require_quads(m: &Creased) -> Result<(), CoreError> {
    if m.mesh.faces().any(|f| f.len() != 4) {
        return Err(CoreError::InvalidParameter {
            name: "mesh",
            reason: "limit positions and normals need quads; subdivide once first".into(),
        });
    }
    Ok(())
}

/// Which limit rule a vertex follows, with its sharp neighbours.
enum Kind {
    Corner,
    Crease(usize, usize),
    Smooth,
}

fn kind(topo: &Topology, v: usize, boundary: Boundary) -> Kind {
    let inc: Vec<usize> = topo.vertex_edges(v).collect();
    let sharp: Vec<usize> = inc
        .iter()
        .copied()
        .filter(|&e| topo.is_boundary(e) || topo.sharpness[e] >= 1.0)
        .collect();
    let n_boundary = inc.iter().filter(|&&e| topo.is_boundary(e)).count();
    if sharp.len() > 2 || (boundary == Boundary::EdgeAndCorner && n_boundary == 2 && inc.len() == 2)
    {
        Kind::Corner
    } else if sharp.len() == 2 {
        Kind::Crease(topo.other(sharp[0], v), topo.other(sharp[1], v))
    } else {
        Kind::Smooth
    }
}

/// Limit positions of the vertices of a mesh of quads (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`] when a face is not a quad (subdivide once
/// first) or an edge is non-manifold.
pub fn limit_positions(m: &Creased, boundary: Boundary) -> Result<Vec<[f64; 3]>, CoreError> {
    require_quads(m)?;
    let topo = Topology::new(m)?;
    let p = m.mesh.positions();
    let fv = m.mesh.face_vertices();
    Ok((0..p.len())
        .into_par_iter()
        .map(|v| limit_point(&topo, fv, p, v, boundary))
        .collect())
}

fn limit_point(
    topo: &Topology,
    fv: &[u32],
    p: &[[f64; 3]],
    v: usize,
    boundary: Boundary,
) -> [f64; 3] {
    let pv = p[v];
    match kind(topo, v, boundary) {
        Kind::Corner => pv,
        Kind::Crease(a, b) => p[a].plus(p[b]).plus(pv.times(4.0)).times(1.0 / 6.0),
        Kind::Smooth => {
            let n = topo.valence(v) as f64;
            let e_sum = topo
                .vertex_edges(v)
                .fold([0.0; 3], |acc: [f64; 3], e| acc.plus(p[topo.other(e, v)]));
            let d_sum = topo
                .v_corners
                .of(v)
                .iter()
                .fold([0.0; 3], |acc: [f64; 3], &c| {
                    acc.plus(p[fv[topo.next(topo.next(c as usize))] as usize])
                });
            pv.times(n * n)
                .plus(e_sum.times(4.0))
                .plus(d_sum)
                .times(1.0 / (n * (n + 5.0)))
        }
    }
}

/// Unit limit normals of the vertices of a mesh of quads (see the module docs).
///
/// # Errors
/// As [`limit_positions`].
pub fn limit_normals(m: &Creased, boundary: Boundary) -> Result<Vec<[f64; 3]>, CoreError> {
    require_quads(m)?;
    let topo = Topology::new(m)?;
    let p = m.mesh.positions();
    let fv = m.mesh.face_vertices();
    let unit = |a: [f64; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        if l > 0.0 && l.is_finite() {
            a.times(1.0 / l)
        } else {
            [0.0, 0.0, 1.0]
        }
    };
    Ok((0..p.len())
        .into_par_iter()
        .map(|v| {
            // Mean face normal: the fallback and the orientation reference.
            let face_n = topo
                .v_corners
                .of(v)
                .iter()
                .fold([0.0; 3], |acc: [f64; 3], &c| {
                    let c = c as usize;
                    let (a, b) = (p[fv[topo.next(c)] as usize], p[fv[topo.prev(c)] as usize]);
                    acc.plus(cross(sub(a, p[v]), sub(b, p[v])))
                });
            let Some(ring) = topo.ring(v, fv) else {
                return unit(face_n);
            };
            match kind(&topo, v, boundary) {
                Kind::Corner => unit(face_n),
                Kind::Crease(a, b) => {
                    let along = sub(p[b], p[a]);
                    let here = limit_point(&topo, fv, p, v, boundary);
                    // The next row: limit of the (edge, diagonal) neighbours off the crease.
                    let off: Vec<[f64; 3]> = ring
                        .iter()
                        .filter(|(e, _)| *e as usize != a && *e as usize != b)
                        .map(|&(e, _)| limit_point(&topo, fv, p, e as usize, boundary))
                        .collect();
                    if off.is_empty() {
                        return unit(face_n);
                    }
                    let mean = off
                        .iter()
                        .fold([0.0; 3], |acc: [f64; 3], q| acc.plus(*q))
                        .times(1.0 / off.len() as f64);
                    let nrm = cross(along, sub(mean, here));
                    let d = nrm[0] * face_n[0] + nrm[1] * face_n[1] + nrm[2] * face_n[2];
                    unit(if d < 0.0 { nrm.times(-1.0) } else { nrm })
                }
                Kind::Smooth => {
                    let n = ring.len();
                    if n != topo.valence(v) {
                        return unit(face_n);
                    }
                    let tau = std::f64::consts::TAU;
                    let nf = n as f64;
                    let a_n = 1.0
                        + (tau / nf).cos()
                        + (std::f64::consts::PI / nf).cos()
                            * (2.0 * (9.0 + (tau / nf).cos())).sqrt();
                    let tangent = |shift: usize| {
                        (0..n).fold([0.0; 3], |acc: [f64; 3], j| {
                            let c0 = (tau * ((j + n - shift) % n) as f64 / nf).cos();
                            let c1 = (tau * ((j + 1 + n - shift) % n) as f64 / nf).cos();
                            let (e, d) = ring[j];
                            acc.plus(p[e as usize].times(a_n * c0))
                                .plus(p[d as usize].times(c0 + c1))
                        })
                    };
                    let nrm = cross(tangent(0), tangent(1));
                    let l2 = nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2];
                    if l2 > 0.0 { unit(nrm) } else { unit(face_n) }
                }
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::key;
    use std::collections::HashMap;

    /// Uniform cubic B-spline basis at t ∈ [0, 1].
    fn basis(t: f64) -> [f64; 4] {
        let s = 1.0 - t;
        [
            s * s * s / 6.0,
            (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
            (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
            t * t * t / 6.0,
        ]
    }

    /// A bumpy n × n grid whose x, y are the B-spline parameters.
    fn grid(n: usize) -> (PolyMesh, Vec<[f64; 3]>) {
        let m = asperity_core::shapes::grid_quads(n, |i, j| {
            ((i * 7 + j * 3) % 5) as f64 * 0.3 - 0.2 * (i as f64 - j as f64).abs()
        });
        let pos = m.positions().to_vec();
        (m, pos)
    }

    /// The bicubic B-spline surface of the grid at (u, v) in index units.
    fn bspline(pos: &[[f64; 3]], n: usize, u: f64, v: f64) -> [f64; 3] {
        let (i, j) = (u.floor() as usize, v.floor() as usize);
        let (bu, bv) = (basis(u - i as f64), basis(v - j as f64));
        let mut out = [0.0; 3];
        for (b, wv) in bv.iter().enumerate() {
            for (a, wu) in bu.iter().enumerate() {
                let p = pos[(j + b - 1) * n + (i + a - 1)];
                for k in 0..3 {
                    out[k] += wu * wv * p[k];
                }
            }
        }
        out
    }

    #[test]
    fn regular_grid_limit_is_the_bicubic_bspline() {
        let n = 8;
        let (mesh, pos) = grid(n);
        let level1 = subdivide(&Creased::smooth(mesh), Boundary::EdgeOnly).unwrap();
        let level2 = subdivide(&level1, Boundary::EdgeOnly).unwrap();
        let limit = limit_positions(&level2, Boundary::EdgeOnly).unwrap();
        // Level 2 vertex points of the level-1 vertex points of original vertex
        // (i, j) sit at the end of the list; their limits are S(i, j). Check every
        // level-2 vertex in the interior by locating it through its x, y, which
        // in this flat-in-xy grid equal the parameters (x and y are linear).
        let mut checked = 0;
        for (k, q) in limit.iter().enumerate() {
            let (u, v) = (q[0], q[1]);
            if !(2.0..=n as f64 - 3.0).contains(&u) || !(2.0..=n as f64 - 3.0).contains(&v) {
                continue;
            }
            let s = bspline(&pos, n, u, v);
            for c in 0..3 {
                assert!(
                    (q[c] - s[c]).abs() < 1e-12,
                    "vertex {k} at ({u}, {v}): {q:?} vs {s:?}"
                );
            }
            checked += 1;
        }
        assert!(checked > 100, "{checked}");
    }

    #[test]
    fn boundaries_and_creases_follow_cubic_bspline_curves() {
        // An open grid: the boundary limit is the cubic B-spline of the boundary row.
        let n = 7;
        let (mesh, pos) = grid(n);
        let level1 = subdivide(&Creased::smooth(mesh.clone()), Boundary::EdgeOnly).unwrap();
        let limit = limit_positions(&level1, Boundary::EdgeOnly).unwrap();
        let mut on_boundary = 0;
        for q in &limit {
            if q[1] == 0.0 && q[0] >= 1.0 && q[0] <= n as f64 - 2.0 {
                on_boundary += 1;
                let i = q[0].floor() as usize;
                let t = q[0] - i as f64;
                let (i, t) = if i == n - 2 { (i - 1, 1.0) } else { (i, t) };
                let b = basis(t);
                let z: f64 = (0..4).map(|a| b[a] * pos[i + a - 1][2]).sum();
                assert!((q[2] - z).abs() < 1e-12, "{q:?} vs {z}");
            }
        }
        assert!(on_boundary >= 9, "{on_boundary}");
        // EDGE_AND_CORNER keeps the four grid corners.
        let c = subdivide(&Creased::smooth(mesh.clone()), Boundary::EdgeAndCorner).unwrap();
        let c = subdivide(&c, Boundary::EdgeAndCorner).unwrap();
        for corner in [pos[0], pos[n - 1], pos[n * (n - 1)], pos[n * n - 1]] {
            assert!(c.mesh.positions().contains(&corner), "{corner:?} moved");
        }
        // An infinitely sharp crease along row j = 3 behaves like a boundary:
        // its limit is the cubic B-spline of that row.
        let mut creases = HashMap::new();
        for i in 0..n - 1 {
            let v = (3 * n + i) as u32;
            creases.insert(key(v, v + 1), f64::INFINITY);
        }
        let creased = Creased { mesh, creases };
        let l1 = subdivide(&creased, Boundary::EdgeOnly).unwrap();
        let l2 = subdivide(&l1, Boundary::EdgeOnly).unwrap();
        let limit = limit_positions(&l2, Boundary::EdgeOnly).unwrap();
        let mut on_crease = 0;
        for q in &limit {
            if q[1] == 3.0 && q[0] >= 1.0 && q[0] <= n as f64 - 2.0 {
                let i = (q[0].floor() as usize).min(n - 3);
                let t = q[0] - i as f64;
                let b = basis(t);
                let z: f64 = (0..4).map(|a| b[a] * pos[3 * n + i + a - 1][2]).sum();
                assert!((q[2] - z).abs() < 1e-12, "{q:?} vs {z}");
                on_crease += 1;
            }
        }
        assert!(on_crease > 10);
    }

    #[test]
    fn cube_converges_and_keeps_its_corners_when_sharp() {
        // The unit cube [0, 1]³: the base cube moved and halved.
        let base = crate::base::cube();
        let v: Vec<[f64; 3]> = base
            .positions()
            .iter()
            .map(|p| p.map(|x| (x + 1.0) / 2.0))
            .collect();
        let faces: Vec<Vec<u32>> = base.faces().map(<[u32]>::to_vec).collect();
        let cube = Creased::smooth(base.with_positions(v.clone()).unwrap());
        // Limit of an extraordinary (valence 3) vertex: repeated subdivision
        // converges to the limit formula.
        let mut m = subdivide(&cube, Boundary::EdgeOnly).unwrap();
        let limit = limit_positions(&m, Boundary::EdgeOnly).unwrap();
        let target = limit[m.mesh.n_vertices() - 8]; // vertex point of vertex 0
        let mut last = f64::INFINITY;
        for _ in 0..8 {
            m = subdivide(&m, Boundary::EdgeOnly).unwrap();
            let p = m.mesh.positions()[m.mesh.n_vertices() - 8];
            let d = ((p[0] - target[0]).powi(2)
                + (p[1] - target[1]).powi(2)
                + (p[2] - target[2]).powi(2))
            .sqrt();
            assert!(d < last, "converges monotonically");
            last = d;
        }
        assert!(last < 1e-4, "{last}");
        // All edges sharp: the corners stay, the faces stay flat.
        let mut creases = HashMap::new();
        for f in &faces {
            for k in 0..f.len() {
                creases.insert(key(f[k], f[(k + 1) % 4]), f64::INFINITY);
            }
        }
        let sharp = Creased {
            mesh: cube.mesh.clone(),
            creases,
        };
        let s2 = subdivide(
            &subdivide(&sharp, Boundary::EdgeOnly).unwrap(),
            Boundary::EdgeOnly,
        )
        .unwrap();
        for p in s2.mesh.positions() {
            assert!(
                p.iter().any(|&x| x == 0.0 || x == 1.0),
                "{p:?} left the faces"
            );
        }
        for c in &v {
            assert!(s2.mesh.positions().contains(c));
        }
    }

    fn euler(m: &PolyMesh) -> (usize, usize, usize) {
        let mut e = std::collections::HashSet::new();
        for f in m.faces() {
            for k in 0..f.len() {
                e.insert(key(f[k], f[(k + 1) % f.len()]));
            }
        }
        (m.n_vertices(), e.len(), m.n_faces())
    }

    #[test]
    fn counts_euler_characteristic_and_exact_cube_values() {
        // The [−1, 1]³ cube; its last vertex is the corner (1, 1, 1).
        let cube = Creased::smooth(crate::base::cube());
        // The corner (1, 1, 1): 5/9 after one step, 55/108 after two, and the same
        // limit position from every level.
        let l1 = subdivide(&cube, Boundary::EdgeOnly).unwrap();
        let l2 = subdivide(&l1, Boundary::EdgeOnly).unwrap();
        let corner = |m: &Creased| m.mesh.positions()[m.mesh.n_vertices() - 1];
        assert!(
            corner(&l1).iter().all(|&x| (x - 5.0 / 9.0).abs() < 1e-15),
            "{:?}",
            corner(&l1)
        );
        assert!(
            corner(&l2)
                .iter()
                .all(|&x| (x - 55.0 / 108.0).abs() < 1e-15),
            "{:?}",
            corner(&l2)
        );
        let lim1 = limit_positions(&l1, Boundary::EdgeOnly).unwrap();
        let lim2 = limit_positions(&l2, Boundary::EdgeOnly).unwrap();
        let l3 = subdivide(&l2, Boundary::EdgeOnly).unwrap();
        let lim3 = limit_positions(&l3, Boundary::EdgeOnly).unwrap();
        let (a, b, c) = (
            lim1[lim1.len() - 1],
            lim2[lim2.len() - 1],
            lim3[lim3.len() - 1],
        );
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() < 1e-14 && (b[k] - c[k]).abs() < 1e-14,
                "{a:?} {b:?} {c:?}"
            );
        }
        // V′ = V + E + F, E′ = 2E + Σ|f|, F′ = Σ|f|; χ preserved — a cube, an open
        // grid, and a mixed triangle/pentagon mesh.
        let (grid_mesh, _) = grid(5);
        let mixed = PolyMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.5, 1.0, 0.0],
                [2.0, 0.5, 0.0],
                [1.8, 1.4, 0.0],
                [1.0, 1.8, 0.0],
            ],
            &[vec![0u32, 1, 2], vec![1, 3, 4, 5, 2]],
        )
        .unwrap();
        for m in [cube.mesh.clone(), grid_mesh, mixed] {
            let (v, e, f) = euler(&m);
            let corners: usize = m.faces().map(<[u32]>::len).sum();
            let s = subdivide(&Creased::smooth(m), Boundary::EdgeOnly).unwrap();
            let (v2, e2, f2) = euler(&s.mesh);
            assert_eq!((v2, e2, f2), (v + e + f, 2 * e + corners, corners));
            assert_eq!(
                v2 as i64 - e2 as i64 + f2 as i64,
                v as i64 - e as i64 + f as i64
            );
        }
    }

    #[test]
    fn closed_form_refined_topology_equals_the_searched_one() {
        let pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [2.0, 0.5, 0.0],
            [1.8, 1.4, 0.0],
            [1.0, 1.8, 0.0],
        ];
        let open = PolyMesh::new(pos, &[vec![0u32, 1, 2], vec![1, 3, 4, 5, 2]]).unwrap();
        for m in [
            open,
            crate::base::cube(),
            crate::base::torus(1.0, 0.3, 5, 4),
        ] {
            let mut c = Creased::smooth(m);
            let t0 = Topology::new(&c).unwrap();
            let inner = (0..t0.edges.len()).find(|&e| !t0.is_boundary(e)).unwrap();
            let [a, b] = t0.edges[inner];
            c.creases.insert(key(a, b), 2.5);
            let mut topo = Topology::new(&c).unwrap();
            for _ in 0..2 {
                let next = refine_with(&c, &topo, Boundary::EdgeOnly).unwrap();
                let closed = topo.refined(next.mesh.face_vertices(), &next.creases);
                let searched = Topology::new(&next).unwrap();
                assert_eq!(closed.twin, searched.twin);
                assert_eq!(closed.edges, searched.edges);
                assert_eq!(closed.edge_faces, searched.edge_faces);
                assert_eq!(closed.corner_edge, searched.corner_edge);
                assert_eq!(closed.sharpness, searched.sharpness);
                assert!(closed.sharpness.iter().any(|&s| s > 0.0));
                c = next;
                topo = closed;
            }
        }
    }

    #[test]
    fn output_order_and_bad_input() {
        // A triangle and a pentagon sharing an edge: counts follow the documented order.
        let pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [2.0, 0.5, 0.0],
            [1.8, 1.4, 0.0],
            [1.0, 1.8, 0.0],
        ];
        let m = PolyMesh::new(pos, &[vec![0u32, 1, 2], vec![1, 3, 4, 5, 2]]).unwrap();
        let s = subdivide(&Creased::smooth(m), Boundary::EdgeOnly).unwrap();
        // 2 faces + 7 edges + 6 vertices; 3 + 5 quads.
        assert_eq!(s.mesh.n_vertices(), 15);
        assert_eq!(s.mesh.n_faces(), 8);
        assert!(s.mesh.faces().all(|f| f.len() == 4));
        // Face points first: the triangle's centroid.
        assert!((s.mesh.positions()[0][0] - 0.5).abs() < 1e-15);
        let bad = Creased {
            mesh: s.mesh.clone(),
            creases: HashMap::from([((0, 1), -1.0)]),
        };
        assert!(subdivide(&bad, Boundary::EdgeOnly).is_err());
        let tri = Creased::smooth(
            PolyMesh::new(
                vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                &[[0u32, 1, 2]],
            )
            .unwrap(),
        );
        assert!(limit_positions(&tri, Boundary::EdgeOnly).is_err());
    }
}
