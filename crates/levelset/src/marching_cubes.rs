//! Marching cubes on φ = 0 (§6: "the zero level set … is extracted … by the marching
//! cubes method", ref. \[13\], Lorensen & Cline 1987), watertight and edge-manifold.
//!
//! The classic 256-case table is ambiguous on faces whose corners alternate in sign,
//! and two cubes sharing such a face may cut it differently, leaving holes. Here the
//! table is built from face contours, so every decision is a property of the face:
//!
//! * Inside is φ < 0; a node with φ = 0 counts as outside, the same for every cube
//!   (exact zeros are the usual source of open or bubbly meshes).
//! * On each face the contour joins the sign changes of its four edges; on an
//!   ambiguous face the asymptotic decider (Nielson & Hamann 1991) joins the two
//!   negative corners iff the bilinear saddle is negative, i.e. iff the product of
//!   the negative corners' values exceeds that of the positive ones. Both cubes see
//!   the same four values, so they cut the face the same way.
//! * Each face's segments are oriented with the inside on their left seen from
//!   outside the cube; every cut edge then starts one segment and ends another, so
//!   the segments chain into closed loops, each triangulated as a fan. A fan
//!   diagonal joining two vertices of one face could coincide with the neighbour
//!   cube's diagonal; the fan's apex is chosen so that none does, and where no apex
//!   works (a loop through both segments of an ambiguous face) the loop is fanned
//!   around an extra vertex at its centre. Loops in one
//!   cube are disjoint (the interior ambiguity of case 13 is resolved as two
//!   separate sheets), so every mesh edge has exactly two triangles and every
//!   vertex a disc of them: the mesh is closed and manifold wherever φ > 0 on the
//!   grid's boundary.
//!
//! The table (256 cases × the 64 face decisions) is built once, on first use.
//! Vertices are shared between cubes by their grid edge; their positions come from
//! linear interpolation, kept 10⁻³ of a cell away from the nodes so that no two
//! coincide. Normals are ∇φ/|∇φ| (Eq. 1) and the optional mean curvature
//! H = ½∇·(∇φ/|∇φ|) (Eq. 2's κ = 2H), from central differences interpolated along
//! the edge.

use std::sync::OnceLock;

use asperity_core::TriMesh;
use rayon::prelude::*;

use crate::curvature::curvature_from;
use crate::grid::GridSpec;

/// Corner `c` of a cube is at offset (c & 1, c >> 1 & 1, c >> 2).
fn corner_bit(c: usize, axis: usize) -> usize {
    (c >> axis) & 1
}

/// The cube edge joining two corners that differ in one bit: id = axis·4 + the two
/// other bits (lower axis first).
fn edge_of(a: usize, b: usize) -> usize {
    let diff = a ^ b;
    let axis = diff.trailing_zeros() as usize;
    let (u, v) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    axis * 4 + corner_bit(a, u) + 2 * corner_bit(a, v)
}

/// The two corners of cube edge `e` (lower first).
fn edge_corners(e: usize) -> (usize, usize) {
    let axis = e / 4;
    let (u, v) = match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let base = ((e & 1) << u) | (((e >> 1) & 1) << v);
    (base, base | (1 << axis))
}

/// The 6 faces' corners, counter-clockwise seen from outside the cube.
pub(crate) fn face_cycles() -> [[usize; 4]; 6] {
    let mut out = [[0; 4]; 6];
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in 0..2 {
            let at = |a: usize, b: usize| (side << axis) | (a << u) | (b << v);
            // e_u × e_v = e_axis: (0,0),(1,0),(1,1),(0,1) is counter-clockwise about +axis.
            let ccw = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
            out[axis * 2 + side] = if side == 1 {
                ccw
            } else {
                [ccw[0], ccw[3], ccw[2], ccw[1]]
            };
        }
    }
    out
}

/// Triangles (cube edge ids) for a sign case and the face decisions.
pub(crate) struct Table {
    /// Triangles per key: cube edge ids 0..12, or 12 + L for the centre of loop L.
    pub(crate) triangles: Vec<Vec<[u8; 3]>>,
    /// Per key, the loops that are fanned around a centre vertex (their edges).
    pub(crate) centres: Vec<Vec<Vec<u8>>>,
    /// Faces that are ambiguous in each case (bit f).
    ambiguous: [u8; 256],
}

