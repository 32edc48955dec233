//! One validation of surface meshes for every command and format.
//!
//! The methods that walk a mesh as a surface — Catmull–Clark subdivision
//! (velho-perlin §2), cellular automata on its triangles (gobron-chiba §3,
//! algorithm step 1 "verify completeness of object") and the voxelised solid of
//! curved growth (kim-machiraju-thompson §4) — all need the same things of it:
//! faces of non-zero area, every edge shared by at most two faces, the faces
//! around every vertex forming one fan, and shared edges run in opposite
//! directions. [`check_surface`] tests these in that order and reports the first
//! problem with the element it concerns, so the same file gets the same answer
//! from `subdiv`, `surface-ca` and `growth --substrate mesh`. Faces with fewer
//! than three corners, or a repeated corner, are refused when the mesh is built
//! ([`crate::PolyMesh::new`], the readers).
//!
//! [`split_vertex_fans`] repairs the one defect that can be repaired without
//! guessing: a vertex where separate fans meet (a "bowtie") becomes one vertex
//! per fan.

use std::fmt;

use crate::vec3::{cross, dot, sub};
use crate::{CoreError, TriMesh};

/// What a method needs of a mesh beyond the checks every surface method makes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SurfaceNeeds {
    /// Every edge shared by exactly two faces (the mesh bounds a solid).
    pub closed: bool,
}

/// The first problem [`check_surface`] found.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshDefect {
    /// The mesh has no face.
    Empty,
    /// A face of (near) zero area: area ≤ 10⁻¹² × its longest edge².
    Degenerate {
        /// Face number.
        face: usize,
        /// Its area.
        area: f64,
    },
    /// An edge used by more than two faces.
    NonManifoldEdge {
        /// Its end vertices.
        edge: [u32; 2],
        /// How many faces use it.
        faces: usize,
    },
    /// A vertex whose faces form more than one fan (two cones touching at a point).
    NonManifoldVertex {
        /// Vertex number.
        vertex: u32,
        /// How many separate fans meet there.
        fans: usize,
    },
    /// Two faces run their shared edge the same way.
    Inconsistent {
        /// The edge, in the direction both faces run it.
        edge: [u32; 2],
    },
    /// Edges used by one face only, where a closed surface is needed.
    Open {
        /// Number of boundary edges.
        boundary_edges: usize,
    },
}

impl MeshDefect {
    /// Whether [`repair_surface`] (degenerate faces dropped, faces reoriented,
    /// bowties split) can fix it.
    pub fn repairable(&self) -> bool {
        matches!(
            self,
            MeshDefect::Degenerate { .. }
                | MeshDefect::Inconsistent { .. }
                | MeshDefect::NonManifoldVertex { .. }
        )
    }
}

impl fmt::Display for MeshDefect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshDefect::Empty => write!(f, "the mesh has no face"),
            MeshDefect::Degenerate { face, area } => {
                write!(f, "face {face} is degenerate (area {area:.3e})")
            }
            MeshDefect::NonManifoldEdge {
                edge: [a, b],
                faces,
            } => write!(
                f,
                "edge {a}–{b} is shared by {faces} faces (a non-manifold edge; at most 2 allowed)"
            ),
            MeshDefect::NonManifoldVertex { vertex, fans } => write!(
                f,
                "vertex {vertex} joins {fans} separate fans of faces (a non-manifold vertex)"
            ),
            MeshDefect::Inconsistent { edge: [a, b] } => write!(
                f,
                "two faces run their shared edge {a}→{b} the same way (inconsistent orientation)"
            ),
            MeshDefect::Open { boundary_edges } => write!(
                f,
                "it is not closed: {boundary_edges} edges belong to one face only, so it bounds no solid"
            ),
        }
    }
}

impl From<MeshDefect> for CoreError {
    fn from(d: MeshDefect) -> Self {
        let hint = if d.repairable() {
            "; `asperity convert --repair IN OUT` writes a repaired copy"
        } else {
            ""
        };
        CoreError::InvalidParameter {
            name: "mesh",
            reason: format!("{d}{hint}"),
        }
    }
}

