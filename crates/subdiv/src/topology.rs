//! The connectivity of one subdivision level, for [`crate::catmull_clark`]:
//! edges numbered in first-appearance order, twins across edges, the corners
//! around every vertex and the crease sharpness of every edge — built by search
//! for a base mesh and in closed form for every refined level.
//!
//! velho-perlin §2 describes the multiresolution surface by its levels; the
//! order of a level's vertices (face points, edge points, vertex points) that
//! every later stage relies on is fixed here by [`Topology::refine`].
//!
//! **Speed.** The edge table is built without hashing: the twin of a face
//! corner is found among the faces of its vertex (compressed adjacency), and
//! every stage runs in parallel with rayon, writing each result at its own
//! index, so the output does not depend on the thread count.

use std::collections::HashMap;

use asperity_core::{CoreError, PolyMesh};
use rayon::prelude::*;

/// "No face" in [`Topology::edge_faces`].
pub const NONE: u32 = u32::MAX;

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

    /// `mesh` with the edges (a, b) tagged with sharpness s.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for a vertex out of range, a pair that is
    /// not an edge of the mesh, or a negative or NaN sharpness.
    pub fn with_creases(mesh: PolyMesh, creases: &[(u32, u32, f64)]) -> Result<Self, CoreError> {
        let mut c = Self::smooth(mesh);
        let n = c.mesh.n_vertices() as u32;
        let edges: std::collections::HashSet<(u32, u32)> = c
            .mesh
            .faces()
            .flat_map(|f| (0..f.len()).map(move |k| key(f[k], f[(k + 1) % f.len()])))
            .collect();
        let bad = |reason: String| CoreError::InvalidParameter {
            name: "crease",
            reason,
        };
        for &(a, b, s) in creases {
            if a >= n || b >= n {
                return Err(bad(format!("{a}-{b}: the base has {n} vertices")));
            }
            if !edges.contains(&key(a, b)) {
                return Err(bad(format!("{a}-{b}: not an edge of the base")));
            }
            if s.is_nan() || s < 0.0 {
                return Err(bad(format!("{a}-{b}: sharpness {s} is negative")));
            }
            c.creases.insert(key(a, b), s);
        }
        Ok(c)
    }
}