/// Faces (bits) whose corners alternate in sign, per sign case.
fn ambiguous_faces(faces: &[[usize; 4]; 6]) -> [u8; 256] {
    let mut ambiguous = [0u8; 256];
    for (case, amb) in ambiguous.iter_mut().enumerate() {
        for (f, cyc) in faces.iter().enumerate() {
            let neg = cyc.map(|c| case >> c & 1 == 1);
            if neg[0] == neg[2] && neg[1] == neg[3] && neg[0] != neg[1] {
                *amb |= 1 << f;
            }
        }
    }
    ambiguous
}

/// The contour segments of every face for a sign case and face decisions, as
/// `next[edge]`: the cut edge each segment leads to from its start (inside on
/// the left seen from outside); `u8::MAX` for uncut edges.
fn face_segments(faces: &[[usize; 4]; 6], case: usize, decisions: usize) -> [u8; 12] {
    let mut next = [u8::MAX; 12];
    for (f, cyc) in faces.iter().enumerate() {
        let neg = cyc.map(|c| case >> c & 1 == 1);
        // Crossings in cyclic order: (edge, is_out).
        let mut xs = Vec::with_capacity(4);
        for s in 0..4 {
            let (a, b) = (cyc[s], cyc[(s + 1) % 4]);
            if neg[s] != neg[(s + 1) % 4] {
                xs.push((edge_of(a, b), neg[s]));
            }
        }
        match xs.len() {
            0 => {}
            2 => {
                let (o, i) = if xs[0].1 {
                    (xs[0].0, xs[1].0)
                } else {
                    (xs[1].0, xs[0].0)
                };
                next[o] = i as u8;
            }
            4 => {
                let connected = decisions >> f & 1 == 1;
                for s in 0..4 {
                    if xs[s].1 {
                        let i = if connected {
                            xs[(s + 1) % 4].0
                        } else {
                            xs[(s + 3) % 4].0
                        };
                        next[xs[s].0] = i as u8;
                    }
                }
            }
            _ => unreachable!("a face has 0, 2 or 4 sign changes"),
        }
    }
    next
}

/// Triangles of one loop of cut edges, added to `tris`: a fan from an apex
/// with no diagonal along a face (it could be the neighbour cube's diagonal
/// too, an edge with four triangles), or around a centre vertex (loop number
/// `centres.len()`, recorded in `centres`).
fn fan(lp: &[u8], edge_faces: &[u8; 12], tris: &mut Vec<[u8; 3]>, centres: &mut Vec<Vec<u8>>) {
    let m = lp.len();
    let apex = (0..m).find(|&a| {
        (2..m - 1).all(|off| {
            let b = (a + off) % m;
            edge_faces[lp[a] as usize] & edge_faces[lp[b] as usize] == 0
        })
    });
    match apex {
        Some(a) => {
            for w in 1..m - 1 {
                let (x, y) = (lp[(a + w) % m], lp[(a + w + 1) % m]);
                tris.push([lp[a], y, x]);
            }
        }
        None => {
            let centre = 12 + centres.len() as u8;
            for w in 0..m {
                tris.push([centre, lp[(w + 1) % m], lp[w]]);
            }
            centres.push(lp.to_vec());
        }
    }
}

/// The segments chained into loops, each triangulated: (triangles, the loops
/// fanned around a centre).
fn triangulate_loops(next: &[u8; 12], edge_faces: &[u8; 12]) -> (Vec<[u8; 3]>, Vec<Vec<u8>>) {
    let mut seen = [false; 12];
    let mut tris = Vec::new();
    let mut loop_centres = Vec::new();
    for start in 0..12 {
        if next[start] == u8::MAX || seen[start] {
            continue;
        }
        let mut lp = Vec::new();
        let mut e = start;
        while !seen[e] {
            seen[e] = true;
            lp.push(e as u8);
            e = next[e] as usize;
        }
        fan(&lp, edge_faces, &mut tris, &mut loop_centres);
    }
    (tris, loop_centres)
}