/// Checks a polygon mesh (faces as vertex lists, counter-clockwise) in the order
/// of the module docs: degenerate faces, non-manifold edges, non-manifold
/// vertices, orientation, then (if asked) closedness.
///
/// # Errors
/// The first [`MeshDefect`] found.
pub fn check_surface<'a, I>(
    positions: &[[f64; 3]],
    faces: I,
    needs: SurfaceNeeds,
) -> Result<(), MeshDefect>
where
    I: Iterator<Item = &'a [u32]> + Clone,
{
    if faces.clone().next().is_none() {
        return Err(MeshDefect::Empty);
    }
    for (f, face) in faces.clone().enumerate() {
        let area = polygon_area(positions, face);
        let longest = (0..face.len())
            .map(|k| {
                let d = sub(
                    positions[face[(k + 1) % face.len()] as usize],
                    positions[face[k] as usize],
                );
                dot(d, d)
            })
            .fold(0.0, f64::max);
        if area.is_nan() || area <= 1e-12 * longest {
            return Err(MeshDefect::Degenerate { face: f, area });
        }
    }
    let mut directed: Vec<[u32; 2]> = faces
        .clone()
        .flat_map(|face| (0..face.len()).map(move |k| [face[k], face[(k + 1) % face.len()]]))
        .collect();
    let mut undirected: Vec<[u32; 2]> = directed
        .iter()
        .map(|&[a, b]| [a.min(b), a.max(b)])
        .collect();
    undirected.sort_unstable();
    let mut boundary_edges = 0;
    for run in undirected.chunk_by(|a, b| a == b) {
        match run.len() {
            1 => boundary_edges += 1,
            2 => {}
            n => {
                return Err(MeshDefect::NonManifoldEdge {
                    edge: run[0],
                    faces: n,
                });
            }
        }
    }
    if let Some((vertex, fans)) = first_split_vertex(positions.len(), faces) {
        return Err(MeshDefect::NonManifoldVertex { vertex, fans });
    }
    directed.sort_unstable();
    if let Some(w) = directed.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshDefect::Inconsistent { edge: w[0] });
    }
    if needs.closed && boundary_edges > 0 {
        return Err(MeshDefect::Open { boundary_edges });
    }
    Ok(())
}

/// [`check_surface`] for a triangle mesh.
///
/// # Errors
/// As [`check_surface`].
pub fn check_triangles(mesh: &TriMesh, needs: SurfaceNeeds) -> Result<(), MeshDefect> {
    check_surface(
        mesh.positions(),
        mesh.triangles().iter().map(|t| t.as_slice()),
        needs,
    )
}

/// [`check_surface`] for a polygon mesh.
///
/// # Errors
/// As [`check_surface`].
pub fn check_polygons(mesh: &crate::PolyMesh, needs: SurfaceNeeds) -> Result<(), MeshDefect> {
    check_surface(mesh.positions(), mesh.faces(), needs)
}

/// Area of a polygon from Newell's vector (exact for planar polygons).
fn polygon_area(p: &[[f64; 3]], face: &[u32]) -> f64 {
    let o = p[face[0] as usize];
    let mut n = [0.0; 3];
    for k in 1..face.len().saturating_sub(1) {
        let c = cross(sub(p[face[k] as usize], o), sub(p[face[k + 1] as usize], o));
        n = [n[0] + c[0], n[1] + c[1], n[2] + c[2]];
    }
    0.5 * dot(n, n).sqrt()
}

/// The link of every vertex: for each face around it, the pair of neighbours
/// (previous, next corner) — the edge opposite the vertex in a triangle.
fn links<'a>(n: usize, faces: impl Iterator<Item = &'a [u32]>) -> Vec<Vec<[u32; 2]>> {
    let mut link: Vec<Vec<[u32; 2]>> = vec![Vec::new(); n];
    for face in faces {
        let m = face.len();
        for k in 0..m {
            link[face[k] as usize].push([face[(k + m - 1) % m], face[(k + 1) % m]]);
        }
    }
    link
}

