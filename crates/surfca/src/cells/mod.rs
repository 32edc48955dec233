//! Per-triangle cell grids and their communication across edges and vertices
//! (gobron-chiba, "Triangle Division and Cell Properties" and "Data Communication
//! in CA").
//!
//! **Division.** Each input triangle ABC is laid in its own plane frame — A at the
//! origin, AB along the x axis, C above it (the paper puts B on an axis and C on
//! the other; any such frame is equivalent) — and covered by square cells of one
//! size h. A cell is *active* when it overlaps the triangle with positive area,
//! otherwise it is an OUT-CELL and does not exist; an active cell is COMP-IN when
//! its centre is inside the triangle and PART-IN otherwise (Figure 3). The cell's
//! part inside the triangle is kept as a polygon (the triangle clipped by the
//! square): the polygons of a triangle's cells tile it exactly, so cell areas sum
//! to the mesh area and the cells can be drawn without gaps.
//!
//! **Neighbourhood.** Inside a triangle a cell has its 8 surrounding cells (4 sides,
//! 4 corners). Where a neighbour position falls outside the triangle:
//! - *across an edge*: the neighbour triangle is unfolded about the shared edge
//!   and the position is mapped to the cell of the neighbour's grid that contains
//!   it (or the nearest active one) — the paper's pairing of edge cells with the
//!   nearest cell of the opposite grid along the oriented shared edge (Figure 7),
//!   computed once;
//! - *beyond a vertex* (outside two edges): the nearest cell, in 3-D, among the
//!   cells near that vertex in the other triangles around it, so information
//!   crosses every vertex;
//! - on a boundary edge there is no neighbour.
//!
//! **Redundancy.** When the two grids are rotated against each other several cells
//! map to one cell across the edge (the paper estimates 1 − cos x for grids x
//! apart, 1 − 2√2/π ≈ 9.9 % on average over random orientations, Figure 8). Two
//! measures are kept:
//! - [`CellStats::paper_redundancy`], the paper's: edge cells paired by their
//!   projections on the shared edge (the `pairing` module), second receptions
//!   counted. On the paper's set-up ([`figure8`]) it averages 10.5 %, within 1
//!   point of 9.9 %, and follows 1 − cos x (least-squares slope 1.01; at every angle the mean over eight grid
//!   placements is within 1.6 points); the test `pairing_redundancy_against_the_papers_estimate` measures it.
//! - [`CellStats::pairing_redundancy`], of the links actually made: the share of
//!   side links across edges (per source triangle and direction) that land on a
//!   cell another such link already reaches. With the default
//!   [`Pairing::Unfolded`] it averages 2.4 % (at most 4.2 %), a quarter of the
//!   estimate, because these links map each side neighbour's unfolded position to
//!   the cell containing it (2-D, nearly one-to-one) rather than pairing edge cells
//!   by their projections on the edge (1-D, many-to-one where the grids' densities
//!   along the edge differ). [`Pairing::Paper`] links by the paper's projection
//!   instead (`--pairing paper`).
//!
//! # Deviations from the paper
//!
//! **Symmetric links.** Links are made symmetric (if a sees b, b sees a), so
//! conservative rules stay conservative: every exchange has two ends. The paper
//! transfers edge data at the end of each step instead; the symmetric graph gives
//! the same reach without the duplicated cells.

use asperity_core::vec3::{cross, dot, norm, scale, sub};
use asperity_core::{CoreError, MemoryBudget, TriMesh};

mod links;
mod pairing;

use links::*;
use pairing::*;
pub use pairing::{FIGURE8_CELLS, Figure8Point, Pairing, figure8};

/// Where a cell lies relative to its triangle (Figure 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InFlag {
    /// Centre inside the triangle.
    CompIn,
    /// Overlaps the triangle, centre outside.
    PartIn,
}

/// How the cell size is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CellSize {
    /// Side h in mesh units.
    Size(f64),
    /// About this many cells, border cells included: h solves A/h² + 0.64·P/h = n
    /// (A the area, P the summed triangle perimeters).
    Count(usize),
}