fn build_table() -> Table {
    let faces = face_cycles();
    let ambiguous = ambiguous_faces(&faces);
    let mut triangles = vec![Vec::new(); 256 * 64];
    let mut centres = vec![Vec::new(); 256 * 64];
    // Faces (bits) that each cube edge lies on.
    let mut edge_faces = [0u8; 12];
    for (f, cyc) in faces.iter().enumerate() {
        for s in 0..4 {
            edge_faces[edge_of(cyc[s], cyc[(s + 1) % 4])] |= 1 << f;
        }
    }
    for case in 1..255usize {
        for decisions in 0..64usize {
            if decisions & !(ambiguous[case] as usize) != 0 {
                continue;
            }
            let next = face_segments(&faces, case, decisions);
            let (tris, loop_centres) = triangulate_loops(&next, &edge_faces);
            triangles[case | decisions << 8] = tris;
            centres[case | decisions << 8] = loop_centres;
        }
    }
    Table {
        triangles,
        centres,
        ambiguous,
    }
}

pub(crate) fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(build_table)
}

/// Vertex keys with this bit are loop centres: (cube base node << 2) | loop.
pub(crate) const CENTRE: u64 = 1 << 63;

/// Options for [`extract`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ExtractOptions {
    /// Add the per-vertex attribute `mean_curvature` (H = ½κ of Eq. 2).
    pub curvature: bool,
    /// Drop connected components with fewer triangles than this.
    pub min_shell_triangles: usize,
}

/// What [`extract`] dropped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExtractStats {
    /// Components found before shell removal.
    pub components: usize,
    /// Components removed as too small.
    pub shells_removed: usize,
}

/// A vertex's position, normal (not yet unit) and mean curvature.
pub(crate) type Vertex = ([f64; 3], [f64; 3], f64);

/// φ on a grid, read node by node: the dense array or the sparse bricks.
pub(crate) trait Volume: Sync {
    /// The grid.
    fn grid(&self) -> &GridSpec;
    /// φ at node `c`.
    fn at(&self, c: [usize; 3]) -> f32;
}

/// A dense φ array as a [`Volume`].
struct Dense<'a> {
    phi: &'a [f32],
    grid: &'a GridSpec,
}

impl Volume for Dense<'_> {
    fn grid(&self) -> &GridSpec {
        self.grid
    }

    #[inline]
    fn at(&self, c: [usize; 3]) -> f32 {
        self.phi[self.grid.index(c[0], c[1], c[2])]
    }
}

/// The table key (case | face decisions << 8) of a cube with corner values
/// `v` (corner c at offset (c & 1, c >> 1 & 1, c >> 2)).
#[inline]
pub(crate) fn cube_key_of(tab: &Table, faces: &[[usize; 4]; 6], v: [f32; 8]) -> usize {
    let mut case = 0usize;
    for (c, x) in v.iter().enumerate() {
        if *x < 0.0 {
            case |= 1 << c;
        }
    }
    let mut decisions = 0usize;
    let amb = tab.ambiguous[case];
    if amb != 0 {
        for (f, cyc) in faces.iter().enumerate() {
            if amb >> f & 1 == 1 {
                let w = cyc.map(|c| f64::from(v[c]));
                // Negative pair product vs positive pair product.
                let (neg, pos) = if w[0] < 0.0 {
                    (w[0] * w[2], w[1] * w[3])
                } else {
                    (w[1] * w[3], w[0] * w[2])
                };
                if neg > pos {
                    decisions |= 1 << f;
                }
            }
        }
    }
    case | decisions << 8
}

/// The cubes of a grid with its φ: table keys, triangles and vertices.
pub(crate) struct Cubes<'a, P: Volume> {
    volume: &'a P,
    grid: GridSpec,
    pub(crate) tab: &'static Table,
    pub(crate) faces: [[usize; 4]; 6],
    corner_offset: [usize; 8],
}