/// The links of a range of vertices as one flat list: for vertex v, the
/// (previous, next) corners of each triangle around it, in
/// `entries[start[v] - start[first]..start[v + 1] - start[first]]`.
pub(crate) struct Links<'a> {
    start: &'a [u32],
    first: usize,
    entries: Vec<[u32; 2]>,
}

/// Per vertex, where its corners start in a list of all corners by vertex
/// (prefix sums of the triangles around each vertex; `n + 1` entries).
pub(crate) fn corner_starts(n: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut start = vec![0u32; n + 1];
    for t in triangles {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    start
}

/// Vertex ranges whose links hold at most about `corners` corners each (a
/// vertex with more takes a range alone).
pub(crate) fn link_batches(start: &[u32], corners: u32) -> Vec<std::ops::Range<usize>> {
    let n = start.len() - 1;
    let mut out = Vec::new();
    let mut first = 0;
    while first < n {
        let limit = start[first].saturating_add(corners);
        let end = start
            .partition_point(|&s| s <= limit)
            .saturating_sub(1)
            .clamp(first + 1, n);
        out.push(first..end);
        first = end;
    }
    out
}

/// What the links say, summed over vertices.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LinkFacts {
    /// Undirected edges.
    pub edges: usize,
    /// Edges with one triangle.
    pub boundary_edges: usize,
    /// The most triangles on one edge.
    pub max_faces: usize,
    /// A used vertex whose triangles form more than one fan.
    pub split_vertex: bool,
    /// A directed edge that two triangles traverse the same way.
    pub repeated_directed_edge: bool,
}

impl LinkFacts {
    pub(crate) fn merge(a: Self, b: Self) -> Self {
        Self {
            edges: a.edges + b.edges,
            boundary_edges: a.boundary_edges + b.boundary_edges,
            max_faces: a.max_faces.max(b.max_faces),
            split_vertex: a.split_vertex || b.split_vertex,
            repeated_directed_edge: a.repeated_directed_edge || b.repeated_directed_edge,
        }
    }
}

/// Link entries a vertex's facts are worked out for on the stack.
const SMALL_LINK: usize = 24;

impl<'a> Links<'a> {
    /// The links of the vertices `range` of `triangles` (no vertex repeated
    /// in a triangle), `start` their [`corner_starts`].
    pub(crate) fn new(
        start: &'a [u32],
        range: std::ops::Range<usize>,
        triangles: &[[u32; 3]],
    ) -> Self {
        let (lo, hi) = (start[range.start], start[range.end]);
        let mut at: Vec<u32> = start[range.clone()].iter().map(|&s| s - lo).collect();
        let mut entries = vec![[0u32; 2]; (hi - lo) as usize];
        let (v0, v1) = (range.start as u32, range.end as u32);
        for &[a, b, c] in triangles {
            for (v, prev, next) in [(a, c, b), (b, a, c), (c, b, a)] {
                if (v0..v1).contains(&v) {
                    let slot = &mut at[(v - v0) as usize];
                    entries[*slot as usize] = [prev, next];
                    *slot += 1;
                }
            }
        }
        Self {
            start,
            first: range.start,
            entries,
        }
    }

    /// The facts of vertex `v`: the edges to higher vertices and their
    /// triangle counts, its fans, its outgoing directed edges.
    pub(crate) fn examine(&self, v: u32) -> LinkFacts {
        let base = self.start[self.first];
        let link = &self.entries[(self.start[v as usize] - base) as usize
            ..(self.start[v as usize + 1] - base) as usize];
        let mut facts = LinkFacts::default();
        if link.is_empty() {
            return facts;
        }
        if link.len() > SMALL_LINK {
            let (fans, _) = fan_labels(link);
            facts.split_vertex = fans > 1;
            let mut next: Vec<u32> = link.iter().map(|e| e[1]).collect();
            next.sort_unstable();
            facts.repeated_directed_edge = next.windows(2).any(|w| w[0] == w[1]);
            let mut around: Vec<u32> = link.iter().flatten().copied().collect();
            around.sort_unstable();
            count_edges(v, &around, &mut facts);
            return facts;
        }
        let k = link.len();
        let mut next = [0u32; SMALL_LINK];
        let mut around = [0u32; 2 * SMALL_LINK];
        for (i, e) in link.iter().enumerate() {
            next[i] = e[1];
            around[2 * i] = e[0];
            around[2 * i + 1] = e[1];
        }
        next[..k].sort_unstable();
        facts.repeated_directed_edge = next[..k].windows(2).any(|w| w[0] == w[1]);
        around[..2 * k].sort_unstable();
        count_edges(v, &around[..2 * k], &mut facts);
        facts.split_vertex = small_fans(link) > 1;
        facts
    }
}