/// Neighbour directions in a cell's own grid: sides first, then corners.
pub const DIRECTIONS: [(i32, i32); 8] = [
    (1, 0),
    (0, 1),
    (-1, 0),
    (0, -1),
    (1, 1),
    (-1, 1),
    (-1, -1),
    (1, -1),
];

/// Whether direction `k` is a side (`k < 4`) or a corner.
pub fn is_side(k: u8) -> bool {
    k < 4
}

/// The opposite direction.
pub fn opposite(k: u8) -> u8 {
    if k < 4 {
        (k + 2) % 4
    } else {
        4 + (k - 4 + 2) % 4
    }
}

/// One triangle's cell grid: square (i, j) spans x ∈ [x0 + i·h, x0 + (i+1)·h],
/// y ∈ [j·h, (j+1)·h] in the triangle's plane frame, where its corners are `local`.
#[derive(Clone, Debug, PartialEq)]
pub struct TriangleGrid {
    /// Left edge of the grid.
    pub x0: f64,
    /// Squares along x.
    pub nx: usize,
    /// Squares along y.
    pub ny: usize,
    /// Corners A, B, C in the frame (A at the origin, B on the x axis).
    pub local: [[f64; 2]; 3],
}

/// Counts and measurements of a cell structure.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct CellStats {
    /// Active cells.
    pub cells: usize,
    /// COMP-IN cells.
    pub comp_in: usize,
    /// PART-IN cells.
    pub part_in: usize,
    /// Grid squares of the triangles' bounding boxes that are OUT-CELLs.
    pub out_cells: usize,
    /// Cell side h.
    pub cell_size: f64,
    /// Shortest triangle edge (h above it gives the paper's Figure 9 failure).
    pub shortest_edge: f64,
    /// Directed links created across edges.
    pub edge_links: usize,
    /// Directed links created around vertices.
    pub vertex_links: usize,
    /// Share of side links across edges (one direction, one source triangle) that
    /// land on a cell another such link already reaches: the cell receives the same
    /// edge data twice (≈ 2.4 % with [`Pairing::Unfolded`] on the paper's set-up,
    /// 5.9 % (at most 12.5 %) with [`Pairing::Paper`]; 0 for grids on one lattice).
    pub pairing_redundancy: f64,
    /// The paper's Figure 8 measure on the same grids: the share of edge cells'
    /// sends, across every interior edge in the direction with more edge cells,
    /// that reach a cell another send already reaches, with the edge cells paired
    /// by their projections on the edge (see the `pairing` module: 1 − cos x for
    /// grids x apart, ≈ 9.9 % over random orientations).
    pub paper_redundancy: f64,
    /// How the cells were linked across edges.
    pub pairing: Pairing,
    /// Human-readable warnings (cell size versus edges, boundaries).
    pub warnings: Vec<String>,
}

/// The cell structure of a mesh.
#[derive(Clone, Debug)]
pub struct Cells {
    /// Cell side.
    pub h: f64,
    /// Owning triangle per cell.
    pub triangle: Vec<u32>,
    /// Grid position (i, j) in the owning triangle's grid.
    pub ij: Vec<[u32; 2]>,
    /// Centroid of the cell's part of the triangle (3-D).
    pub centre: Vec<[f64; 3]>,
    /// Area of the cell's part of the triangle.
    pub area: Vec<f64>,
    /// COMP-IN or PART-IN.
    pub flag: Vec<InFlag>,
    /// Unit normal of the owning triangle, per triangle.
    pub triangle_normal: Vec<[f64; 3]>,
    /// Sum of the cell areas (the mesh area up to rounding).
    pub total_area: f64,
    /// Each triangle's grid in its plane frame.
    pub grids: Vec<TriangleGrid>,
    pub(crate) frames: Vec<Frame>,
    pub(crate) edge_map: std::collections::HashMap<(u32, u32), Vec<(u32, usize)>>,
    poly_offsets: Vec<u32>,
    poly_points: Vec<[f64; 3]>,
    nbr_offsets: Vec<u32>,
    nbr: Vec<u32>,
    nbr_dir: Vec<u8>,
    /// Measurements.
    pub stats: CellStats,
}