impl<'a, P: Volume> Cubes<'a, P> {
    pub(crate) fn new(volume: &'a P) -> Self {
        let grid = *volume.grid();
        let strides = grid.strides();
        let corner_offset: [usize; 8] = std::array::from_fn(|c| {
            corner_bit(c, 0) * strides[0]
                + corner_bit(c, 1) * strides[1]
                + corner_bit(c, 2) * strides[2]
        });
        Self {
            volume,
            grid,
            tab: table(),
            faces: face_cycles(),
            corner_offset,
        }
    }

    /// The key of cube edge `e` of the cube at dense index `base`: its lower
    /// node × 3 + axis.
    #[inline]
    pub(crate) fn edge_key(&self, base: usize, e: usize) -> u64 {
        let (a, _) = edge_corners(e);
        ((base + self.corner_offset[a]) as u64) * 3 + (e / 4) as u64
    }

    /// The vertex keys of the triangles of the cube at dense index `base`
    /// with table key `key`, appended to `out`.
    #[inline]
    pub(crate) fn triangles(&self, base: usize, key: usize, out: &mut Vec<[u64; 3]>) {
        for t in &self.tab.triangles[key] {
            out.push(t.map(|e| {
                if e < 12 {
                    self.edge_key(base, e as usize)
                } else {
                    CENTRE | ((base as u64) << 2) | u64::from(e - 12)
                }
            }));
        }
    }

    /// The table key of the cube whose lowest corner is node `c`.
    fn cube_key_at(&self, c: [usize; 3]) -> usize {
        let v: [f32; 8] = std::array::from_fn(|k| {
            self.volume.at([
                c[0] + corner_bit(k, 0),
                c[1] + corner_bit(k, 1),
                c[2] + corner_bit(k, 2),
            ])
        });
        cube_key_of(self.tab, &self.faces, v)
    }

    /// ∇φ at node `c` by central differences (one-sided at the grid's faces).
    fn gradient(&self, c: [usize; 3]) -> [f64; 3] {
        let grid = &self.grid;
        std::array::from_fn(|a| {
            let (mut lo, mut hi) = (c, c);
            if c[a] > 0 {
                lo[a] -= 1;
            }
            if c[a] + 1 < grid.dims[a] {
                hi[a] += 1;
            }
            let span = hi[a] - lo[a];
            (f64::from(self.volume.at(hi)) - f64::from(self.volume.at(lo)))
                / (span.max(1) as f64 * grid.spacing)
        })
    }

    /// H = ½κ (Eq. 2) at node `c`; 0 on the grid's faces.
    fn mean_curvature(&self, c: [usize; 3]) -> f64 {
        if (0..3).any(|a| c[a] == 0 || c[a] + 1 >= self.grid.dims[a]) {
            return 0.0;
        }
        let at = |o: [isize; 3]| {
            f64::from(
                self.volume
                    .at(std::array::from_fn(|a| c[a].wrapping_add_signed(o[a]))),
            )
        };
        0.5 * curvature_from(at, self.grid.spacing).0
    }

    /// Position, normal and (with `curvature`) mean curvature of the vertex
    /// on grid edge `key`.
    fn edge_vertex(&self, key: u64, curvature: bool) -> Vertex {
        let u = (key / 3) as usize;
        let axis = (key % 3) as usize;
        let c = self.grid.coords(u);
        let mut cv = c;
        cv[axis] += 1;
        let (a, b) = (f64::from(self.volume.at(c)), f64::from(self.volume.at(cv)));
        let t = (a / (a - b)).clamp(1e-3, 1.0 - 1e-3);
        let mut p = self.grid.position(c[0], c[1], c[2]);
        p[axis] += t * self.grid.spacing;
        let (ga, gb) = (self.gradient(c), self.gradient(cv));
        let n: [f64; 3] = std::array::from_fn(|x| ga[x] + t * (gb[x] - ga[x]));
        let h = if curvature {
            let (ka, kb) = (self.mean_curvature(c), self.mean_curvature(cv));
            ka + t * (kb - ka)
        } else {
            0.0
        };
        (p, n, h)
    }

