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

use std::collections::HashMap;

use asperity_core::{CoreError, PolyMesh};

/// How open boundaries behave.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Boundary {
    /// Boundary edges are sharp; boundary vertices follow the crease rule.
    #[default]
    EdgeOnly,
    /// As `EdgeOnly`, and boundary vertices with two edges stay fixed (corners).
    EdgeAndCorner,
}

/// A mesh with crease sharpness per edge (0 = smooth; ∞ = sharp forever).
#[derive(Clone, Debug, PartialEq)]
pub struct Creased {
    /// The polygons.
    pub mesh: PolyMesh,
    /// Sharpness of tagged edges, keyed by (min vertex, max vertex).
    pub creases: HashMap<(u32, u32), f64>,
}

impl Creased {
    /// No creases.
    pub fn smooth(mesh: PolyMesh) -> Self {
        Self {
            mesh,
            creases: HashMap::new(),
        }
    }
}

#[derive(Clone, Debug)]
struct Edge {
    v: [u32; 2],
    faces: Vec<u32>,
    sharpness: f64,
}

/// A multiplicative hasher for vertex-pair keys: the default SipHash dominated
/// the edge table of large levels, and these keys need no DoS resistance.
#[derive(Default)]
struct PairHasher(u64);

impl std::hash::Hasher for PairHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        }
    }
    fn write_u32(&mut self, i: u32) {
        self.0 = (self.0.rotate_left(32) ^ u64::from(i)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
}

type PairMap<V> = HashMap<(u32, u32), V, std::hash::BuildHasherDefault<PairHasher>>;

/// Compressed adjacency: the items of vertex v are `items[start[v]..start[v + 1]]`.
struct Csr {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Csr {
    fn build<I: Iterator<Item = (u32, u32)>>(n: usize, pairs: impl Fn() -> I) -> Self {
        let mut start = vec![0u32; n + 1];
        for (v, _) in pairs() {
            start[v as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[n] as usize];
        for (v, x) in pairs() {
            items[fill[v as usize] as usize] = x;
            fill[v as usize] += 1;
        }
        Self { start, items }
    }

    fn of(&self, v: usize) -> &[u32] {
        &self.items[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [
        a[0] + t * (b[0] - a[0]),
        a[1] + t * (b[1] - a[1]),
        a[2] + t * (b[2] - a[2]),
    ]
}

/// Edges in first-appearance order, and the edge index of each face corner
/// (corner k of face f uses edge (v_k, v_{k+1})).
fn edges(m: &Creased) -> Result<(Vec<Edge>, Vec<u32>), CoreError> {
    let mut index: PairMap<u32> = PairMap::default();
    index.reserve(m.mesh.n_faces() * 2 + 16);
    let mut list: Vec<Edge> = Vec::new();
    let mut corner_edge = Vec::new();
    for (f, face) in m.mesh.faces().enumerate() {
        for k in 0..face.len() {
            let (a, b) = (face[k], face[(k + 1) % face.len()]);
            let e = *index.entry(key(a, b)).or_insert_with(|| {
                list.push(Edge {
                    v: [a, b],
                    faces: Vec::with_capacity(2),
                    sharpness: m.creases.get(&key(a, b)).copied().unwrap_or(0.0),
                });
                list.len() as u32 - 1
            });
            list[e as usize].faces.push(f as u32);
            if list[e as usize].faces.len() > 2 {
                return Err(CoreError::InvalidParameter {
                    name: "mesh",
                    reason: format!(
                        "edge ({a}, {b}) is shared by more than two faces; Catmull–Clark needs a manifold mesh"
                    ),
                });
            }
            corner_edge.push(e);
        }
    }
    Ok((list, corner_edge))
}

/// One Catmull–Clark step (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for a non-manifold edge or a negative or
/// NaN crease sharpness.
pub fn subdivide(m: &Creased, boundary: Boundary) -> Result<Creased, CoreError> {
    if let Some((e, s)) = m.creases.iter().find(|(_, s)| s.is_nan() || **s < 0.0) {
        return Err(CoreError::InvalidParameter {
            name: "crease",
            reason: format!("edge {e:?} has sharpness {s}; sharpness is ≥ 0"),
        });
    }
    let p = m.mesh.positions();
    let (edges, corner_edge) = edges(m)?;
    let nf = m.mesh.n_faces();
    let ne = edges.len();
    let nv = p.len();
    // Face points.
    let face_pts: Vec<[f64; 3]> = m
        .mesh
        .faces()
        .map(|f| {
            let s = f.iter().fold([0.0; 3], |acc, &v| add(acc, p[v as usize]));
            scale(s, 1.0 / f.len() as f64)
        })
        .collect();
    let sharp = |e: &Edge| e.faces.len() < 2 || e.sharpness > 0.0;
    // Edge points.
    let edge_pts: Vec<[f64; 3]> = edges
        .iter()
        .map(|e| {
            let mid = scale(add(p[e.v[0] as usize], p[e.v[1] as usize]), 0.5);
            if e.faces.len() < 2 || e.sharpness >= 1.0 {
                return mid;
            }
            let smooth = scale(
                add(
                    add(p[e.v[0] as usize], p[e.v[1] as usize]),
                    add(face_pts[e.faces[0] as usize], face_pts[e.faces[1] as usize]),
                ),
                0.25,
            );
            lerp(smooth, mid, e.sharpness)
        })
        .collect();
    // Vertex neighbourhoods.
    let v_edges = Csr::build(nv, || {
        edges
            .iter()
            .enumerate()
            .flat_map(|(i, e)| [(e.v[0], i as u32), (e.v[1], i as u32)])
    });
    let v_faces = Csr::build(nv, || {
        m.mesh
            .faces()
            .enumerate()
            .flat_map(|(f, face)| face.iter().map(move |&v| (v, f as u32)))
    });
    let vert_pts: Vec<[f64; 3]> = (0..nv)
        .map(|v| {
            let pv = p[v];
            let inc = v_edges.of(v);
            if inc.is_empty() {
                return pv;
            }
            let n = inc.len() as f64;
            let other = |e: &Edge| {
                if e.v[0] as usize == v { e.v[1] } else { e.v[0] }
            };
            let sharp_edges: Vec<&Edge> = inc
                .iter()
                .map(|&e| &edges[e as usize])
                .filter(|e| sharp(e))
                .collect();
            let boundary_edges = inc
                .iter()
                .filter(|&&e| edges[e as usize].faces.len() < 2)
                .count();
            let smooth_rule = || {
                let q = v_faces
                    .of(v)
                    .iter()
                    .fold([0.0; 3], |acc, &f| add(acc, face_pts[f as usize]));
                let q = scale(q, 1.0 / v_faces.of(v).len() as f64);
                let r = inc.iter().fold([0.0; 3], |acc, &e| {
                    let e = &edges[e as usize];
                    add(acc, scale(add(p[e.v[0] as usize], p[e.v[1] as usize]), 0.5))
                });
                let r = scale(r, 1.0 / n);
                scale(add(add(q, scale(r, 2.0)), scale(pv, n - 3.0)), 1.0 / n)
            };
            let corner = sharp_edges.len() > 2
                || (boundary == Boundary::EdgeAndCorner && boundary_edges == 2 && inc.len() == 2);
            if corner {
                return pv;
            }
            if sharp_edges.len() == 2 {
                let (a, b) = (other(sharp_edges[0]), other(sharp_edges[1]));
                let crease = scale(
                    add(add(p[a as usize], p[b as usize]), scale(pv, 6.0)),
                    1.0 / 8.0,
                );
                // Boundary edges are infinitely sharp; mean sharpness of tagged ones.
                let sigma = sharp_edges
                    .iter()
                    .map(|e| {
                        if e.faces.len() < 2 {
                            f64::INFINITY
                        } else {
                            e.sharpness
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
        })
        .collect();
    // New faces.
    let mut faces: Vec<[u32; 4]> = Vec::new();
    let mut corner = 0usize;
    for (f, face) in m.mesh.faces().enumerate() {
        let len = face.len();
        for k in 0..len {
            let e_next = corner_edge[corner + k];
            let e_prev = corner_edge[corner + (k + len - 1) % len];
            faces.push([
                (nf + ne) as u32 + face[k],
                nf as u32 + e_next,
                f as u32,
                nf as u32 + e_prev,
            ]);
        }
        corner += len;
    }
    let mut positions = face_pts;
    positions.extend(edge_pts);
    positions.extend(vert_pts);
    // Children of creases: (vertex point, edge point) halves with sharpness − 1.
    let mut creases = HashMap::new();
    for (i, e) in edges.iter().enumerate() {
        if e.faces.len() == 2 && e.sharpness > 1.0 {
            let s = e.sharpness - 1.0;
            let ep = (nf + i) as u32;
            for &v in &e.v {
                creases.insert(key((nf + ne) as u32 + v, ep), s);
            }
        }
    }
    Ok(Creased {
        mesh: PolyMesh::new(positions, &faces)?,
        creases,
    })
}

/// Limit positions of the vertices of a mesh of quads (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`] when a face is not a quad (subdivide once
/// first) or an edge is non-manifold.
pub fn limit_positions(m: &Creased, boundary: Boundary) -> Result<Vec<[f64; 3]>, CoreError> {
    if m.mesh.faces().any(|f| f.len() != 4) {
        return Err(CoreError::InvalidParameter {
            name: "mesh",
            reason: "limit positions need quads; subdivide once first".into(),
        });
    }
    let p = m.mesh.positions();
    let (edges, _) = edges(m)?;
    let nv = p.len();
    let mut v_edges: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (i, e) in edges.iter().enumerate() {
        v_edges[e.v[0] as usize].push(i as u32);
        v_edges[e.v[1] as usize].push(i as u32);
    }
    let mut diag: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for f in m.mesh.faces() {
        for k in 0..4 {
            diag[f[k] as usize].push(f[(k + 2) % 4]);
        }
    }
    Ok((0..nv)
        .map(|v| {
            let pv = p[v];
            let inc = &v_edges[v];
            let other = |e: &Edge| if e.v[0] as usize == v { e.v[1] } else { e.v[0] };
            let sharp: Vec<&Edge> = inc
                .iter()
                .map(|&e| &edges[e as usize])
                .filter(|e| e.faces.len() < 2 || e.sharpness >= 1.0)
                .collect();
            let boundary_edges = inc
                .iter()
                .filter(|&&e| edges[e as usize].faces.len() < 2)
                .count();
            if sharp.len() > 2
                || (boundary == Boundary::EdgeAndCorner && boundary_edges == 2 && inc.len() == 2)
            {
                return pv;
            }
            if sharp.len() == 2 {
                let (a, b) = (p[other(sharp[0]) as usize], p[other(sharp[1]) as usize]);
                return scale(add(add(a, b), scale(pv, 4.0)), 1.0 / 6.0);
            }
            let n = inc.len() as f64;
            let e_sum = inc.iter().fold([0.0; 3], |acc, &e| {
                add(acc, p[other(&edges[e as usize]) as usize])
            });
            let d_sum = diag[v]
                .iter()
                .fold([0.0; 3], |acc, &d| add(acc, p[d as usize]));
            scale(
                add(add(scale(pv, n * n), scale(e_sum, 4.0)), d_sum),
                1.0 / (n * (n + 5.0)),
            )
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

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

    fn grid(n: usize) -> (PolyMesh, Vec<[f64; 3]>) {
        let mut pos = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let z = ((i * 7 + j * 3) % 5) as f64 * 0.3 - 0.2 * (i as f64 - j as f64).abs();
                pos.push([i as f64, j as f64, z]);
            }
        }
        let mut faces = Vec::new();
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                let v = (j * n + i) as u32;
                faces.push([v, v + 1, v + n as u32 + 1, v + n as u32]);
            }
        }
        (PolyMesh::new(pos.clone(), &faces).unwrap(), pos)
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
        let v: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let faces = vec![
            [0u32, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let cube = Creased::smooth(PolyMesh::new(v.clone(), &faces).unwrap());
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
            for k in 0..4 {
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