impl Cells {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.area.len()
    }

    /// Whether there are no cells.
    pub fn is_empty(&self) -> bool {
        self.area.is_empty()
    }

    /// The neighbours of cell `c` with their directions in `c`'s grid.
    pub fn neighbours(&self, c: usize) -> impl Iterator<Item = (usize, u8)> + '_ {
        let (a, b) = (
            self.nbr_offsets[c] as usize,
            self.nbr_offsets[c + 1] as usize,
        );
        self.nbr[a..b]
            .iter()
            .zip(&self.nbr_dir[a..b])
            .map(|(&n, &d)| (n as usize, d))
    }

    /// The cell's part of its triangle as a convex polygon (3-D, counter-clockwise
    /// seen from the triangle's normal).
    pub fn polygon(&self, c: usize) -> &[[f64; 3]] {
        &self.poly_points[self.poly_offsets[c] as usize..self.poly_offsets[c + 1] as usize]
    }
}

type V2 = [f64; 2];

/// A triangle's plane frame and grid.
#[derive(Clone, Debug)]
pub(crate) struct Frame {
    pub(crate) verts: [u32; 3],
    pub(crate) origin: [f64; 3],
    pub(crate) e1: [f64; 3],
    pub(crate) e2: [f64; 3],
    /// Local corners A, B, C.
    pub(crate) local: [V2; 3],
    pub(crate) x0: f64,
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    /// Global cell id per grid square, or u32::MAX (OUT-CELL).
    pub(crate) lookup: Vec<u32>,
}

impl Frame {
    pub(crate) fn to_local(&self, p: [f64; 3]) -> V2 {
        let d = sub(p, self.origin);
        [dot(d, self.e1), dot(d, self.e2)]
    }
    fn to_world(&self, q: V2) -> [f64; 3] {
        std::array::from_fn(|k| self.origin[k] + q[0] * self.e1[k] + q[1] * self.e2[k])
    }
    pub(crate) fn cell_at(&self, q: V2, h: f64) -> Option<(i64, i64)> {
        let i = ((q[0] - self.x0) / h).floor() as i64;
        let j = (q[1] / h).floor() as i64;
        (i >= 0 && j >= 0 && (i as usize) < self.nx && (j as usize) < self.ny).then_some((i, j))
    }
    pub(crate) fn get(&self, i: i64, j: i64) -> Option<u32> {
        if i < 0 || j < 0 || i as usize >= self.nx || j as usize >= self.ny {
            return None;
        }
        let v = self.lookup[j as usize * self.nx + i as usize];
        (v != u32::MAX).then_some(v)
    }
    /// Signed distance of q inside edge k (edge k runs from corner k to corner k+1).
    pub(crate) fn edge_inside(&self, q: V2, k: usize) -> f64 {
        let (a, b) = (self.local[k], self.local[(k + 1) % 3]);
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let len = ex.hypot(ey);
        // Counter-clockwise triangle: the inside is on the left.
        (ex * (q[1] - a[1]) - ey * (q[0] - a[0])) / len
    }
}

/// Clips a convex polygon by the half-plane `keep(p) ≥ 0`, where keep is affine.
fn clip(poly: &[V2], keep: impl Fn(V2) -> f64) -> Vec<V2> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (fp, fq) = (keep(p), keep(q));
        if fp >= 0.0 {
            out.push(p);
        }
        if (fp >= 0.0) != (fq >= 0.0) {
            let t = fp / (fp - fq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

fn area_centroid(poly: &[V2]) -> (f64, V2) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let c = p[0] * q[1] - q[0] * p[1];
        a += c;
        cx += (p[0] + q[0]) * c;
        cy += (p[1] + q[1]) * c;
    }
    let a = 0.5 * a;
    if a.abs() < 1e-300 {
        return (0.0, poly.first().copied().unwrap_or([0.0, 0.0]));
    }
    (a, [cx / (6.0 * a), cy / (6.0 * a)])
}

