//! The paper's edge pairing and its redundancy (gobron-chiba, "Edge
//! Communication" and "Comments on Data Transfer Problems", Figures 6–8).
//!
//! **Edge cells.** Along an edge, a triangle's edge cells are the cells the edge
//! runs through, one per grid line crossed along the edge's main axis (a digital
//! line: for an edge x from its grid's axes, x ≤ 45°, one per column, about
//! L cos x / h of them). Each is placed on the edge by projecting its square's
//! centre onto the edge: s ∈ [0, L] from the edge's lower-numbered vertex, the same
//! parameter on both sides.
//!
//! **Pairing (Figure 7).** A cell sends to the edge cell of the opposite triangle
//! whose projection is nearest its own — "the nearest projected cell of the
//! opposite input triangle", the ends clamped to the segment's extremities. Where
//! the sending side has more edge cells than the receiving side the map is
//! many-to-one and "some cells will receive information twice".
//!
//! **Redundancy (Figure 8).** For every interior edge, in the direction with more
//! senders, the share of senders whose receiver another sender already reaches.
//! For one grid along the edge and one x from it the counts are L/h and L cos x / h,
//! so the share is 1 − cos x, and over x uniform in [0, π/4] the paper's average
//! 1 − 2√2/π ≈ 9.9 % — here counted on the grids, not from the formula.
//! [`super::CellStats::paper_redundancy`] reports it whichever [`Pairing`] links
//! the cells.

use super::*;

/// How cells are linked across triangle edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Pairing {
    /// Each side neighbour's position, unfolded across the edge into the
    /// neighbour triangle's plane, links to the cell containing it (2-D, nearly
    /// one-to-one: ≈ 2.4 % redundancy on the paper's set-up).
    #[default]
    Unfolded,
    /// The paper's Figure 7: the neighbour position projected onto the shared
    /// edge links to the opposite edge cell with the nearest projection (1-D,
    /// many-to-one where the grids' densities along the edge differ).
    Paper,
}

impl Pairing {
    /// The name reports and the `--pairing` option use.
    pub fn name(self) -> &'static str {
        match self {
            Pairing::Unfolded => "unfolded",
            Pairing::Paper => "paper",
        }
    }
}

/// Edge cells of one triangle along one edge: (s, cell), sorted by s.
pub(super) type EdgeCells = Vec<(f64, u32)>;

/// The shared edge of frame `f`'s edge `e` in its local coordinates: the start
/// (the lower-numbered vertex), the unit direction and the length.
fn shared_edge(f: &Frame, e: usize) -> (V2, V2, f64) {
    let (ka, kb) = (e, (e + 1) % 3);
    let (a, b) = if f.verts[ka] < f.verts[kb] {
        (f.local[ka], f.local[kb])
    } else {
        (f.local[kb], f.local[ka])
    };
    let d = [b[0] - a[0], b[1] - a[1]];
    let len = d[0].hypot(d[1]);
    (a, [d[0] / len, d[1] / len], len)
}

/// The parameter of `q` projected onto the shared edge of `f`'s edge `e`,
/// clamped to the segment.
pub(super) fn edge_parameter(f: &Frame, e: usize, q: V2) -> f64 {
    let (a, u, len) = shared_edge(f, e);
    ((q[0] - a[0]) * u[0] + (q[1] - a[1]) * u[1]).clamp(0.0, len)
}

/// The edge cells of `f` along its edge `e` (see the module docs).
pub(super) fn edge_cells(f: &Frame, e: usize, h: f64) -> EdgeCells {
    let (a, u, len) = shared_edge(f, e);
    // Inward normal: towards the third corner.
    let third = f.local[(e + 2) % 3];
    let mut n = [-u[1], u[0]];
    if (third[0] - a[0]) * n[0] + (third[1] - a[1]) * n[1] < 0.0 {
        n = [u[1], -u[0]];
    }
    let main = if u[0].abs() >= u[1].abs() { 0 } else { 1 };
    let origin = if main == 0 { f.x0 } else { 0.0 };
    let (lo, hi) = {
        let (p, q) = (a[main], a[main] + len * u[main]);
        (p.min(q), p.max(q))
    };
    let first = ((lo - origin) / h - 0.5).ceil() as i64;
    let last = ((hi - origin) / h - 0.5).floor() as i64;
    let nudge = 1e-9 * h;
    let mut out: EdgeCells = Vec::new();
    for line in first..=last {
        let c = origin + (line as f64 + 0.5) * h;
        let s = (c - a[main]) / u[main];
        let p = [
            a[0] + s * u[0] + nudge * n[0],
            a[1] + s * u[1] + nudge * n[1],
        ];
        let Some((i, j)) = f.cell_at(p, h) else {
            continue;
        };
        if let Some(cell) = f.get(i, j) {
            let centre = [f.x0 + (i as f64 + 0.5) * h, (j as f64 + 0.5) * h];
            out.push((edge_parameter(f, e, centre), cell));
        }
    }
    out.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    out.dedup_by_key(|x| x.1);
    out
}

/// The edge cell of `list` whose parameter is nearest `s` (ties: the lower one).
pub(super) fn nearest_projected(list: &EdgeCells, s: f64) -> Option<u32> {
    let k = list.partition_point(|x| x.0 < s);
    let below = k.checked_sub(1).map(|k| list[k]);
    let above = list.get(k).copied();
    match (below, above) {
        (Some(b), Some(a)) => Some(if s - b.0 <= a.0 - s { b.1 } else { a.1 }),
        (Some(x), None) | (None, Some(x)) => Some(x.1),
        (None, None) => None,
    }
}