    /// The vertex of `key`: on a grid edge, or the centre of a loop (the mean of
    /// its loop's vertices); the normal unit; the mean curvature with
    /// `curvature` (else 0).
    pub(crate) fn vertex(&self, key: u64, curvature: bool) -> Vertex {
        if key & CENTRE == 0 {
            let (p, n, h) = self.edge_vertex(key, curvature);
            return (p, unit(n), h);
        }
        let base = ((key & !CENTRE) >> 2) as usize;
        let lp = &self.tab.centres[self.cube_key_at(self.grid.coords(base))][(key & 3) as usize];
        let mut sum = ([0.0; 3], [0.0; 3], 0.0);
        for &e in lp {
            let (p, n, h) = self.edge_vertex(self.edge_key(base, e as usize), curvature);
            let n = unit(n);
            for x in 0..3 {
                sum.0[x] += p[x];
                sum.1[x] += n[x];
            }
            sum.2 += h;
        }
        let m = lp.len() as f64;
        (sum.0.map(|x| x / m), unit(sum.1), sum.2 / m)
    }
}

impl Cubes<'_, Dense<'_>> {
    /// Whether the row of cubes (·, j, k) can hold the surface. Most rows lie
    /// wholly inside or outside (φ is clamped to ±γ away from the front): one
    /// branch-free pass over their four rows of nodes skips them.
    fn row_is_cut(&self, j: usize, k: usize) -> bool {
        let nx = self.grid.dims[0];
        let phi = self.volume.phi;
        let row = |dj: usize, dk: usize| {
            let start = self.grid.index(0, j + dj, k + dk);
            &phi[start..start + nx]
        };
        let (any, all) = [row(0, 0), row(1, 0), row(0, 1), row(1, 1)]
            .iter()
            .flat_map(|r| r.iter())
            .fold((false, true), |(any, all), &x| {
                let inside = x < 0.0;
                (any | inside, all & inside)
            });
        any && !all
    }

    /// Triangles of the slab of cubes between node planes k and k + 1, as
    /// vertex keys (grid edges, or loop centres with the top bit set).
    fn slab(&self, k: usize) -> Vec<[u64; 3]> {
        let [nx, ny, _] = self.grid.dims;
        let phi = self.volume.phi;
        let mut out = Vec::new();
        for j in 0..ny - 1 {
            if !self.row_is_cut(j, k) {
                continue;
            }
            for i in 0..nx - 1 {
                let base = self.grid.index(i, j, k);
                let v: [f32; 8] = std::array::from_fn(|c| phi[base + self.corner_offset[c]]);
                let key = cube_key_of(self.tab, &self.faces, v);
                let case = key & 255;
                if case == 0 || case == 255 {
                    continue;
                }
                self.triangles(base, key, &mut out);
            }
        }
        out
    }
}