/// The edges from `v` to the higher vertices of `around` (its link's corners,
/// sorted: each neighbour once per triangle on the edge).
fn count_edges(v: u32, around: &[u32], facts: &mut LinkFacts) {
    for run in around.chunk_by(|a, b| a == b) {
        if run[0] > v {
            facts.edges += 1;
            facts.boundary_edges += usize::from(run.len() == 1);
        }
        facts.max_faces = facts.max_faces.max(run.len());
    }
}

/// The number of fans of a short link (entries joined through a shared
/// corner), without allocating.
fn small_fans(link: &[[u32; 2]]) -> usize {
    let k = link.len();
    let mut parent = [0u8; SMALL_LINK];
    for (i, p) in parent.iter_mut().enumerate().take(k) {
        *p = i as u8;
    }
    fn find(p: &mut [u8], mut x: u8) -> u8 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    for i in 0..k {
        for j in i + 1..k {
            let (a, b) = (link[i], link[j]);
            if a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1] {
                let (ri, rj) = (find(&mut parent, i as u8), find(&mut parent, j as u8));
                parent[ri as usize] = rj;
            }
        }
    }
    (0..k)
        .filter(|&i| find(&mut parent, i as u8) == i as u8)
        .count()
}

/// The first vertex whose faces form more than one fan, with the fan count.
fn first_split_vertex<'a>(
    n: usize,
    faces: impl Iterator<Item = &'a [u32]>,
) -> Option<(u32, usize)> {
    links(n, faces).iter().enumerate().find_map(|(v, l)| {
        let fans = fan_labels(l).0;
        (fans > 1).then_some((v as u32, fans))
    })
}

/// Groups the faces around one vertex into fans (faces joined through a shared
/// edge at the vertex): the fan count and each link entry's fan. A link vertex
/// shared by more than two entries (an edge of more than two faces) joins them
/// all, which [`check_surface`] reports as a non-manifold edge before this.
fn fan_labels(link: &[[u32; 2]]) -> (usize, Vec<usize>) {
    let mut parent: Vec<usize> = (0..link.len()).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    // Entries sharing a neighbour share the edge (vertex, neighbour).
    let mut by_neighbour: Vec<(u32, usize)> = link
        .iter()
        .enumerate()
        .flat_map(|(i, &[a, b])| [(a, i), (b, i)])
        .collect();
    by_neighbour.sort_unstable();
    for run in by_neighbour.chunk_by(|x, y| x.0 == y.0) {
        for w in run.windows(2) {
            let (ra, rb) = (find(&mut parent, w[0].1), find(&mut parent, w[1].1));
            parent[ra] = rb;
        }
    }
    let mut label = vec![usize::MAX; link.len()];
    let mut roots: Vec<usize> = Vec::new();
    for (i, l) in label.iter_mut().enumerate() {
        let r = find(&mut parent, i);
        *l = roots.iter().position(|&x| x == r).unwrap_or_else(|| {
            roots.push(r);
            roots.len() - 1
        });
    }
    (roots.len(), label)
}

/// Whether the faces around every vertex form one fan.
pub(crate) fn vertex_fans_single<'a>(n: usize, faces: impl Iterator<Item = &'a [u32]>) -> bool {
    first_split_vertex(n, faces).is_none()
}

