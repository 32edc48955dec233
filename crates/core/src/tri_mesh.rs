//! Indexed triangle meshes with optional per-vertex data, and topology queries.

use crate::vec3::{cross, norm, sub};
use crate::{Aabb, CoreError, RgbaImage};
use rayon::prelude::*;

/// A named per-vertex (or per-point) scalar, e.g. `"curvature"` or `"height"`.
#[derive(Clone, Debug, PartialEq)]
pub struct Attribute {
    /// Name as written to file headers (PLY property name).
    pub name: String,
    /// One value per vertex.
    pub values: Vec<f64>,
}

/// An undirected edge `(lo, hi)` with the number of faces that use it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgeUse {
    /// Smaller vertex index.
    pub lo: u32,
    /// Larger vertex index.
    pub hi: u32,
    /// Number of incident triangles.
    pub faces: u32,
}

/// A mesh's topology from one pass over its edges ([`TriMesh::topology`]):
/// the answers of [`TriMesh::euler_characteristic`], [`TriMesh::genus`],
/// [`TriMesh::is_manifold`] and [`TriMesh::is_watertight`] without sorting the
/// edges once per question (a reconstruction of a few million triangles spent
/// seconds re-sorting them for its report).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Topology {
    /// Undirected edges.
    pub edges: usize,
    /// Boundary loops ([`TriMesh::boundary_loops`]).
    pub boundary_loops: usize,
    /// χ = V − E + F (every vertex counted, used or not).
    pub euler_characteristic: i64,
    /// Genus of an orientable manifold; `None` if not manifold.
    pub genus: Option<i64>,
    /// No edge shared by more than two triangles.
    pub edge_manifold: bool,
    /// One fan around every used vertex.
    pub vertex_manifold: bool,
    /// Every interior edge traversed once in each direction.
    pub oriented: bool,
    /// Every edge shared by exactly two triangles (and there are triangles).
    pub closed: bool,
}

impl Topology {
    /// Edge- and vertex-manifold.
    pub fn is_manifold(&self) -> bool {
        self.edge_manifold && self.vertex_manifold
    }

    /// Closed, manifold and consistently oriented: it encloses a volume.
    pub fn is_watertight(&self) -> bool {
        self.closed && self.vertex_manifold && self.oriented
    }
}

/// Indexed triangle mesh. Faces are counter-clockwise seen from outside.
///
/// Constructors check indices and finiteness, so a `TriMesh` is always valid;
/// per-vertex arrays (normals, colours, UVs, scalars) always have one entry per vertex.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    normals: Option<Vec<[f64; 3]>>,
    colors: Option<Vec<[u8; 4]>>,
    uvs: Option<Vec<[f64; 2]>>,
    scalars: Vec<Attribute>,
    texture: Option<RgbaImage>,
}

pub(crate) fn check_len(what: &str, got: usize, expected: usize) -> crate::Result<()> {
    if got == expected {
        Ok(())
    } else {
        Err(CoreError::LengthMismatch {
            what: what.to_owned(),
            got,
            expected,
        })
    }
}

pub(crate) fn check_finite_points<const N: usize>(
    what: &'static str,
    pts: &[[f64; N]],
) -> crate::Result<()> {
    for (k, p) in pts.iter().enumerate() {
        if let Some(a) = p.iter().position(|v| !v.is_finite()) {
            return Err(CoreError::NonFinite {
                what,
                index: k,
                value: p[a],
            });
        }
    }
    Ok(())
}

fn normalized(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    if n > 0.0 {
        a.map(|v| v / n)
    } else {
        [0.0, 0.0, 0.0]
    }
}

