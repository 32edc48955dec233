//! The completeness check of the paper's algorithm, step 1 (Appendix 2: "verify
//! completeness of object"), and an explicit repair for what can be repaired:
//! degenerate triangles are dropped and triangles are flipped so that every
//! shared edge is used once in each direction (breadth-first over each
//! connected component, keeping its first triangle's orientation). Edges shared
//! by more than two triangles cannot be repaired and are reported.

use asperity_core::{CoreError, TriMesh};

/// What [`repair`] changed.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct RepairReport {
    /// Degenerate (zero-area) triangles removed.
    pub dropped_degenerate: usize,
    /// Triangles flipped to agree with their neighbours.
    pub flipped: usize,
}

fn degenerate(p: &[[f64; 3]], t: [u32; 3]) -> bool {
    let [a, b, c] = t.map(|v| p[v as usize]);
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let area2 = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let longest = [u, v, [c[0] - b[0], c[1] - b[1], c[2] - b[2]]]
        .iter()
        .map(|e| e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
        .fold(0.0, f64::max);
    area2.is_nan() || area2 <= 2e-12 * longest
}

/// The step-1 check: every triangle non-degenerate, every edge shared by at most
/// two triangles, shared edges used in opposite directions.
///
/// # Errors
/// [`CoreError::InvalidParameter`] describing the first problem and whether
/// `--repair` can fix it.
pub fn check(mesh: &TriMesh) -> Result<(), CoreError> {
    let bad = |reason: String| CoreError::InvalidParameter {
        name: "mesh",
        reason,
    };
    if let Some(t) = mesh
        .triangles()
        .iter()
        .position(|&t| degenerate(mesh.positions(), t))
    {
        return Err(bad(format!(
            "triangle {t} is degenerate; --repair drops degenerate triangles"
        )));
    }
    if !mesh.is_edge_manifold() {
        return Err(bad(
            "an edge is shared by more than two triangles; a surface CA needs a manifold mesh \
             (this cannot be repaired automatically)"
                .into(),
        ));
    }
    if !mesh.is_consistently_oriented() {
        return Err(bad(
            "the triangles are not consistently oriented (gobron-chiba, algorithm step 1); \
             --repair reorients them"
                .into(),
        ));
    }
    Ok(())
}

/// Drops degenerate triangles and reorients consistently (see the module docs).
///
/// # Errors
/// [`CoreError::InvalidParameter`] for non-manifold edges, which cannot be repaired.
pub fn repair(mesh: &TriMesh) -> Result<(TriMesh, RepairReport), CoreError> {
    let p = mesh.positions();
    let mut report = RepairReport::default();
    let mut tris: Vec<[u32; 3]> = Vec::with_capacity(mesh.n_faces());
    for &t in mesh.triangles() {
        if degenerate(p, t) {
            report.dropped_degenerate += 1;
        } else {
            tris.push(t);
        }
    }
    let mut edges: std::collections::HashMap<(u32, u32), Vec<usize>> =
        std::collections::HashMap::new();
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(i);
        }
    }
    if edges.values().any(|l| l.len() > 2) {
        return Err(CoreError::InvalidParameter {
            name: "mesh",
            reason: "an edge is shared by more than two triangles; this cannot be repaired".into(),
        });
    }
    let has_directed =
        |t: &[u32; 3], a: u32, b: u32| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b);
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
                        report.flipped += 1;
                    }
                    seen[j] = true;
                    queue.push_back(j);
                }
            }
        }
    }
    Ok((TriMesh::new(p.to_vec(), tris)?, report))
}