/// Gives every extra fan at a non-manifold vertex its own copy of the vertex
/// (with its normal, colour, UV and scalars), so two surfaces touching at a
/// point no longer share it. Returns the mesh and the number of copies made.
///
/// # Errors
/// As [`TriMesh::new`] (not expected: the copies are valid vertices).
pub fn split_vertex_fans(mesh: &TriMesh) -> crate::Result<(TriMesh, usize)> {
    let tris = mesh.triangles();
    let n = mesh.n_vertices();
    // Each (vertex, corner) in the order `links` lists them: face by face.
    let link = links(n, tris.iter().map(|t| t.as_slice()));
    let mut cursor = vec![0usize; n];
    let mut new_index: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut origin: Vec<u32> = (0..n as u32).collect();
    for (v, l) in link.iter().enumerate() {
        let (fans, label) = fan_labels(l);
        if fans <= 1 {
            continue;
        }
        // Fan 0 keeps the vertex; the others get copies.
        let mut ids = vec![v as u32];
        for _ in 1..fans {
            ids.push(
                u32::try_from(origin.len()).map_err(|_| CoreError::InvalidParameter {
                    name: "mesh",
                    reason: "more than 2³² vertices".into(),
                })?,
            );
            origin.push(v as u32);
        }
        new_index[v] = label.iter().map(|&k| ids[k]).collect();
    }
    let copies = origin.len() - n;
    if copies == 0 {
        return Ok((mesh.clone(), 0));
    }
    let triangles: Vec<[u32; 3]> = tris
        .iter()
        .map(|t| {
            t.map(|v| {
                let v = v as usize;
                let k = cursor[v];
                cursor[v] += 1;
                new_index[v].get(k).copied().unwrap_or(v as u32)
            })
        })
        .collect();
    Ok((mesh.with_vertices_from(&origin, triangles)?, copies))
}

/// What [`repair_surface`] changed.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RepairReport {
    /// Degenerate (zero-area) triangles removed.
    pub dropped_degenerate: usize,
    /// Triangles flipped to agree with their neighbours.
    pub flipped: usize,
    /// Vertex copies made where separate fans of triangles met at one vertex.
    pub split_vertices: usize,
}

/// Repairs what can be repaired without guessing: degenerate triangles are
/// dropped; triangles are flipped so that every shared edge is used once in
/// each direction (breadth-first over each connected component, keeping its
/// first triangle's orientation); a vertex where separate fans meet gets one
/// copy per fan ([`split_vertex_fans`]). Per-vertex data is kept.
///
/// # Errors
/// [`CoreError::InvalidParameter`] for an edge shared by more than two
/// triangles, or a surface that cannot be oriented (a Möbius strip), which no
/// repair can fix; an empty result.
pub fn repair_surface(mesh: &TriMesh) -> crate::Result<(TriMesh, RepairReport)> {
    let p = mesh.positions();
    let mut report = RepairReport::default();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(mesh.n_faces());
    for &t in mesh.triangles() {
        if matches!(
            check_surface(p, std::iter::once(t.as_slice()), SurfaceNeeds::default()),
            Err(MeshDefect::Degenerate { .. })
        ) {
            report.dropped_degenerate += 1;
        } else {
            tris.push(t);
        }
    }
    if tris.is_empty() {
        return Err(MeshDefect::Empty.into());
    }
    report.flipped = orient_components(&mut tris)?;
    let identity: Vec<u32> = (0..p.len() as u32).collect();
    let (split, copies) = split_vertex_fans(&mesh.with_vertices_from(&identity, tris)?)?;
    report.split_vertices = copies;
    check_triangles(&split, SurfaceNeeds::default()).map_err(|d| CoreError::InvalidParameter {
        name: "mesh",
        reason: format!("{d} after repair (the surface is not orientable, like a Möbius strip)"),
    })?;
    Ok((split, report))
}