/// Edge cells of every (triangle, edge) that has a neighbour across it.
pub(super) fn all_edge_cells(
    frames: &[Frame],
    edges: &EdgeMap,
    h: f64,
) -> std::collections::HashMap<(u32, usize), EdgeCells> {
    use rayon::prelude::*;
    let sides: Vec<(u32, usize)> = edges
        .values()
        .filter(|l| l.len() == 2)
        .flatten()
        .copied()
        .collect();
    sides
        .into_par_iter()
        .map(|(t, e)| ((t, e), edge_cells(&frames[t as usize], e, h)))
        .collect()
}

/// Senders and redundant receptions of one direction: every sender to the
/// nearest projected receiver.
fn direction_counts(from: &EdgeCells, to: &EdgeCells) -> (usize, usize) {
    let mut receivers: Vec<u32> = from
        .iter()
        .filter_map(|&(s, _)| nearest_projected(to, s))
        .collect();
    let sent = receivers.len();
    receivers.sort_unstable();
    receivers.dedup();
    (sent, sent - receivers.len())
}

/// The paper's redundancy over every interior edge (see the module docs).
pub(super) fn paper_redundancy(
    edges: &EdgeMap,
    cells: &std::collections::HashMap<(u32, usize), EdgeCells>,
) -> f64 {
    let (mut sent, mut twice) = (0usize, 0usize);
    let mut keys: Vec<&(u32, u32)> = edges.keys().collect();
    keys.sort_unstable();
    for key in keys {
        let [x, y] = edges[key].as_slice() else {
            continue;
        };
        let (Some(a), Some(b)) = (cells.get(x), cells.get(y)) else {
            continue;
        };
        let (from, to) = if a.len() >= b.len() { (a, b) } else { (b, a) };
        let (s, r) = direction_counts(from, to);
        sent += s;
        twice += r;
    }
    if sent > 0 {
        twice as f64 / sent as f64
    } else {
        0.0
    }
}

/// One angle of [`figure8`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Figure8Point {
    /// x, the angle between the two grids (radians).
    pub x: f64,
    /// The paper's 1 − cos x.
    pub estimate: f64,
    /// The paper's measure, mean over the grid placements.
    pub paper: f64,
    /// Its standard deviation over the placements (one placement's sampling error).
    pub paper_sd: f64,
    /// asperity's unfolded links' redundancy, mean over the placements.
    pub unfolded: f64,
    /// The paper's links' redundancy, mean over the placements.
    pub paper_links: f64,
}

/// Cells along the shared edge in [`figure8`].
pub const FIGURE8_CELLS: f64 = 100.0;

/// The paper's Figure 8 measured: two triangles sharing an edge of about
/// [`FIGURE8_CELLS`] cells, one grid along the edge and the other x from it, for
/// `angles` values of x at the midpoints of [0, π/4]; each angle over
/// `placements` edge lengths 100 + 0.37k cells (so the grid lines cross the
/// edge at different offsets), both pairings built.
///
/// # Errors
/// The memory budget (each build holds about 10⁴ cells).
pub fn figure8(
    angles: usize,
    placements: usize,
    budget: &MemoryBudget,
) -> Result<Vec<Figure8Point>, CoreError> {
    let placements = placements.max(1);
    (0..angles)
        .map(|k| {
            let x = std::f64::consts::FRAC_PI_4 * (k as f64 + 0.5) / angles as f64;
            let mut paper = Vec::with_capacity(placements);
            let (mut unfolded, mut paper_links) = (0.0, 0.0);
            for j in 0..placements {
                let l = FIGURE8_CELLS + 0.37 * j as f64;
                let mesh = TriMesh::new(
                    vec![
                        [0.0, 0.0, 0.0],
                        [l, 0.0, 0.0],
                        [l / 2.0, l, 0.0],
                        [-l * x.cos(), -l * x.sin(), 0.0],
                    ],
                    vec![[0, 1, 2], [3, 0, 1]],
                )?;
                let a = build_with(&mesh, CellSize::Size(1.0), Pairing::Unfolded, budget)?;
                let b = build_with(&mesh, CellSize::Size(1.0), Pairing::Paper, budget)?;
                paper.push(a.stats.paper_redundancy);
                unfolded += a.stats.pairing_redundancy;
                paper_links += b.stats.pairing_redundancy;
            }
            let n = placements as f64;
            let mean = paper.iter().sum::<f64>() / n;
            let var = paper.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
            Ok(Figure8Point {
                x,
                estimate: 1.0 - x.cos(),
                paper: mean,
                paper_sd: var.sqrt(),
                unfolded: unfolded / n,
                paper_links: paper_links / n,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_projected_breaks_ties_downwards() {
        let list: EdgeCells = vec![(0.5, 7), (1.5, 8), (2.5, 9)];
        assert_eq!(nearest_projected(&list, 0.0), Some(7));
        assert_eq!(nearest_projected(&list, 1.0), Some(7));
        assert_eq!(nearest_projected(&list, 1.01), Some(8));
        assert_eq!(nearest_projected(&list, 9.0), Some(9));
        assert_eq!(nearest_projected(&Vec::new(), 1.0), None);
    }

    #[test]
    fn many_to_one_counts_the_second_receptions() {
        // Four senders one apart onto two receivers two apart: two receive twice.
        let from: EdgeCells = (0..4).map(|k| (k as f64 + 0.5, k)).collect();
        let to: EdgeCells = vec![(1.0, 10), (3.0, 11)];
        assert_eq!(direction_counts(&from, &to), (4, 2));
        assert_eq!(direction_counts(&to, &from), (2, 0));
    }
}