/// g/|g|, or +z where that is not finite.
fn unit(g: [f64; 3]) -> [f64; 3] {
    let len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let n = g.map(|x| x / len);
    if len > 0.0 && n.iter().all(|x| x.is_finite()) {
        n
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// The triangle mesh of {φ = 0} on `grid` (φ < 0 inside; x fastest).
///
/// # Panics
/// If `phi` does not have one value per node.
pub fn extract(phi: &[f32], grid: &GridSpec, options: &ExtractOptions) -> (TriMesh, ExtractStats) {
    assert_eq!(phi.len(), grid.len(), "one φ value per node");
    let volume = Dense { phi, grid };
    let cubes = Cubes::new(&volume);
    // Slab by slab, so the order does not depend on the thread count.
    let slabs: Vec<Vec<[u64; 3]>> = (0..grid.dims[2].saturating_sub(1))
        .into_par_iter()
        .map(|k| cubes.slab(k))
        .collect();
    assemble(&cubes, slabs.concat(), options)
}

/// The mesh of the triangles `keyed` (vertex keys, in the dense cube order)
/// with vertices from `cubes`, small shells dropped.
pub(crate) fn assemble<P: Volume>(
    cubes: &Cubes<P>,
    keyed: Vec<[u64; 3]>,
    options: &ExtractOptions,
) -> (TriMesh, ExtractStats) {
    let mut keys: Vec<u64> = keyed.iter().flatten().copied().collect();
    keys.par_sort_unstable();
    keys.dedup();
    keys.shrink_to_fit();
    let triangles = index_triangles(&cubes.grid, &keyed, &keys);
    drop(keyed);
    assemble_indexed(cubes, triangles, keys, options)
}

/// The mesh of `triangles` (indices into `keys`, the vertex keys in
/// increasing order) with vertices from `cubes`, small shells dropped.
pub(crate) fn assemble_indexed<P: Volume>(
    cubes: &Cubes<P>,
    triangles: Vec<[u32; 3]>,
    keys: Vec<u64>,
    options: &ExtractOptions,
) -> (TriMesh, ExtractStats) {
    let mut vertices = Vertices::with_capacity(keys.len(), options.curvature);
    vertices.extend(cubes, &keys);
    drop(keys);
    vertices.into_mesh(triangles, options)
}

/// A mesh's vertex data as it is made: positions, normals and, if asked, the
/// mean curvature.
pub(crate) struct Vertices {
    positions: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    curvature: Option<Vec<f64>>,
}

impl Vertices {
    /// Room for `n` vertices; with the curvature when `curvature`.
    pub(crate) fn with_capacity(n: usize, curvature: bool) -> Self {
        Self {
            positions: Vec::with_capacity(n),
            normals: Vec::with_capacity(n),
            curvature: curvature.then(|| Vec::with_capacity(n)),
        }
    }

    /// Appends the vertices of `keys`, in their order. A caller holding its
    /// keys in parts frees each part once it is read.
    pub(crate) fn extend<P: Volume>(&mut self, cubes: &Cubes<P>, keys: &[u64]) {
        let with_curvature = self.curvature.is_some();
        let made = keys
            .par_iter()
            .map(|&key| cubes.vertex(key, with_curvature));
        // Straight into the arrays (rayon unzips an indexed iterator in place).
        let mut arrays = (
            std::mem::take(&mut self.positions),
            std::mem::take(&mut self.normals),
        );
        match &mut self.curvature {
            None => arrays.par_extend(made.map(|(p, n, _)| (p, n))),
            Some(h) => {
                let mut all = (arrays, std::mem::take(h));
                all.par_extend(made.map(|(p, n, k)| ((p, n), k)));
                (arrays, *h) = all;
            }
        }
        (self.positions, self.normals) = arrays;
    }

    /// The mesh of `triangles` (indices into these vertices), small shells
    /// dropped.
    pub(crate) fn into_mesh(
        self,
        mut triangles: Vec<[u32; 3]>,
        options: &ExtractOptions,
    ) -> (TriMesh, ExtractStats) {
        let Self {
            mut positions,
            mut normals,
            mut curvature,
        } = self;
        let stats = drop_shells(
            (&mut positions, &mut normals, &mut curvature),
            &mut triangles,
            options.min_shell_triangles,
        );
        let mut mesh = TriMesh::new(positions, triangles)
            .expect("marching cubes builds valid indices")
            .with_normals(normals)
            .expect("one normal per vertex");
        if let Some(h) = curvature {
            mesh = mesh
                .with_scalar("mean_curvature", h)
                .expect("one value per vertex");
        }
        (mesh, stats)
    }
}

/// The triangles as indices into `keys` (sorted: grid-edge keys by their
/// node's dense index, then loop centres). Each edge key is looked up among
/// the keys of its own row of nodes, found from a table of row starts.
fn index_triangles(grid: &GridSpec, keyed: &[[u64; 3]], keys: &[u64]) -> Vec<[u32; 3]> {
    let [nx, ny, nz] = grid.dims;
    let row_key = |row: usize| (row * nx) as u64 * 3;
    let edges = keys.partition_point(|&k| k & CENTRE == 0);
    let (edge_keys, centres) = keys.split_at(edges);
    let starts: Vec<u32> = (0..=ny * nz)
        .into_par_iter()
        .map(|row| edge_keys.partition_point(|&k| k < row_key(row)) as u32)
        .collect();
    keyed
        .par_iter()
        .map(|t| {
            t.map(|k| {
                if k & CENTRE != 0 {
                    let at = centres.binary_search(&k).expect("a loop centre's key");
                    return (edges + at) as u32;
                }
                let row = (k / 3) as usize / nx;
                let (lo, hi) = (starts[row] as usize, starts[row + 1] as usize);
                let at = edge_keys[lo..hi].binary_search(&k).expect("a vertex key");
                (lo + at) as u32
            })
        })
        .collect()
}

/// Drops the entries of `v` that `keep` refuses, in place (a copy of the
/// vertex arrays would be the extraction's largest allocation).
fn retain_indexed<T: Copy>(v: &mut Vec<T>, keep: impl Fn(usize) -> bool) {
    let mut w = 0;
    for i in 0..v.len() {
        if keep(i) {
            v[w] = v[i];
            w += 1;
        }
    }
    v.truncate(w);
}

/// A mesh's vertex data: positions, normals and (optionally) curvature.
type VertexData<'a> = (
    &'a mut Vec<[f64; 3]>,
    &'a mut Vec<[f64; 3]>,
    &'a mut Option<Vec<f64>>,
);

/// Drops connected components of fewer than `min` triangles (with their
/// vertices); returns the component count and how many were dropped.
fn drop_shells(
    (positions, normals, curvature): VertexData,
    triangles: &mut Vec<[u32; 3]>,
    min: usize,
) -> ExtractStats {
    let n = positions.len();
    let (components, labels) = asperity_core::tri_mesh::component_labels(n, triangles);
    let mut stats = ExtractStats {
        components,
        shells_removed: 0,
    };
    if min == 0 || components == 0 {
        return stats;
    }
    let mut size = vec![0usize; components];
    for t in triangles.iter() {
        size[labels[t[0] as usize] as usize] += 1;
    }
    let keep_comp: Vec<bool> = size.iter().map(|&s| s >= min).collect();
    stats.shells_removed = keep_comp.iter().filter(|k| !**k).count();
    if stats.shells_removed > 0 {
        triangles.retain(|t| keep_comp[labels[t[0] as usize] as usize]);
        let mut remap = vec![u32::MAX; n];
        let mut next = 0u32;
        for (i, r) in remap.iter_mut().enumerate() {
            if keep_comp[labels[i] as usize] {
                *r = next;
                next += 1;
            }
        }
        let keep = |i: usize| remap[i] != u32::MAX;
        retain_indexed(positions, keep);
        retain_indexed(normals, keep);
        if let Some(h) = curvature.as_mut() {
            retain_indexed(h, keep);
        }
        for t in triangles.iter_mut() {
            *t = t.map(|v| remap[v as usize]);
        }
    }
    stats
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::MemoryBudget;
    use proptest::prelude::*;

    use crate::grid::Sizing;

    fn grid(n: usize, lo: f64, hi: f64) -> GridSpec {
        GridSpec::around(
            &[[lo; 3], [hi; 3]],
            Sizing::Resolution(n),
            |_| 2,
            &MemoryBudget::unlimited(),
        )
        .unwrap()
    }

    #[test]
    fn every_case_closes_into_loops_with_consistent_edges() {
        let tab = table();
        for case in 1..255usize {
            // A case's triangles use exactly the cut edges.
            let cut: Vec<usize> = (0..12)
                .filter(|&e| {
                    let (a, b) = edge_corners(e);
                    (case >> a & 1) != (case >> b & 1)
                })
                .collect();
            let tris = &tab.triangles[case];
            let mut used: Vec<usize> = tris.iter().flatten().map(|&e| e as usize).collect();
            used.sort_unstable();
            used.dedup();
            assert_eq!(used, cut, "case {case}");
        }
    }

    #[test]
    fn sphere_is_closed_oriented_outward_and_has_the_right_curvature() {
        let g = grid(40, -1.0, 1.0);
        let r = 0.7;
        let phi = g.sample(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - r);
        let (mesh, stats) = extract(
            &phi,
            &g,
            &ExtractOptions {
                curvature: true,
                min_shell_triangles: 0,
            },
        );
        assert_eq!(stats.components, 1);
        assert!(mesh.is_watertight() && mesh.is_manifold());
        assert!(mesh.is_consistently_oriented());
        assert_eq!(mesh.euler_characteristic(), 2);
        // Outward: positive enclosed volume close to the ball's.
        let vol = mesh.signed_volume();
        let exact = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        assert!((vol - exact).abs() < 0.02 * exact, "{vol} vs {exact}");
        for (p, n) in mesh.positions().iter().zip(mesh.normals().unwrap()) {
            let len = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((len - r).abs() < 0.01, "vertex off the sphere: {len}");
            let dot = (p[0] * n[0] + p[1] * n[1] + p[2] * n[2]) / len;
            assert!(dot > 0.99, "normal not radial: {dot}");
        }
        let h = mesh.scalar("mean_curvature").unwrap();
        let mean = h.iter().sum::<f64>() / h.len() as f64;
        assert!(
            (mean - 1.0 / r).abs() < 0.03 / r,
            "mean curvature {mean} vs {}",
            1.0 / r
        );
    }

    #[test]
    fn torus_has_genus_one_and_small_shells_can_be_dropped() {
        let g = grid(48, -1.2, 1.2);
        let (big, small) = (0.7, 0.25);
        let torus = |p: [f64; 3]| {
            let q = (p[0] * p[0] + p[1] * p[1]).sqrt() - big;
            (q * q + p[2] * p[2]).sqrt() - small
        };
        let blob = |p: [f64; 3]| {
            ((p[0] - 1.0).powi(2) + (p[1] - 1.0).powi(2) + (p[2] - 1.0).powi(2)).sqrt() - 0.08
        };
        let phi = g.sample(|p| torus(p).min(blob(p)));
        let (mesh, stats) = extract(&phi, &g, &ExtractOptions::default());
        assert_eq!(stats.components, 2);
        assert_eq!(mesh.euler_characteristic(), 2); // torus 0 + sphere 2
        let (clean, stats) = extract(
            &phi,
            &g,
            &ExtractOptions {
                curvature: false,
                min_shell_triangles: 200,
            },
        );
        assert_eq!(stats.shells_removed, 1);
        assert!(clean.is_watertight() && clean.is_manifold());
        assert_eq!(clean.genus(), Some(1));
    }

    #[test]
    fn exact_zeros_count_as_outside() {
        let g = grid(8, 0.0, 8.0);
        // A slab |z − z0| ≤ … with φ exactly 0 on whole node layers.
        let z0 = g.position(0, 0, 6)[2];
        let phi = g.sample(|p| ((p[2] - z0).abs() - 2.0 * g.spacing).max(-10.0));
        assert!(phi.contains(&0.0));
        let (mesh, _) = extract(&phi, &g, &ExtractOptions::default());
        assert!(mesh.n_faces() > 0);
        assert!(mesh.is_manifold());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]
        /// Random fields (with exact zeros and ambiguous faces everywhere) give closed
        /// edge-manifold meshes when the boundary is outside.
        #[test]
        fn random_fields_give_closed_manifold_meshes(values in prop::collection::vec(-3i8..=3, 7 * 7 * 7), scale in 0.1f32..2.0) {
            let g = GridSpec { origin: [0.0; 3], spacing: 1.0, dims: [9, 9, 9] };
            let mut phi = vec![1.0f32; g.len()];
            let mut it = values.iter();
            for k in 1..8 {
                for j in 1..8 {
                    for i in 1..8 {
                        phi[g.index(i, j, k)] = f32::from(*it.next().unwrap()) * scale;
                    }
                }
            }
            let (mesh, _) = extract(&phi, &g, &ExtractOptions::default());
            prop_assert!(mesh.boundary_edges().is_empty(), "open mesh");
            prop_assert!(mesh.is_edge_manifold(), "non-manifold edge");
            prop_assert!(mesh.is_vertex_manifold(), "non-manifold vertex");
            prop_assert!(mesh.is_consistently_oriented());
        }
    }
}