impl TriMesh {
    /// A mesh of `triangles` over `positions`.
    ///
    /// # Errors
    /// [`CoreError::IndexOutOfRange`] for a bad index, [`CoreError::NonFinite`] for
    /// a NaN or infinite coordinate.
    pub fn new(positions: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> crate::Result<Self> {
        check_finite_points("vertex", &positions)?;
        let n = positions.len();
        for (f, t) in triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&v| v as usize >= n) {
                return Err(CoreError::IndexOutOfRange {
                    face: f,
                    index: index as u64,
                    len: n,
                });
            }
        }
        Ok(Self {
            positions,
            triangles,
            ..Self::default()
        })
    }

    /// A mesh from polygons: a convex polygon fanned from its first corner, a
    /// non-convex one ear-clipped in its plane ([`crate::polygon`]). Unlike [`crate::PolyMesh::new`], repeated corners are
    /// allowed (they give degenerate triangles, as files sometimes contain).
    ///
    /// # Errors
    /// [`CoreError::TooFewCorners`], and as [`TriMesh::new`].
    pub fn from_polygons<F: AsRef<[u32]>>(
        positions: Vec<[f64; 3]>,
        faces: &[F],
    ) -> crate::Result<Self> {
        let mut triangles = Vec::with_capacity(faces.len());
        for (f, face) in faces.iter().enumerate() {
            let face = face.as_ref();
            if face.len() < 3 {
                return Err(CoreError::TooFewCorners {
                    face: f,
                    corners: face.len(),
                });
            }
            triangles.extend(crate::polygon::triangulate_face(&positions, face));
        }
        Self::new(positions, triangles)
    }

    /// Adds per-vertex normals.
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] or [`CoreError::NonFinite`].
    pub fn with_normals(mut self, normals: Vec<[f64; 3]>) -> crate::Result<Self> {
        check_len("normals", normals.len(), self.positions.len())?;
        check_finite_points("normal", &normals)?;
        self.normals = Some(normals);
        Ok(self)
    }
    /// The mesh with `f` applied to every position and normal — for a rotation
    /// or reflection (such as a change of up axis), which keeps normals normals.
    pub fn map_vectors(mut self, f: impl Fn([f64; 3]) -> [f64; 3]) -> Self {
        self.positions.iter_mut().for_each(|p| *p = f(*p));
        if let Some(n) = &mut self.normals {
            n.iter_mut().for_each(|v| *v = f(*v));
        }
        self
    }
    /// Adds per-vertex RGBA colours.
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`].
    pub fn with_colors(mut self, colors: Vec<[u8; 4]>) -> crate::Result<Self> {
        check_len("colors", colors.len(), self.positions.len())?;
        self.colors = Some(colors);
        Ok(self)
    }
    /// Adds per-vertex texture coordinates (u right, v up, as in OBJ and PLY).
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] or [`CoreError::NonFinite`].
    pub fn with_uvs(mut self, uvs: Vec<[f64; 2]>) -> crate::Result<Self> {
        check_len("uvs", uvs.len(), self.positions.len())?;
        check_finite_points("uv", &uvs)?;
        self.uvs = Some(uvs);
        Ok(self)
    }
    /// Attaches a texture image (sampled with the UVs).
    pub fn with_texture(mut self, texture: RgbaImage) -> Self {
        self.texture = Some(texture);
        self
    }
    /// Adds (or replaces) a named per-vertex scalar.
    ///
    /// # Errors
    /// [`CoreError::LengthMismatch`] or [`CoreError::NonFinite`].
    pub fn with_scalar(mut self, name: &str, values: Vec<f64>) -> crate::Result<Self> {
        check_len(name, values.len(), self.positions.len())?;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(CoreError::NonFinite {
                what: "scalar value",
                index: k,
                value: values[k],
            });
        }
        self.scalars.retain(|a| a.name != name);
        self.scalars.push(Attribute {
            name: name.to_owned(),
            values,
        });
        Ok(self)
    }
    /// A mesh whose vertex `i` is a copy of this mesh's vertex `origin[i]` (its
    /// position, normal, colour, UV and scalars), with new `triangles`; the
    /// texture is kept.
    ///
    /// # Errors
    /// [`CoreError::IndexOutOfRange`] for an origin or a triangle index out of range.
    pub fn with_vertices_from(
        &self,
        origin: &[u32],
        triangles: Vec<[u32; 3]>,
    ) -> crate::Result<Self> {
        if let Some(k) = origin
            .iter()
            .position(|&o| o as usize >= self.positions.len())
        {
            return Err(CoreError::IndexOutOfRange {
                face: k,
                index: origin[k] as u64,
                len: self.positions.len(),
            });
        }
        fn pick<T: Copy>(v: &[T], origin: &[u32]) -> Vec<T> {
            origin.iter().map(|&o| v[o as usize]).collect()
        }
        let mut m = Self::new(pick(&self.positions, origin), triangles)?;
        m.normals = self.normals.as_deref().map(|v| pick(v, origin));
        m.colors = self.colors.as_deref().map(|v| pick(v, origin));
        m.uvs = self.uvs.as_deref().map(|v| pick(v, origin));
        m.scalars = self
            .scalars
            .iter()
            .map(|a| Attribute {
                name: a.name.clone(),
                values: pick(&a.values, origin),
            })
            .collect();
        m.texture = self.texture.clone();
        Ok(m)
    }

    /// Drops the stored normals.
    pub fn without_normals(mut self) -> Self {
        self.normals = None;
        self
    }

    /// The mesh without its named per-vertex scalars.
    pub fn without_scalars(mut self) -> Self {
        self.scalars.clear();
        self
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.positions.len()
    }
    /// Number of triangles.
    pub fn n_faces(&self) -> usize {
        self.triangles.len()
    }
    /// Vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }
    /// Triangles as vertex-index triples.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// Per-vertex normals, if stored.
    pub fn normals(&self) -> Option<&[[f64; 3]]> {
        self.normals.as_deref()
    }
    /// Per-vertex RGBA colours, if any.
    pub fn colors(&self) -> Option<&[[u8; 4]]> {
        self.colors.as_deref()
    }
    /// Per-vertex UVs, if any.
    pub fn uvs(&self) -> Option<&[[f64; 2]]> {
        self.uvs.as_deref()
    }
    /// Named per-vertex scalars.
    pub fn scalars(&self) -> &[Attribute] {
        &self.scalars
    }
    /// The values of scalar `name`.
    pub fn scalar(&self, name: &str) -> Option<&[f64]> {
        self.scalars
            .iter()
            .find(|a| a.name == name)
            .map(|a| a.values.as_slice())
    }
    /// The texture image, if any.
    pub fn texture(&self) -> Option<&RgbaImage> {
        self.texture.as_ref()
    }
    /// Bounding box of the vertices, `None` for no vertices.
    pub fn bounds(&self) -> Option<Aabb> {
        Aabb::from_points(&self.positions)
    }

    #[inline]
    fn corners(&self, [a, b, c]: [u32; 3]) -> [[f64; 3]; 3] {
        let p = &self.positions;
        [p[a as usize], p[b as usize], p[c as usize]]
    }

    /// Unit normal of each triangle (zero for degenerate triangles).
    pub fn face_normals(&self) -> Vec<[f64; 3]> {
        self.triangles
            .iter()
            .map(|&t| {
                let [a, b, c] = self.corners(t);
                normalized(cross(sub(b, a), sub(c, a)))
            })
            .collect()
    }

    /// Area-weighted vertex normals (the normalised sum of incident face cross products).
    pub fn vertex_normals(&self) -> Vec<[f64; 3]> {
        let mut acc = vec![[0.0; 3]; self.positions.len()];
        for &t in &self.triangles {
            let [a, b, c] = self.corners(t);
            let n = cross(sub(b, a), sub(c, a));
            for v in t {
                for k in 0..3 {
                    acc[v as usize][k] += n[k];
                }
            }
        }
        acc.into_iter().map(normalized).collect()
    }

    /// Stores [`TriMesh::vertex_normals`] as the mesh's normals.
    pub fn with_computed_normals(mut self) -> Self {
        self.normals = Some(self.vertex_normals());
        self
    }

    /// The meshes of `parts` as one, each part's vertices in its colour, with
    /// computed normals (e.g. an attractor in grey with a curve on it in blue).
    ///
    /// # Errors
    /// [`CoreError::IndexOutOfRange`] if the parts hold more than 2³² vertices.
    pub fn merge_colored(parts: &[(&TriMesh, [u8; 4])]) -> crate::Result<Self> {
        let mut pos = Vec::new();
        let mut tris = Vec::new();
        let mut colors = Vec::new();
        for (m, c) in parts {
            let base = pos.len() as u32;
            pos.extend_from_slice(m.positions());
            tris.extend(m.triangles().iter().map(|t| t.map(|v| v + base)));
            colors.extend(std::iter::repeat_n(*c, m.n_vertices()));
        }
        Ok(TriMesh::new(pos, tris)?
            .with_colors(colors)?
            .with_computed_normals())
    }

    /// Total surface area.
    pub fn area(&self) -> f64 {
        self.sum_over_triangles(|[a, b, c]| 0.5 * norm(cross(sub(b, a), sub(c, a))))
    }

    /// Signed enclosed volume (divergence theorem); meaningful for closed,
    /// consistently oriented meshes, positive when faces point outward.
    pub fn signed_volume(&self) -> f64 {
        self.sum_over_triangles(|[a, b, c]| {
            let n = cross(b, c);
            a[0] * n[0] + a[1] * n[1] + a[2] * n[2]
        }) / 6.0
    }

    /// Σ `f`(corners) over the triangles: blocks of a fixed size summed in
    /// parallel, then the blocks' sums in order, so the rounding is the same
    /// at any thread count.
    fn sum_over_triangles(&self, f: impl Fn([[f64; 3]; 3]) -> f64 + Sync) -> f64 {
        const BLOCK: usize = 1 << 14;
        let blocks: Vec<f64> = self
            .triangles
            .par_chunks(BLOCK)
            .map(|block| {
                let mut sum = 0.0;
                for &t in block {
                    sum += f(self.corners(t));
                }
                sum
            })
            .collect();
        blocks.into_iter().sum()
    }

    /// Every undirected edge with its face count, sorted by `(lo, hi)`.
    pub fn edges(&self) -> Vec<EdgeUse> {
        let mut half: Vec<(u32, u32)> = self
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
            .map(|(u, v)| (u.min(v), u.max(v)))
            .collect();
        half.sort_unstable();
        let mut out: Vec<EdgeUse> = Vec::with_capacity(half.len() / 2 + 1);
        for (lo, hi) in half {
            match out.last_mut() {
                Some(e) if e.lo == lo && e.hi == hi => e.faces += 1,
                _ => out.push(EdgeUse { lo, hi, faces: 1 }),
            }
        }
        out
    }

    /// Euler characteristic χ = V − E + F (all stored vertices count, used or not).
    pub fn euler_characteristic(&self) -> i64 {
        self.euler_from(&self.edges())
    }

    /// Edges used by exactly one triangle.
    pub fn boundary_edges(&self) -> Vec<[u32; 2]> {
        self.edges()
            .into_iter()
            .filter(|e| e.faces == 1)
            .map(|e| [e.lo, e.hi])
            .collect()
    }

    /// Whether no edge is shared by more than two triangles.
    pub fn is_edge_manifold(&self) -> bool {
        self.edges().iter().all(|e| e.faces <= 2)
    }

    /// Whether the triangles around every used vertex form one fan (a disc or a
    /// half-disc), i.e. no two cones touch at a single vertex.
    pub fn is_vertex_manifold(&self) -> bool {
        crate::mesh_check::vertex_fans_single(
            self.positions.len(),
            self.triangles.iter().map(|t| t.as_slice()),
        )
    }

    /// Edge- and vertex-manifold.
    pub fn is_manifold(&self) -> bool {
        self.is_edge_manifold() && self.is_vertex_manifold()
    }

    /// Whether every interior edge is traversed once in each direction (consistent winding).
    pub fn is_consistently_oriented(&self) -> bool {
        let mut directed: Vec<(u32, u32)> = self
            .triangles
            .iter()
            .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
            .collect();
        directed.sort_unstable();
        directed.windows(2).all(|w| w[0] != w[1])
    }

    /// Closed (no boundary edge), manifold and consistently oriented: it encloses a volume.
    pub fn is_watertight(&self) -> bool {
        !self.triangles.is_empty()
            && self.edges().iter().all(|e| e.faces == 2)
            && self.is_vertex_manifold()
            && self.is_consistently_oriented()
    }

    /// Boundary loops as vertex sequences (each loop listed once, open end implied).
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        self.loops_of(&self.edges())
    }

    /// Boundary loops of `edges` (this mesh's [`TriMesh::edges`]).
    fn loops_of(&self, edges: &[EdgeUse]) -> Vec<Vec<u32>> {
        let boundary: std::collections::HashSet<(u32, u32)> = edges
            .iter()
            .filter(|e| e.faces == 1)
            .map(|e| (e.lo, e.hi))
            .collect();
        // Directed boundary half-edges as the faces traverse them.
        let mut next: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
        for &[a, b, c] in &self.triangles {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                if boundary.contains(&(u.min(v), u.max(v))) {
                    next.entry(u).or_default().push(v);
                }
            }
        }
        let mut loops = Vec::new();
        while let Some((&start, _)) = next.iter().next() {
            let mut lp = vec![start];
            let mut cur = start;
            while let Some(outs) = next.get_mut(&cur) {
                let Some(v) = outs.pop() else { break };
                if outs.is_empty() {
                    next.remove(&cur);
                }
                if v == start {
                    break;
                }
                lp.push(v);
                cur = v;
            }
            loops.push(lp);
        }
        loops
    }

    /// Number of connected components of the triangles (isolated vertices ignored).
    pub fn n_components(&self) -> usize {
        component_labels(self.positions.len(), &self.triangles).0
    }

    /// Genus of an orientable manifold: g = (2c − χ − b) / 2 with c components and b
    /// boundary loops (unused vertices excluded from χ). `None` if not manifold.
    pub fn genus(&self) -> Option<i64> {
        if !self.is_manifold() {
            return None;
        }
        let edges = self.edges();
        let loops = self.loops_of(&edges).len();
        Some(self.genus_of(self.euler_from(&edges), loops))
    }

    fn euler_from(&self, edges: &[EdgeUse]) -> i64 {
        self.positions.len() as i64 - edges.len() as i64 + self.triangles.len() as i64
    }

    /// The genus of a manifold with this Euler characteristic and number of
    /// boundary loops.
    fn genus_of(&self, euler: i64, boundary_loops: usize) -> i64 {
        let mut used = vec![false; self.positions.len()];
        for t in &self.triangles {
            for &v in t {
                used[v as usize] = true;
            }
        }
        let unused = used.iter().filter(|u| !**u).count() as i64;
        let chi = euler - unused;
        let c = self.n_components() as i64;
        (2 * c - chi - boundary_loops as i64) / 2
    }

    /// Euler characteristic, genus, manifoldness, orientation and closure (see
    /// [`Topology`]), from each vertex's link: the (previous, next) corners of
    /// the triangles around it, gathered once, then read vertex by vertex in
    /// parallel. A mesh with degenerate triangles (a vertex repeated) takes the
    /// sorted-edges path instead.
    pub fn topology(&self) -> Topology {
        let corners = 3 * self.triangles.len() as u64;
        self.topology_in_batches((corners / LINK_BATCHES).clamp(1 << 20, u32::MAX as u64) as u32)
    }

    /// [`TriMesh::topology`] holding the links of about `corners` corners at
    /// a time.
    fn topology_in_batches(&self, corners: u32) -> Topology {
        if self
            .triangles
            .iter()
            .any(|&[a, b, c]| a == b || b == c || c == a)
        {
            return self.topology_by_edges();
        }
        use crate::mesh_check::{LinkFacts, Links, corner_starts, link_batches};
        let n = self.positions.len();
        // The links a batch of vertices at a time, to bound the memory: each
        // batch reads all the triangles (a fast scan) for its corners.
        let start = corner_starts(n, &self.triangles);
        let mut facts = LinkFacts::default();
        for range in link_batches(&start, corners) {
            let links = Links::new(&start, range.clone(), &self.triangles);
            let batch = range
                .into_par_iter()
                .with_min_len(4096)
                .map(|v| links.examine(v as u32))
                .reduce(LinkFacts::default, LinkFacts::merge);
            facts = LinkFacts::merge(facts, batch);
        }
        drop(start);
        let edge_manifold = facts.max_faces <= 2;
        let closed = !self.triangles.is_empty() && facts.boundary_edges == 0 && edge_manifold;
        let boundary_loops = if facts.boundary_edges > 0 {
            self.loops_of(&self.edges()).len()
        } else {
            0
        };
        let euler_characteristic = n as i64 - facts.edges as i64 + self.triangles.len() as i64;
        let vertex_manifold = !facts.split_vertex;
        let genus = (edge_manifold && vertex_manifold)
            .then(|| self.genus_of(euler_characteristic, boundary_loops));
        Topology {
            edges: facts.edges,
            boundary_loops,
            euler_characteristic,
            genus,
            edge_manifold,
            vertex_manifold,
            oriented: !facts.repeated_directed_edge,
            closed: closed && facts.max_faces == 2,
        }
    }

    /// [`TriMesh::topology`] by sorting the edges (any triangles).
    fn topology_by_edges(&self) -> Topology {
        // The edges go before the vertex fans and the directed sort are built,
        // so no two of the three big arrays are alive at once.
        let (edges, euler_characteristic, edge_manifold, closed, boundary_loops) = {
            let edges = self.edges();
            (
                edges.len(),
                self.euler_from(&edges),
                edges.iter().all(|e| e.faces <= 2),
                !self.triangles.is_empty() && edges.iter().all(|e| e.faces == 2),
                self.loops_of(&edges).len(),
            )
        };
        let vertex_manifold = self.is_vertex_manifold();
        let genus = (edge_manifold && vertex_manifold)
            .then(|| self.genus_of(euler_characteristic, boundary_loops));
        Topology {
            edges,
            boundary_loops,
            euler_characteristic,
            genus,
            edge_manifold,
            vertex_manifold,
            oriented: self.is_consistently_oriented(),
            closed,
        }
    }
}

/// The batches [`TriMesh::topology`] reads the vertex links in (each holds
/// about this fraction of the corners, at 8 bytes a corner, and scans the
/// triangles once).
const LINK_BATCHES: u64 = 4;

/// Connected components of `triangles` over `n` vertices (by shared vertices): the
/// count and a label per vertex, numbered in order of first appearance by vertex
/// index; vertices no triangle uses get `u32::MAX` and are not counted.
///
/// The triangles are united in parallel by a lock-free union–find: a root is
/// linked under the smaller of the two roots, by a compare-exchange that
/// succeeds only while it is still a root, so every parent has a smaller
/// index than its child, no cycle can form, and each component's root ends as
/// its smallest vertex whatever order the unions ran in. Numbering the roots
/// in vertex order then gives the labels of a sequential pass, at any thread
/// count.
pub fn component_labels(n: usize, triangles: &[[u32; 3]]) -> (usize, Vec<u32>) {
    use std::sync::atomic::{AtomicBool, AtomicU32, Ordering::Relaxed};
    // Every value ever stored in `parent[x]` is an ancestor of x (a smaller
    // index in x's component), so a stale read is still a valid step up.
    fn root(parent: &[AtomicU32], mut x: u32) -> u32 {
        loop {
            let p = parent[x as usize].load(Relaxed);
            if p == x {
                return x;
            }
            let g = parent[p as usize].load(Relaxed);
            if g != p {
                // Path halving.
                let _ = parent[x as usize].compare_exchange(p, g, Relaxed, Relaxed);
            }
            x = g;
        }
    }
    fn unite(parent: &[AtomicU32], mut a: u32, mut b: u32) {
        loop {
            (a, b) = (root(parent, a), root(parent, b));
            if a == b {
                return;
            }
            let (lo, hi) = (a.min(b), a.max(b));
            if parent[hi as usize]
                .compare_exchange(hi, lo, Relaxed, Relaxed)
                .is_ok()
            {
                return;
            }
        }
    }
    let parent: Vec<AtomicU32> = (0..n as u32).into_par_iter().map(AtomicU32::new).collect();
    let used: Vec<AtomicBool> = (0..n)
        .into_par_iter()
        .map(|_| AtomicBool::new(false))
        .collect();
    triangles
        .par_iter()
        .with_min_len(1 << 12)
        .for_each(|&[a, b, c]| {
            unite(&parent, a, b);
            unite(&parent, b, c);
            for v in [a, b, c] {
                used[v as usize].store(true, Relaxed);
            }
        });
    let mut labels: Vec<u32> = (0..n as u32)
        .into_par_iter()
        .map(|v| {
            if used[v as usize].load(Relaxed) {
                root(&parent, v)
            } else {
                u32::MAX
            }
        })
        .collect();
    drop((parent, used));
    // A root comes before the rest of its component, so its label is set by
    // the time they read it.
    let mut count = 0u32;
    for v in 0..n {
        let r = labels[v];
        if r == u32::MAX {
            continue;
        }
        labels[v] = if r as usize == v {
            count += 1;
            count - 1
        } else {
            labels[r as usize]
        };
    }
    (count as usize, labels)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The components by breadth-first search over vertex adjacency, numbered
    /// by their smallest vertex: a reference for [`component_labels`].
    fn components_by_search(n: usize, triangles: &[[u32; 3]]) -> (usize, Vec<u32>) {
        let mut adjacent = vec![Vec::new(); n];
        for &[a, b, c] in triangles {
            for (u, v) in [(a, b), (b, c), (c, a)] {
                adjacent[u as usize].push(v);
                adjacent[v as usize].push(u);
            }
        }
        let mut labels = vec![u32::MAX; n];
        let mut count = 0;
        for start in 0..n {
            if labels[start] != u32::MAX || adjacent[start].is_empty() {
                continue;
            }
            labels[start] = count;
            let mut queue = vec![start as u32];
            while let Some(u) = queue.pop() {
                for &v in &adjacent[u as usize] {
                    if labels[v as usize] == u32::MAX {
                        labels[v as usize] = count;
                        queue.push(v);
                    }
                }
            }
            count += 1;
        }
        (count as usize, labels)
    }

    #[test]
    fn components_match_a_search_at_any_thread_count() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for (n, faces, spread) in [
            (10, 3, 10),
            (2000, 900, 40),
            (50_000, 30_000, 8),
            (50_000, 60_000, 50_000),
        ] {
            // Triangles among nearby vertices make many components, chains
            // of them long trees; some vertices stay unused.
            let triangles: Vec<[u32; 3]> = (0..faces)
                .map(|_| {
                    let a = rng.random_range(0..n as u32);
                    let near = |rng: &mut rand_chacha::ChaCha8Rng| {
                        (a + rng.random_range(0..spread)).min(n as u32 - 1)
                    };
                    [a, near(&mut rng), near(&mut rng)]
                })
                .collect();
            let expected = components_by_search(n, &triangles);
            for threads in [1, 2, 7] {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let got = pool.install(|| component_labels(n, &triangles));
                assert_eq!(
                    got, expected,
                    "{n} vertices, {faces} faces, {threads} threads"
                );
            }
        }
    }

    /// The cube [−1, 1]³, 12 outward-facing triangles.
    fn cube() -> TriMesh {
        crate::shapes::cube_cage().triangulate()
    }

    #[test]
    fn cube_is_a_watertight_sphere() {
        let m = cube();
        assert_eq!(m.euler_characteristic(), 2);
        assert!(m.is_watertight());
        assert!(m.boundary_loops().is_empty());
        assert_eq!(m.genus(), Some(0));
        assert!((m.area() - 24.0).abs() < 1e-12);
        assert!((m.signed_volume() - 8.0).abs() < 1e-12);
        for (n, p) in m.vertex_normals().iter().zip(m.positions()) {
            // Corner normals point away from the centre.
            let d: f64 = (0..3).map(|k| n[k] * p[k]).sum();
            assert!(d > 0.0);
        }
    }

    #[test]
    fn open_and_broken_meshes() {
        let m = cube();
        let mut t = m.triangles().to_vec();
        t.pop();
        let open = TriMesh::new(m.positions().to_vec(), t.clone()).unwrap();
        assert!(!open.is_watertight());
        assert_eq!(open.boundary_loops().len(), 1);
        assert_eq!(open.boundary_loops()[0].len(), 3);
        assert_eq!(open.euler_characteristic(), 1);
        // Flipping one face breaks orientation, not closure.
        let mut flipped = m.triangles().to_vec();
        flipped[0].swap(1, 2);
        let f = TriMesh::new(m.positions().to_vec(), flipped).unwrap();
        assert!(!f.is_consistently_oriented() && !f.is_watertight());
        // Three triangles on one edge: not edge-manifold.
        let fin = crate::shapes::fin();
        assert!(!fin.is_edge_manifold());
        assert_eq!(fin.genus(), None);
        // Two triangles touching at one vertex: a bow-tie, not vertex-manifold.
        let bow = TriMesh::new(
            vec![
                [0.0; 3],
                [1.0, 0.0, 0.0],
                [1.0, 1.0, 0.0],
                [-1.0, 0.0, 0.0],
                [-1.0, -1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        )
        .unwrap();
        assert!(bow.is_edge_manifold() && !bow.is_vertex_manifold());
        assert_eq!(bow.n_components(), 1);
    }

    #[test]
    fn construction_is_validated() {
        let err = TriMesh::new(vec![[0.0; 3]; 3], vec![[0, 1, 3]]).unwrap_err();
        assert_eq!(
            err,
            CoreError::IndexOutOfRange {
                face: 0,
                index: 3,
                len: 3
            }
        );
        let err = TriMesh::new(vec![[0.0, f64::NAN, 0.0]], vec![]).unwrap_err();
        assert!(matches!(err, CoreError::NonFinite { index: 0, .. }));
        let m = cube();
        assert!(m.clone().with_colors(vec![[0; 4]; 7]).is_err());
        assert!(m.clone().with_scalar("k", vec![f64::INFINITY; 8]).is_err());
        let m = m
            .with_scalar("k", vec![1.0; 8])
            .unwrap()
            .with_scalar("k", vec![2.0; 8])
            .unwrap();
        assert_eq!(m.scalars().len(), 1);
        assert_eq!(m.scalar("k").unwrap()[0], 2.0);
    }

    #[test]
    fn torus_has_genus_one() {
        // A 6×5 quad torus split into triangles: χ = 0, genus 1.
        let torus = crate::shapes::torus(2.0, 1.0, 6, 5);
        assert_eq!(torus.euler_characteristic(), 0);
        assert!(torus.is_watertight());
        assert_eq!(torus.genus(), Some(1));
        assert!(torus.signed_volume() > 0.0, "outward orientation");
    }

    #[test]
    fn topology_agrees_with_each_question() {
        let cube = cube();
        let mut t = cube.triangles().to_vec();
        t.pop();
        let open = TriMesh::new(cube.positions().to_vec(), t).unwrap();
        let mut flipped = cube.triangles().to_vec();
        flipped[0].swap(1, 2);
        let flipped = TriMesh::new(cube.positions().to_vec(), flipped).unwrap();
        let fin = crate::shapes::fin();
        let torus = crate::shapes::torus(2.0, 1.0, 6, 5);
        let empty = TriMesh::new(vec![[0.0; 3]], vec![]).unwrap();
        // Two cubes sharing one vertex (a vertex with two fans), a triangle
        // repeated with the same winding, and a degenerate triangle.
        let (cp, ct) = (cube.positions().to_vec(), cube.triangles().to_vec());
        let mut pos = cp.clone();
        pos.extend(cp.iter().skip(1).map(|p| [-p[0], -p[1], -p[2]]));
        let mut tri = ct.clone();
        let shift = |v: u32| if v == 0 { 0 } else { v + cp.len() as u32 - 1 };
        tri.extend(ct.iter().map(|t| {
            let mut u = t.map(shift);
            u.swap(1, 2);
            u
        }));
        let bowtie = TriMesh::new(pos, tri).unwrap();
        let mut twice = ct.clone();
        twice.push(ct[0]);
        let twice = TriMesh::new(cp.clone(), twice).unwrap();
        let mut degenerate = ct.clone();
        degenerate.push([0, 0, 1]);
        let degenerate = TriMesh::new(cp, degenerate).unwrap();
        for m in [
            cube, open, flipped, fin, torus, empty, bowtie, twice, degenerate,
        ] {
            let t = m.topology();
            assert_eq!(t, m.topology_by_edges());
            for corners in [1, 7, 40] {
                assert_eq!(
                    m.topology_in_batches(corners),
                    t,
                    "{corners} corners a batch"
                );
            }
            assert_eq!(t.euler_characteristic, m.euler_characteristic());
            assert_eq!(t.genus, m.genus());
            assert_eq!(t.is_manifold(), m.is_manifold());
            assert_eq!(t.is_watertight(), m.is_watertight());
            assert_eq!(t.oriented, m.is_consistently_oriented());
            assert_eq!(t.edges, m.edges().len());
            assert_eq!(t.boundary_loops, m.boundary_loops().len());
        }
    }
}