fn invalid(name: &'static str, reason: String) -> CoreError {
    CoreError::InvalidParameter { name, reason }
}

/// Builds the cell structure of `mesh` (see the module docs). With
/// [`CellSize::Count`] the size is estimated, and corrected once by the measured
/// count when it is more than 10 % off.
///
/// # Errors
/// [`CoreError::InvalidParameter`] for an empty mesh, a degenerate triangle, an
/// edge shared by more than two triangles or a bad cell size;
/// [`CoreError::MemoryLimit`] when the estimate exceeds `budget`.
pub fn build(mesh: &TriMesh, size: CellSize, budget: &MemoryBudget) -> Result<Cells, CoreError> {
    build_with(mesh, size, Pairing::Unfolded, budget)
}

/// [`build`] with the cells linked across edges by `pairing`.
///
/// # Errors
/// As [`build`].
pub fn build_with(
    mesh: &TriMesh,
    size: CellSize,
    pairing: Pairing,
    budget: &MemoryBudget,
) -> Result<Cells, CoreError> {
    let first = build_once(mesh, size, pairing, budget)?;
    match size {
        CellSize::Count(n) if (first.len() as f64 / n as f64 - 1.0).abs() > 0.1 => {
            let h = first.h * (first.len() as f64 / n as f64).sqrt();
            build_once(mesh, CellSize::Size(h), pairing, budget)
        }
        _ => Ok(first),
    }
}

/// Area, summed perimeters and shortest edge of a mesh.
struct MeshMeasures {
    area: f64,
    perimeter: f64,
    shortest: f64,
}

/// Measures the triangles, refusing degenerate ones.
fn measure(pos: &[[f64; 3]], tris: &[[u32; 3]]) -> Result<MeshMeasures, CoreError> {
    if tris.is_empty() {
        return Err(invalid("mesh", "has no triangles".into()));
    }
    let mut m = MeshMeasures {
        area: 0.0,
        perimeter: 0.0,
        shortest: f64::INFINITY,
    };
    for (t, tri) in tris.iter().enumerate() {
        let [a, b, c] = tri.map(|v| pos[v as usize]);
        let n = cross(sub(b, a), sub(c, a));
        let area = 0.5 * norm(n);
        let longest = norm(sub(b, a)).max(norm(sub(c, b))).max(norm(sub(a, c)));
        if area.is_nan() || area <= 1e-12 * longest * longest {
            return Err(invalid(
                "mesh",
                format!(
                    "triangle {t} is degenerate (area {area:e}); remove it or run with ⟨repair⟩"
                ),
            ));
        }
        m.area += area;
        for (p, q) in [(a, b), (b, c), (c, a)] {
            let l = norm(sub(q, p));
            m.shortest = m.shortest.min(l);
            m.perimeter += l;
        }
    }
    Ok(m)
}

/// About how many cells [`build`] makes on `mesh` for `size` (A/h² + 0.64·P/h,
/// the relation [`CellSize::Count`] solves), without building them: for checks
/// of time and memory before the work.
///
/// # Errors
/// The mesh's (degenerate or non-finite) or a bad size.
pub fn estimated_count(mesh: &TriMesh, size: CellSize) -> Result<f64, CoreError> {
    let m = measure(mesh.positions(), mesh.triangles())?;
    let h = cell_side(size, &m)?;
    Ok(m.area / (h * h) + 0.64 * m.perimeter / h)
}

/// The cell side for `size` on a mesh of these measures.
fn cell_side(size: CellSize, m: &MeshMeasures) -> Result<f64, CoreError> {
    let h = match size {
        CellSize::Size(h) => h,
        CellSize::Count(n) => {
            if n == 0 {
                return Err(invalid("cells", "must be at least 1".into()));
            }
            // Cells ≈ A/h² + k·P/h: every triangle adds a border of PART-IN cells
            // along its perimeter P (k ≈ 2/π for random orientations, measured
            // 0.6–0.7). Solve for 1/h.
            let k = 0.64;
            let (a, p) = (m.area, m.perimeter);
            let x = (-k * p + (k * k * p * p + 4.0 * a * n as f64).sqrt()) / (2.0 * a);
            1.0 / x
        }
    };
    if !(h.is_finite() && h > 0.0) {
        return Err(invalid("cell size", format!("must be positive, got {h}")));
    }
    Ok(h)
}