/// Flips triangles so that neighbours run their shared edge in opposite
/// directions; returns the number flipped.
fn orient_components(tris: &mut [[u32; 3]]) -> crate::Result<usize> {
    let mut edges: std::collections::HashMap<(u32, u32), Vec<usize>> =
        std::collections::HashMap::new();
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(i);
        }
    }
    if let Some((&(a, b), l)) = edges
        .iter()
        .filter(|(_, l)| l.len() > 2)
        .min_by_key(|(e, _)| **e)
    {
        return Err(MeshDefect::NonManifoldEdge {
            edge: [a, b],
            faces: l.len(),
        }
        .into());
    }
    let has_directed =
        |t: &[u32; 3], a: u32, b: u32| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
    let mut flipped = 0;
    let mut seen = vec![false; tris.len()];
    for start in 0..tris.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut queue = std::collections::VecDeque::from([start]);
        while let Some(i) = queue.pop_front() {
            let t = tris[i];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                for &j in &edges[&(a.min(b), a.max(b))] {
                    if j == i || seen[j] {
                        continue;
                    }
                    // The neighbour must use the edge as b → a.
                    if has_directed(&tris[j], a, b) {
                        tris[j].swap(1, 2);
                        flipped += 1;
                    }
                    seen[j] = true;
                    queue.push_back(j);
                }
            }
        }
    }
    Ok(flipped)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bowtie() -> TriMesh {
        TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        )
        .unwrap()
    }

    #[test]
    fn a_bowtie_is_a_non_manifold_vertex_and_splits_into_two_fans() {
        let m = bowtie();
        assert_eq!(
            check_triangles(&m, SurfaceNeeds::default()),
            Err(MeshDefect::NonManifoldVertex { vertex: 0, fans: 2 })
        );
        let (fixed, copies) = split_vertex_fans(&m).unwrap();
        assert_eq!(copies, 1);
        assert_eq!(fixed.n_vertices(), 6);
        assert_eq!(fixed.triangles(), &[[0, 1, 2], [5, 3, 4]]);
        assert_eq!(fixed.positions()[5], [0.0; 3]);
        assert_eq!(check_triangles(&fixed, SurfaceNeeds::default()), Ok(()));
    }

    #[test]
    fn the_closed_octahedron_passes_and_the_open_one_is_named() {
        let oct = crate::shapes::icosphere(0, 1.0);
        assert_eq!(check_triangles(&oct, SurfaceNeeds { closed: true }), Ok(()));
        let open = TriMesh::new(oct.positions().to_vec(), oct.triangles()[1..].to_vec()).unwrap();
        assert_eq!(check_triangles(&open, SurfaceNeeds::default()), Ok(()));
        assert_eq!(
            check_triangles(&open, SurfaceNeeds { closed: true }),
            Err(MeshDefect::Open { boundary_edges: 3 })
        );
    }

    #[test]
    fn each_defect_is_found_with_its_element() {
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [2.0, 0.0, 0.0],
        ];
        let flat = [[0u32, 1, 4]];
        assert!(matches!(
            check_surface(
                &p,
                flat.iter().map(|f| f.as_slice()),
                SurfaceNeeds::default()
            ),
            Err(MeshDefect::Degenerate { face: 0, .. })
        ));
        let three = [[0u32, 1, 2], [1, 0, 3], [0, 1, 3]];
        assert!(matches!(
            check_surface(
                &p,
                three.iter().map(|f| f.as_slice()),
                SurfaceNeeds::default()
            ),
            Err(MeshDefect::NonManifoldEdge {
                edge: [0, 1],
                faces: 3
            })
        ));
        let flipped = [[0u32, 1, 2], [0, 1, 3]];
        assert_eq!(
            check_surface(
                &p,
                flipped.iter().map(|f| f.as_slice()),
                SurfaceNeeds::default()
            ),
            Err(MeshDefect::Inconsistent { edge: [0, 1] })
        );
        let none: [[u32; 3]; 0] = [];
        assert_eq!(
            check_surface(
                &p,
                none.iter().map(|f| f.as_slice()),
                SurfaceNeeds::default()
            ),
            Err(MeshDefect::Empty)
        );
    }

    #[test]
    fn quads_are_checked_like_triangles() {
        let cube = crate::shapes::cube_cage();
        assert_eq!(check_polygons(&cube, SurfaceNeeds { closed: true }), Ok(()));
    }
}