/// Compressed adjacency: the items of vertex v are `items[start[v]..start[v + 1]]`.
#[derive(Clone, Debug, Default)]
pub struct Csr {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Csr {
    fn build(n: usize, pairs: impl Iterator<Item = (u32, u32)> + Clone) -> Self {
        let mut start = vec![0u32; n + 1];
        for (v, _) in pairs.clone() {
            start[v as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[n] as usize];
        for (v, x) in pairs {
            items[fill[v as usize] as usize] = x;
            fill[v as usize] += 1;
        }
        Self { start, items }
    }

    /// The items of vertex `v`.
    pub fn of(&self, v: usize) -> &[u32] {
        &self.items[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// The key of edge (a, b) in a crease map: (min, max).
pub(crate) fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The connectivity of one level: edges in first-appearance order (walking the
/// faces' corners), the edge of every corner (corner k of face f uses edge
/// (v_k, v_{k+1})), twins across edges, and the corners of every vertex.
/// Faces must be consistently oriented.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Face offsets (as [`PolyMesh::face_offsets`]).
    pub offsets: Vec<u32>,
    /// The face of every corner (empty for a mesh of quads: corner c is in face c / 4).
    corner_face: Vec<u32>,
    /// The twin corner across the corner's edge ([`NONE`] on a boundary): the
    /// corner of the neighbouring face whose edge runs the other way.
    pub twin: Vec<u32>,
    /// Endpoints of every edge.
    pub edges: Vec<[u32; 2]>,
    /// The one or two faces of every edge (second [`NONE`] on a boundary).
    pub edge_faces: Vec<[u32; 2]>,
    /// Crease sharpness of every edge.
    pub sharpness: Vec<f64>,
    /// The edge of every corner.
    pub corner_edge: Vec<u32>,
    /// Corners of each vertex, in face order.
    pub v_corners: Csr,
    quads: bool,
    /// Whether any edge is a boundary or tagged sharp (else the smooth rules apply everywhere).
    pub(crate) any_sharp: bool,
}

/// Endpoints and faces of the edges a block of corners owns.
type EdgeBlock = (Vec<[u32; 2]>, Vec<[u32; 2]>);

/// Face offsets, face vertices and crease tags of a refined level.
pub type Refined = (Vec<u32>, Vec<u32>, HashMap<(u32, u32), f64>);

/// Corners per block of the parallel edge numbering.
const BLOCK: usize = 1 << 16;

impl Topology {
    /// The connectivity of `m`, found by searching the faces around each
    /// vertex (for a base mesh; refined levels use [`Topology::refined`]).
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] for an edge shared by more than two
    /// faces, faces of inconsistent orientation, or a negative or NaN crease
    /// sharpness.
    pub fn new(m: &Creased) -> Result<Self, CoreError> {
        if let Some((e, s)) = m.creases.iter().find(|(_, s)| s.is_nan() || **s < 0.0) {
            return Err(CoreError::InvalidParameter {
                name: "crease",
                reason: format!("edge {e:?} has sharpness {s}; sharpness is ≥ 0"),
            });
        }
        let offsets = m.mesh.face_offsets().to_vec();
        let fv = m.mesh.face_vertices();
        let nv = m.mesh.n_vertices();
        let nc = fv.len();
        let mut corner_face = vec![0u32; nc];
        for f in 0..offsets.len() - 1 {
            corner_face[offsets[f] as usize..offsets[f + 1] as usize].fill(f as u32);
        }
        let v_corners = Csr::build(nv, fv.iter().enumerate().map(|(c, &v)| (v, c as u32)));
        let quads = m.mesh.faces().all(|f| f.len() == 4);
        let mut topo = Self {
            offsets,
            corner_face,
            twin: Vec::new(),
            edges: Vec::new(),
            edge_faces: Vec::new(),
            sharpness: Vec::new(),
            corner_edge: Vec::new(),
            v_corners,
            quads,
            any_sharp: true,
        };
        // Twins: the corner of another face whose edge joins the same two vertices.
        let t = &topo;
        topo.twin = (0..nc)
            .into_par_iter()
            .map(|c| {
                let (a, b) = (fv[c], fv[t.next(c)]);
                let mut found = NONE;
                let mut same_way = NONE;
                let mut count = 0;
                for &c2 in t.v_corners.of(a as usize) {
                    let c2 = c2 as usize;
                    if t.face_of(c2) == t.face_of(c) {
                        continue;
                    }
                    if fv[t.prev(c2)] == b {
                        found = t.prev(c2) as u32;
                        count += 1;
                    } else if fv[t.next(c2)] == b {
                        same_way = c2 as u32;
                        count += 1;
                    }
                }
                if count > 1 {
                    return Err(CoreError::InvalidParameter {
                        name: "mesh",
                        reason: format!(
                            "edge ({a}, {b}) is shared by more than two faces; Catmull–Clark needs a manifold mesh"
                        ),
                    });
                }
                if same_way != NONE {
                    return Err(CoreError::InvalidParameter {
                        name: "mesh",
                        reason: format!(
                            "faces {} and {} run their shared edge ({a}, {b}) the same way: the orientation is inconsistent; reorient the mesh (e.g. asperity surface-ca --repair, or MeshLab)",
                            t.face_of(c),
                            t.face_of(same_way as usize)
                        ),
                    });
                }
                Ok(found)
            })
            .collect::<Result<_, _>>()?;
        topo.number_edges(fv, &m.creases);
        Ok(topo)
    }

    /// The connectivity of the next level ([`Topology::refine`]'s quads) in
    /// closed form: child quad c has corners 4c…4c + 3, and its twins follow
    /// from this level's twins — no searching.
    pub fn refined(&self, child_fv: &[u32], creases: &HashMap<(u32, u32), f64>) -> Self {
        self.refined_with(child_fv, creases, true)
    }

    /// As [`Topology::refined`]; without `edges` only the vertex adjacency is
    /// built (enough for frames and neighbourhoods, not for refining again).
    pub fn refined_with(
        &self,
        child_fv: &[u32],
        creases: &HashMap<(u32, u32), f64>,
        edges: bool,
    ) -> Self {
        let nc = self.corner_count();
        let nv = self.n_faces() + self.edges.len() + self.n_vertices();
        let twin: Vec<u32> = (0..if edges { 4 * nc } else { 0 })
            .into_par_iter()
            .map(|k| {
                let c = k / 4;
                let x = |t: u32| t == NONE;
                match k % 4 {
                    0 => {
                        let t = self.twin[c];
                        if x(t) {
                            NONE
                        } else {
                            4 * self.next(t as usize) as u32 + 3
                        }
                    }
                    1 => 4 * self.next(c) as u32 + 2,
                    2 => 4 * self.prev(c) as u32 + 1,
                    _ => {
                        let t = self.twin[self.prev(c)];
                        if x(t) { NONE } else { 4 * t }
                    }
                }
            })
            .collect();
        let offsets: Vec<u32> = (0..=nc as u32).into_par_iter().map(|i| 4 * i).collect();
        let v_corners = self.child_corners(nv);
        debug_assert_eq!(child_fv.len(), 4 * nc);
        let mut topo = Self {
            offsets,
            corner_face: Vec::new(),
            twin,
            edges: Vec::new(),
            edge_faces: Vec::new(),
            sharpness: Vec::new(),
            corner_edge: Vec::new(),
            v_corners,
            quads: true,
            any_sharp: true,
        };
        if edges {
            topo.number_edges(child_fv, creases);
        }
        topo
    }

    /// Corners of every child vertex, ascending: face point F(f) is corner 2
    /// of each child quad of f, edge point E(e) corner 1 or 3 of the quads on
    /// either side of e, vertex point V(v) corner 0 of each quad at v.
    fn child_corners(&self, nv: usize) -> Csr {
        let (nf, ne) = (self.n_faces(), self.edges.len());
        let counts: Vec<u32> = (0..nv)
            .into_par_iter()
            .map(|v| {
                if v < nf {
                    self.offsets[v + 1] - self.offsets[v]
                } else if v < nf + ne {
                    if self.is_boundary(v - nf) { 2 } else { 4 }
                } else {
                    self.v_corners.of(v - nf - ne).len() as u32
                }
            })
            .collect();
        let mut start = Vec::with_capacity(nv + 1);
        let mut total = 0u32;
        start.push(0);
        for c in &counts {
            total += c;
            start.push(total);
        }
        let faces = (0..nf)
            .into_par_iter()
            .flat_map_iter(|f| (self.offsets[f]..self.offsets[f + 1]).map(|c| 4 * c + 2));
        let edges = (0..ne).into_par_iter().flat_map_iter(|e| {
            // The owning corner c and, across, its twin t.
            let c = self.owner(e);
            let mut k = [4 * c as u32 + 1, 4 * self.next(c) as u32 + 3, NONE, NONE];
            let t = self.twin[c];
            if t != NONE {
                k[2] = 4 * t + 1;
                k[3] = 4 * self.next(t as usize) as u32 + 3;
            }
            k.sort_unstable();
            k.into_iter().filter(|&x| x != NONE)
        });
        let verts = (0..nv - nf - ne)
            .into_par_iter()
            .flat_map_iter(|v| self.v_corners.of(v).iter().map(|&c| 4 * c));
        let mut items: Vec<u32> = Vec::with_capacity(total as usize);
        items.par_extend(faces);
        items.par_extend(edges);
        items.par_extend(verts);
        Csr { start, items }
    }

    /// The corner that owns edge `e` (its first appearance).
    fn owner(&self, e: usize) -> usize {
        let [a, _] = self.edges[e];
        let f = self.edge_faces[e][0];
        self.v_corners
            .of(a as usize)
            .iter()
            .map(|&c| c as usize)
            .find(|&c| self.face_of(c) == f && self.corner_edge[c] as usize == e)
            .expect("an edge's first face has a corner at its first vertex")
    }

    /// Edge ids in first-appearance order (the corner of the lower face owns
    /// an edge), numbered in parallel blocks with a prefix sum.
    fn number_edges(&mut self, fv: &[u32], creases: &HashMap<(u32, u32), f64>) {
        let nc = fv.len();
        let owns = |c: usize| {
            let t = self.twin[c];
            t == NONE || self.face_of(t as usize) > self.face_of(c)
        };
        let counts: Vec<u32> = (0..nc.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                (b * BLOCK..((b + 1) * BLOCK).min(nc))
                    .filter(|&c| owns(c))
                    .count() as u32
            })
            .collect();
        let mut first = Vec::with_capacity(counts.len());
        let mut total = 0u32;
        for c in &counts {
            first.push(total);
            total += c;
        }
        let mut corner_edge = vec![0u32; nc];
        let blocks: Vec<EdgeBlock> = corner_edge
            .par_chunks_mut(BLOCK)
            .enumerate()
            .map(|(b, chunk)| {
                let mut id = first[b];
                let mut e = Vec::with_capacity(counts[b] as usize);
                let mut f = Vec::with_capacity(counts[b] as usize);
                for (i, slot) in chunk.iter_mut().enumerate() {
                    let c = b * BLOCK + i;
                    if owns(c) {
                        *slot = id;
                        id += 1;
                        e.push([fv[c], fv[self.next(c)]]);
                        let t = self.twin[c];
                        f.push([
                            self.face_of(c),
                            if t == NONE {
                                NONE
                            } else {
                                self.face_of(t as usize)
                            },
                        ]);
                    }
                }
                (e, f)
            })
            .collect();
        let owned = corner_edge.clone();
        corner_edge.par_iter_mut().enumerate().for_each(|(c, e)| {
            if !owns(c) {
                *e = owned[self.twin[c] as usize];
            }
        });
        let mut edges = Vec::with_capacity(total as usize);
        let mut edge_faces = Vec::with_capacity(total as usize);
        for (e, f) in blocks {
            edges.extend(e);
            edge_faces.extend(f);
        }
        self.sharpness = if creases.is_empty() {
            vec![0.0; edges.len()]
        } else {
            edges
                .iter()
                .map(|e| creases.get(&key(e[0], e[1])).copied().unwrap_or(0.0))
                .collect()
        };
        self.any_sharp =
            self.sharpness.iter().any(|&s| s > 0.0) || self.twin.par_iter().any(|&t| t == NONE);
        self.corner_edge = corner_edge;
        self.edges = edges;
        self.edge_faces = edge_faces;
    }

    /// The face of corner `c`.
    pub fn face_of(&self, c: usize) -> u32 {
        if self.quads {
            (c / 4) as u32
        } else {
            self.corner_face[c]
        }
    }

    /// Whether the edge table (twins, edges) has been built: the finest level
    /// of a hierarchy has only its vertex adjacency.
    pub fn has_edges(&self) -> bool {
        !self.twin.is_empty() || self.corner_count() == 0
    }

    pub(crate) fn corner_count(&self) -> usize {
        self.v_corners.items.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.offsets.len() - 1
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.v_corners.start.len() - 1
    }

    /// The corner after `c` in its face.
    pub fn next(&self, c: usize) -> usize {
        if self.quads {
            return (c & !3) | ((c + 1) & 3);
        }
        let f = self.face_of(c) as usize;
        let (s, e) = (self.offsets[f] as usize, self.offsets[f + 1] as usize);
        if c + 1 == e { s } else { c + 1 }
    }

    /// The corner before `c` in its face.
    pub fn prev(&self, c: usize) -> usize {
        if self.quads {
            return (c & !3) | ((c + 3) & 3);
        }
        let f = self.face_of(c) as usize;
        let (s, e) = (self.offsets[f] as usize, self.offsets[f + 1] as usize);
        if c == s { e - 1 } else { c - 1 }
    }

    /// The edges of vertex `v`: the outgoing edge of each of its corners, plus
    /// the incoming boundary edge where its fan opens.
    pub fn vertex_edges(&self, v: usize) -> impl Iterator<Item = usize> + '_ {
        self.v_corners.of(v).iter().flat_map(move |&c| {
            let c = c as usize;
            let p = self.prev(c);
            let open = (self.twin[p] == NONE).then(|| self.corner_edge[p] as usize);
            std::iter::once(self.corner_edge[c] as usize).chain(open)
        })
    }

    /// Number of edges at vertex `v`.
    pub fn valence(&self, v: usize) -> usize {
        self.vertex_edges(v).count()
    }

    pub(crate) fn is_boundary(&self, e: usize) -> bool {
        self.edge_faces[e][1] == NONE
    }

    pub(crate) fn is_sharp(&self, e: usize) -> bool {
        self.is_boundary(e) || self.sharpness[e] > 0.0
    }

    /// Checks that every vertex's faces form one fan (a manifold vertex), as
    /// the per-level rules assume of a base mesh.
    ///
    /// # Errors
    /// [`CoreError::InvalidParameter`] naming the first non-manifold vertex.
    pub fn check_base(&self, fv: &[u32]) -> Result<(), CoreError> {
        let bad = (0..self.n_vertices()).into_par_iter().find_first(|&v| {
            let corners = self.v_corners.of(v);
            if corners.is_empty() {
                return false;
            }
            // Walk the fan from a boundary corner if there is one.
            let start = corners
                .iter()
                .map(|&c| c as usize)
                .find(|&c| self.twin[c] == NONE)
                .unwrap_or(corners[0] as usize);
            let mut c = start;
            let mut seen = 0;
            loop {
                seen += 1;
                // Across the edge (prev, v) into the neighbour, at v's corner there.
                let t = self.twin[self.prev(c)];
                if t == NONE || seen > corners.len() {
                    break;
                }
                let t = t as usize;
                c = if fv[t] == v as u32 { t } else { self.next(t) };
                if c == start {
                    break;
                }
            }
            seen != corners.len()
        });
        match bad {
            Some(v) => Err(CoreError::InvalidParameter {
                name: "mesh",
                reason: format!(
                    "vertex {v} joins separate fans of faces (a non-manifold vertex); Catmull–Clark needs a manifold mesh"
                ),
            }),
            None => Ok(()),
        }
    }

    pub(crate) fn other(&self, e: usize, v: usize) -> usize {
        let [a, b] = self.edges[e];
        if a as usize == v {
            b as usize
        } else {
            a as usize
        }
    }

    /// The connectivity of the next level: quads (V(vᵢ), E(vᵢ, vᵢ₊₁), F(f),
    /// E(vᵢ₋₁, vᵢ)) as CSR arrays, and the children of creases.
    pub fn refine(&self, fv: &[u32]) -> Refined {
        let (nf, ne) = (self.n_faces() as u32, self.edges.len() as u32);
        let nc = fv.len();
        let mut quads = vec![0u32; 4 * nc];
        quads.par_chunks_mut(4).enumerate().for_each(|(c, q)| {
            let f = self.face_of(c);
            q[0] = nf + ne + fv[c];
            q[1] = nf + self.corner_edge[c];
            q[2] = f;
            q[3] = nf + self.corner_edge[self.prev(c)];
        });
        let offsets: Vec<u32> = (0..=nc as u32).map(|i| 4 * i).collect();
        // Children of creases: (vertex point, edge point) halves with sharpness − 1.
        let mut creases = HashMap::new();
        for (i, e) in self.edges.iter().enumerate() {
            let s = self.sharpness[i];
            if !self.is_boundary(i) && s > 1.0 {
                let ep = nf + i as u32;
                for &v in e {
                    creases.insert(key(nf + ne + v, ep), s - 1.0);
                }
            }
        }
        (offsets, quads, creases)
    }

    /// The vertex ring of `v` on a quad mesh, in order around the outward
    /// normal: (edge neighbour, diagonal neighbour) pairs, starting after a
    /// boundary edge if there is one. `None` when `v` is not a quad-mesh vertex.
    pub(crate) fn ring(&self, v: usize, fv: &[u32]) -> Option<Vec<(u32, u32)>> {
        let corners = self.v_corners.of(v);
        let start = corners
            .iter()
            .map(|&c| c as usize)
            .find(|&c| self.twin[c] == NONE)
            .unwrap_or(*corners.first()? as usize);
        let mut ring = Vec::with_capacity(corners.len());
        let mut c = start;
        loop {
            let f = self.face_of(c) as usize;
            if self.offsets[f + 1] - self.offsets[f] != 4 {
                return None;
            }
            ring.push((fv[self.next(c)], fv[self.next(self.next(c))]));
            let t = self.twin[self.prev(c)];
            if t == NONE || ring.len() > corners.len() {
                break;
            }
            let t = t as usize;
            c = if fv[t] == v as u32 { t } else { self.next(t) };
            if c == start {
                break;
            }
        }
        Some(ring)
    }
}