/// Edge (min vertex, max vertex) → its triangles with the edge's index in each.
type EdgeMap = std::collections::HashMap<(u32, u32), Vec<(u32, usize)>>;

/// The edge map and the number of boundary edges, refusing non-manifold edges.
fn edge_map(tris: &[[u32; 3]]) -> Result<(EdgeMap, usize), CoreError> {
    let mut edges = EdgeMap::new();
    for (t, tri) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push((t as u32, k));
        }
    }
    let mut boundary_edges = 0usize;
    for (e, list) in &edges {
        if list.len() > 2 {
            return Err(invalid(
                "mesh",
                format!(
                    "edge ({}, {}) is shared by {} triangles; surface cells need a manifold mesh",
                    e.0,
                    e.1,
                    list.len()
                ),
            ));
        }
        if list.len() == 1 {
            boundary_edges += 1;
        }
    }
    Ok((edges, boundary_edges))
}

impl Cells {
    /// No cells yet, side `h`, room for `triangles` triangles.
    fn empty(h: f64, triangles: usize) -> Self {
        Cells {
            h,
            triangle: Vec::new(),
            ij: Vec::new(),
            centre: Vec::new(),
            area: Vec::new(),
            flag: Vec::new(),
            triangle_normal: Vec::with_capacity(triangles),
            total_area: 0.0,
            grids: Vec::with_capacity(triangles),
            frames: Vec::new(),
            edge_map: std::collections::HashMap::new(),
            poly_offsets: vec![0],
            poly_points: Vec::new(),
            nbr_offsets: Vec::new(),
            nbr: Vec::new(),
            nbr_dir: Vec::new(),
            stats: CellStats::default(),
        }
    }
}

/// Triangle `tri`'s plane frame (A at the origin, AB along x, C above) with an
/// empty grid of squares of side `h` over its bounding box; returns its unit
/// normal too.
fn frame(tri: [u32; 3], pos: &[[f64; 3]], h: f64) -> (Frame, [f64; 3]) {
    let [a, b, c] = tri.map(|v| pos[v as usize]);
    let ab = sub(b, a);
    let e1 = scale(ab, 1.0 / norm(ab));
    let n = cross(ab, sub(c, a));
    let n = scale(n, 1.0 / norm(n));
    let e2 = cross(n, e1);
    let mut f = Frame {
        verts: tri,
        origin: a,
        e1,
        e2,
        local: [[0.0, 0.0], [0.0; 2], [0.0; 2]],
        x0: 0.0,
        nx: 0,
        ny: 0,
        lookup: Vec::new(),
    };
    f.local = [[0.0, 0.0], f.to_local(b), f.to_local(c)];
    let [_, lb, lc] = f.local;
    f.x0 = lc[0].min(0.0);
    let xmax = lb[0].max(lc[0]);
    f.nx = (((xmax - f.x0) / h).ceil() as usize).max(1);
    f.ny = ((lc[1] / h).ceil() as usize).max(1);
    f.lookup = vec![u32::MAX; f.nx * f.ny];
    (f, n)
}

/// Square (i, j) of `f`'s grid clipped to the triangle: its polygon in the frame.
fn clip_square(f: &Frame, i: usize, j: usize, h: f64) -> Vec<V2> {
    let (xa, ya) = (f.x0 + i as f64 * h, j as f64 * h);
    let (xb, yb) = (xa + h, ya + h);
    let mut poly = f.local.to_vec();
    poly = clip(&poly, |p| p[0] - xa);
    poly = clip(&poly, |p| xb - p[0]);
    poly = clip(&poly, |p| p[1] - ya);
    clip(&poly, |p| yb - p[1])
}

/// Covers triangle `t` (frame `f`) with cells: every square of its grid that
/// overlaps it with positive area becomes a cell; returns the OUT-CELL count.
fn cover(cells: &mut Cells, f: &mut Frame, t: usize) -> usize {
    let h = cells.h;
    let mut out_cells = 0usize;
    for j in 0..f.ny {
        for i in 0..f.nx {
            let poly = clip_square(f, i, j, h);
            let (area, centroid) = if poly.len() >= 3 {
                area_centroid(&poly)
            } else {
                (0.0, [0.0, 0.0])
            };
            if area <= 1e-12 * h * h {
                out_cells += 1;
                continue;
            }
            let id = cells.area.len() as u32;
            f.lookup[j * f.nx + i] = id;
            let centre = [f.x0 + i as f64 * h + 0.5 * h, j as f64 * h + 0.5 * h];
            let inside = (0..3).all(|k| f.edge_inside(centre, k) >= 0.0);
            cells.triangle.push(t as u32);
            cells.ij.push([i as u32, j as u32]);
            cells.centre.push(f.to_world(centroid));
            cells.area.push(area);
            cells.flag.push(if inside {
                InFlag::CompIn
            } else {
                InFlag::PartIn
            });
            cells
                .poly_points
                .extend(poly.iter().map(|&q| f.to_world(q)));
            cells.poly_offsets.push(cells.poly_points.len() as u32);
        }
    }
    out_cells
}

/// Frames and cells of every triangle; returns the frames and the OUT-CELL count.
fn divide(cells: &mut Cells, pos: &[[f64; 3]], tris: &[[u32; 3]]) -> (Vec<Frame>, usize) {
    let mut frames = Vec::with_capacity(tris.len());
    let mut out_cells = 0usize;
    for (t, tri) in tris.iter().enumerate() {
        let (mut f, n) = frame(*tri, pos, cells.h);
        cells.triangle_normal.push(n);
        out_cells += cover(cells, &mut f, t);
        cells.grids.push(TriangleGrid {
            x0: f.x0,
            nx: f.nx,
            ny: f.ny,
            local: f.local,
        });
        frames.push(f);
    }
    (frames, out_cells)
}

/// The cells within 2.5h of each mesh vertex (for links beyond vertices).
fn cells_near_vertices(
    frames: &[Frame],
    cells: &Cells,
    pos: &[[f64; 3]],
) -> std::collections::HashMap<u32, Vec<u32>> {
    let h = cells.h;
    let reach = 2.5 * h;
    let mut near_vertex: std::collections::HashMap<u32, Vec<u32>> =
        std::collections::HashMap::new();
    for f in frames {
        for k in 0..3 {
            let v = f.verts[k];
            let q = f.local[k];
            let r = (reach / h).ceil() as i64 + 1;
            let (ci, cj) = (
                ((q[0] - f.x0) / h).floor() as i64,
                (q[1] / h).floor() as i64,
            );
            for j in cj - r..=cj + r {
                for i in ci - r..=ci + r {
                    if let Some(c) = f.get(i, j) {
                        let d = norm(sub(cells.centre[c as usize], pos[v as usize]));
                        if d <= reach {
                            near_vertex.entry(v).or_default().push(c);
                        }
                    }
                }
            }
        }
    }
    near_vertex
}

/// What links are made from: the frames, the edge map, the cells near each
/// vertex, the cells and the mesh positions.
impl Cells {
    /// Stores each cell's links sorted by direction, without self-links or
    /// repeats.
    fn set_neighbours(&mut self, mut links: Vec<Vec<(u32, u8)>>) {
        self.nbr_offsets.reserve(links.len() + 1);
        self.nbr_offsets.push(0);
        for l in &mut links {
            l.sort_by_key(|&(n, k)| (k, n));
            let mut seen: Vec<u32> = Vec::with_capacity(l.len());
            for &(n, k) in l.iter() {
                if n as usize == self.nbr_offsets.len() - 1 || seen.contains(&n) {
                    continue;
                }
                seen.push(n);
                self.nbr.push(n);
                self.nbr_dir.push(k);
            }
            self.nbr_offsets.push(self.nbr.len() as u32);
        }
    }
}

/// Warnings on the cell size against the shortest edge and on boundaries.
fn warnings(h: f64, shortest: f64, boundary_edges: usize) -> Vec<String> {
    let mut warnings = Vec::new();
    if h > shortest {
        warnings.push(format!(
            "cell size {h:.4} exceeds the shortest triangle edge {shortest:.4}: \
             neighbours can skip across thin triangles (gobron-chiba Figure 9); use more cells"
        ));
    }
    if boundary_edges > 0 {
        warnings.push(format!(
            "the mesh has {boundary_edges} boundary edges; nothing crosses them"
        ));
    }
    warnings
}

fn build_once(
    mesh: &TriMesh,
    size: CellSize,
    pairing: Pairing,
    budget: &MemoryBudget,
) -> Result<Cells, CoreError> {
    let (pos, tris) = (mesh.positions(), mesh.triangles());
    let m = measure(pos, tris)?;
    let h = cell_side(size, &m)?;
    // ≈ 260 bytes per cell (record, polygon, links); cells ≈ area/h² plus a border.
    let estimate = (m.area / (h * h)) * 1.3 + 4.0 * tris.len() as f64;
    budget.check_elements(estimate as u128 + 1, 260, "the surface-CA cells")?;
    let (edges, boundary_edges) = edge_map(tris)?;
    let mut cells = Cells::empty(h, tris.len());
    let (frames, out_cells) = divide(&mut cells, pos, tris);
    let near_vertex = cells_near_vertices(&frames, &cells, pos);
    let edge_cells = all_edge_cells(&frames, &edges, h);
    let linker = Linker {
        frames: &frames,
        edges: &edges,
        near_vertex: &near_vertex,
        cells: &cells,
        pos,
        pairing,
        edge_cells: &edge_cells,
    };
    let mut links = linker.links();
    let redundancy = pairing_redundancy(&mut links.cross);
    symmetrise(&mut links.links);
    let n_cells = cells.len();
    cells.set_neighbours(links.links);
    cells.total_area = cells.area.iter().sum();
    let comp_in = cells.flag.iter().filter(|f| **f == InFlag::CompIn).count();
    cells.stats = CellStats {
        cells: n_cells,
        comp_in,
        part_in: n_cells - comp_in,
        out_cells,
        cell_size: h,
        shortest_edge: m.shortest,
        edge_links: links.edge_links,
        vertex_links: links.vertex_links,
        pairing_redundancy: redundancy,
        paper_redundancy: paper_redundancy(&edges, &edge_cells),
        pairing,
        warnings: warnings(h, m.shortest, boundary_edges),
    };
    cells.frames = frames;
    cells.edge_map = edges;
    Ok(cells)
}

/// The active cell of `g` containing `q`, or the nearest active one (by centroid).
fn nearest_in(g: &Frame, q: V2, h: f64, centres: &[[f64; 3]]) -> Option<u32> {
    if let Some((i, j)) = g.cell_at(q, h)
        && let Some(c) = g.get(i, j)
    {
        return Some(c);
    }
    let p = g.to_world(q);
    let (ci, cj) = (
        ((q[0] - g.x0) / h).floor() as i64,
        (q[1] / h).floor() as i64,
    );
    for r in 1..=3i64 {
        let mut best: Option<(f64, u32)> = None;
        for j in cj - r..=cj + r {
            for i in ci - r..=ci + r {
                if let Some(c) = g.get(i, j) {
                    let d = norm(sub(centres[c as usize], p));
                    if best.is_none_or(|(bd, bc)| d < bd || (d == bd && c < bc)) {
                        best = Some((d, c));
                    }
                }
            }
        }
        if let Some((_, c)) = best {
            return Some(c);
        }
    }
    // A thin triangle far from q: scan it.
    g.lookup
        .iter()
        .filter(|&&c| c != u32::MAX)
        .min_by(|&&a, &&b| {
            norm(sub(centres[a as usize], p))
                .total_cmp(&norm(sub(centres[b as usize], p)))
                .then(a.cmp(&b))
        })
        .copied()
}
