//! Watershed segmentation of a height field into motifs, and Wolf pruning
//! (ISO 25178-2:2021 §5.3–5.4, Table 2; Scott, "Pattern analysis and
//! metrology: the extraction of stable features from observable
//! measurements", Proc. R. Soc. A 460, 2004; Wolf, "A Fortran subroutine for
//! cartographic generalization", Computers & Geosciences 17, 1991).
//!
//! The segmentation works on *dales* — the catchment basins of the field —
//! and finds hills as the dales of the negated field.
//!
//! 1. **Descent.** Every point drains to the 8-neighbour of steepest descent:
//!    the largest (z − z_q)/|p − q| over the neighbours q, the physical
//!    distance counting the spacing, so a diagonal step counts √(dx² + dy²).
//!    A point with no lower neighbour is a pit; neighbouring pits share a
//!    height and form one pit (a flat-bottomed dale).
//! 2. **Dales.** Each point belongs to the pit its descent reaches: the
//!    change tree's leaves (Scott 2004).
//! 3. **Saddles.** Two dales meet where two neighbouring points carry their
//!    labels; the water poured into one spills into the other at the higher
//!    of the two heights, and the pair's saddle is the lowest such pour
//!    height along their common border.
//! 4. **Wolf pruning.** A dale's local depth is its lowest saddle minus its
//!    pit. While the shallowest dale is shallower than the threshold
//!    (ISO 25178-3's default: 5 % of Sz), it is merged into the dale across
//!    its lowest saddle, which keeps the deeper pit; the merged dale's saddles
//!    are the lower of the two dales' saddles to each neighbour. The dales
//!    left are the significant ones.
//!
//! Missing points belong to no dale and border the dales around them as the
//! field's edge does: a motif touching either is *incomplete*, which ISO's
//! feature parameters leave out by default. A periodic field wraps, and has no
//! edge. Ties (equal slopes, equal depths, equal saddles) go to the first in
//! the fixed order of neighbours, labels and points, so the segmentation is
//! the same at any thread count.
//!
//! Written here rather than taken from a crate: the image-processing crates'
//! watersheds (e.g. `imageproc`'s) flood from markers on integer images, and
//! have neither the saddle graph nor Wolf pruning, which are the algorithm.

use std::cmp::{Ordering, Reverse};
use std::collections::{BTreeMap, BinaryHeap};

use asperity_core::HeightField;
use rayon::prelude::*;

/// The label of a point in no motif (a missing point).
pub const NO_MOTIF: u32 = u32::MAX;

/// The 8 neighbours' offsets, in the order ties are broken.
const NEIGHBOURS: [(isize, isize); 8] = [
    (-1, -1),
    (0, -1),
    (1, -1),
    (-1, 0),
    (1, 0),
    (-1, 1),
    (0, 1),
    (1, 1),
];

/// One significant motif: a dale, or a hill of the negated field.
#[derive(Clone, Debug, PartialEq)]
pub struct Motif {
    /// The row-major index of its pit (its peak, for a hill).
    pub critical: usize,
    /// The height of its pit, in the segmented (dale) orientation.
    pub depth_at: f64,
    /// Its lowest saddle in the same orientation (∞ for a motif without a
    /// neighbour: a field that is one motif).
    pub saddle: f64,
    /// The number of points it holds.
    pub points: usize,
    /// Σ max(0, saddle − z) over its points: the volume of water it holds
    /// up to its saddle, in height × points (times dx·dy for a volume).
    pub volume: f64,
    /// Whether it touches the field's edge or a missing point.
    pub incomplete: bool,
}

/// The significant motifs and the motif of every point.
#[derive(Clone, Debug)]
pub struct Segmentation {
    /// Per point, its motif's index in `motifs`, or [`NO_MOTIF`].
    pub labels: Vec<u32>,
    /// The motifs, in the order of their first point.
    pub motifs: Vec<Motif>,
    /// The dales found before pruning.
    pub unpruned: usize,
}

/// The heights segmented, read with a sign (−1: the hills of the field,
/// segmented as the dales of its negation) without a negated copy.
#[derive(Clone, Copy)]
pub struct Heights<'a> {
    z: &'a [f64],
    sign: f64,
}

impl<'a> Heights<'a> {
    /// The dales of `z` (row-major; NaN for missing points).
    pub fn dales(z: &'a [f64]) -> Self {
        Self { z, sign: 1.0 }
    }
    /// The hills of `z`: the dales of −z.
    pub fn hills(z: &'a [f64]) -> Self {
        Self { z, sign: -1.0 }
    }
    #[inline]
    fn at(&self, p: usize) -> f64 {
        self.sign * self.z[p]
    }
    fn len(&self) -> usize {
        self.z.len()
    }
}

/// The geometry the segmentation walks: dimensions, periodicity and the
/// distance of each neighbour.
struct Lattice {
    nx: usize,
    ny: usize,
    periodic: bool,
    distance: [f64; 8],
}

impl Lattice {
    fn new(h: &HeightField, periodic: bool) -> Self {
        let [dx, dy] = h.spacing();
        let distance =
            NEIGHBOURS.map(|(a, b)| ((a as f64 * dx).powi(2) + (b as f64 * dy).powi(2)).sqrt());
        Self {
            nx: h.nx(),
            ny: h.ny(),
            periodic,
            distance,
        }
    }

    /// The index of neighbour `k` of point (i, j), if it lies in the field.
    #[inline]
    fn neighbour(&self, i: usize, j: usize, k: usize) -> Option<usize> {
        let (a, b) = NEIGHBOURS[k];
        let wrap = |v: usize, d: isize, n: usize| -> Option<usize> {
            let w = v as isize + d;
            if (0..n as isize).contains(&w) {
                Some(w as usize)
            } else if self.periodic && n > 2 {
                Some(w.rem_euclid(n as isize) as usize)
            } else {
                None
            }
        };
        Some(wrap(j, b, self.ny)? * self.nx + wrap(i, a, self.nx)?)
    }
}

/// Segments `z` (over `h`'s grid) into
/// dales and prunes those shallower than `threshold` (Wolf pruning). The
/// field has fewer than 2³² points (indices are held as `u32`).
pub fn dales(h: &HeightField, z: Heights, periodic: bool, threshold: f64) -> Segmentation {
    let lattice = Lattice::new(h, periodic);
    let down = descent(&lattice, z);
    let (basin, pits) = basins(&lattice, z, &down);
    let mut graph = Graph::new(&lattice, z, &basin, &pits);
    let unpruned = pits.len();
    graph.prune(threshold);
    graph.into_segmentation(z, basin, unpruned)
}

/// Per point, the neighbour it drains to (itself for a pit or a missing point).
fn descent(l: &Lattice, z: Heights) -> Vec<u32> {
    let nx = l.nx;
    let inverse = l.distance.map(|d| 1.0 / d);
    // inside the field the neighbours are fixed offsets (the edges, and a
    // field that wraps, go through `Lattice::neighbour`)
    let offsets = NEIGHBOURS.map(|(a, b)| b * nx as isize + a);
    let mut down = vec![0u32; z.len()];
    down.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        let inner_row = j > 0 && j + 1 < l.ny;
        for (i, d) in row.iter_mut().enumerate() {
            let p = j * nx + i;
            *d = p as u32;
            let here = z.at(p);
            if here.is_nan() {
                continue;
            }
            let mut steepest = 0.0;
            let mut consider = |k: usize, q: usize| {
                let slope = (here - z.at(q)) * inverse[k];
                if slope > steepest {
                    (steepest, *d) = (slope, q as u32);
                }
            };
            if inner_row && i > 0 && i + 1 < nx {
                for (k, o) in offsets.iter().enumerate() {
                    consider(k, p.wrapping_add_signed(*o));
                }
            } else {
                for k in 0..8 {
                    if let Some(q) = l.neighbour(i, j, k) {
                        consider(k, q);
                    }
                }
            }
        }
    });
    down
}

/// A pit: its first point and its height.
#[derive(Clone, Copy, Debug)]
struct Pit {
    at: usize,
    z: f64,
}

/// Per point its dale (the pit its descent reaches; [`NO_MOTIF`] for a missing
/// point), and the pits, numbered in the order of their first point.
fn basins(l: &Lattice, z: Heights, down: &[u32]) -> (Vec<u32>, Vec<Pit>) {
    let mut basin = vec![NO_MOTIF; z.len()];
    let mut pits = Vec::new();
    let mut queue = Vec::new();
    for p in 0..z.len() {
        if down[p] as usize != p || z.at(p).is_nan() || basin[p] != NO_MOTIF {
            continue;
        }
        // a new pit: every neighbouring pit point at its height joins it
        let label = pits.len() as u32;
        pits.push(Pit { at: p, z: z.at(p) });
        basin[p] = label;
        queue.push(p);
        while let Some(q) = queue.pop() {
            for k in 0..8 {
                let Some(r) = l.neighbour(q % l.nx, q / l.nx, k) else {
                    continue;
                };
                if down[r] as usize == r && basin[r] == NO_MOTIF && z.at(r) == z.at(q) {
                    basin[r] = label;
                    queue.push(r);
                }
            }
        }
    }
    let mut path = Vec::new();
    for p in 0..z.len() {
        let mut q = p;
        while basin[q] == NO_MOTIF && !z.at(q).is_nan() {
            path.push(q);
            q = down[q] as usize;
        }
        let label = basin[q];
        for r in path.drain(..) {
            basin[r] = label;
        }
    }
    (basin, pits)
}

/// A local depth on the pruning heap, ordered by depth then label.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Depth(f64, u32, u32);

impl Eq for Depth {}
impl PartialOrd for Depth {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Depth {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0
            .total_cmp(&other.0)
            .then(self.1.cmp(&other.1))
            .then(self.2.cmp(&other.2))
    }
}

/// The dales' saddle graph while pruning.
struct Graph {
    /// Per dale, its neighbours and the saddle to each.
    saddles: Vec<BTreeMap<u32, f64>>,
    /// Per dale, its lowest saddle and the neighbour across it (kept as dales
    /// merge, so the heap never rescans a large dale's border).
    low: Vec<Option<(f64, u32)>>,
    /// Per dale, its pit (the deepest of the dales merged into it).
    pits: Vec<Pit>,
    /// Per dale, the dale it was merged into (itself while alive).
    merged_into: Vec<u32>,
    /// Per dale, whether one of its points touches the edge or a missing point.
    incomplete: Vec<bool>,
}

impl Graph {
    fn new(l: &Lattice, z: Heights, basin: &[u32], pits: &[Pit]) -> Self {
        let n = pits.len();
        // the pairs come sorted by (lower, higher) label, so each dale's
        // neighbours arrive in increasing order and the maps are bulk-built
        let mut sorted: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
        for (a, b, pour) in borders(l, z, basin) {
            sorted[a as usize].push((b, pour));
            sorted[b as usize].push((a, pour));
        }
        let saddles: Vec<BTreeMap<u32, f64>> = sorted
            .into_par_iter()
            .map(|v| v.into_iter().collect())
            .collect();
        let mut g = Self {
            saddles,
            low: vec![None; n],
            pits: pits.to_vec(),
            merged_into: (0..n as u32).collect(),
            incomplete: incomplete(l, z, basin, n),
        };
        g.low = (0..n as u32).into_par_iter().map(|d| g.lowest(d)).collect();
        g
    }

    /// The lowest saddle of dale `d` and the neighbour across it (the first
    /// label of equal saddles), from its border.
    fn lowest(&self, d: u32) -> Option<(f64, u32)> {
        let mut best: Option<(f64, u32)> = None;
        for (&to, &s) in &self.saddles[d as usize] {
            if best.is_none_or(|(b, _)| s < b) {
                best = Some((s, to));
            }
        }
        best
    }

    fn depth(&self, d: u32) -> Option<f64> {
        self.low[d as usize].map(|(s, _)| s - self.pits[d as usize].z)
    }

    /// Merges every dale shallower than `threshold`, the shallowest first.
    fn prune(&mut self, threshold: f64) {
        let mut version = vec![0u32; self.pits.len()];
        let mut heap: BinaryHeap<Reverse<Depth>> = (0..self.pits.len() as u32)
            .filter_map(|d| Some(Reverse(Depth(self.depth(d)?, d, 0))))
            .collect();
        while let Some(Reverse(Depth(depth, d, v))) = heap.pop() {
            if v != version[d as usize] || self.merged_into[d as usize] != d {
                continue;
            }
            if depth >= threshold {
                break;
            }
            let Some((_, into)) = self.low[d as usize] else {
                continue;
            };
            self.merge(d, into);
            version[into as usize] += 1;
            if let Some(depth) = self.depth(into) {
                heap.push(Reverse(Depth(depth, into, version[into as usize])));
            }
        }
    }

    /// Merges dale `d` into its neighbour `into`. A third dale's saddle to `d`
    /// becomes one to `into` (the lower of the two), which leaves its lowest
    /// saddle's height, and so its depth, as it was.
    fn merge(&mut self, d: u32, into: u32) {
        let moved = std::mem::take(&mut self.saddles[d as usize]);
        self.saddles[into as usize].remove(&d);
        let mut lowest_moved: Option<(f64, u32)> = None;
        for (other, s) in moved {
            if other == into {
                continue;
            }
            let o = &mut self.saddles[other as usize];
            o.remove(&d);
            let kept = o.get(&into).map_or(s, |t| t.min(s));
            o.insert(into, kept);
            self.saddles[into as usize].insert(other, kept);
            if let Some(low) = self.low[other as usize].as_mut().filter(|low| low.1 == d) {
                low.1 = into;
            }
            if lowest_moved.is_none_or(|(b, _)| kept < b) {
                lowest_moved = Some((kept, other));
            }
        }
        self.low[into as usize] = match self.low[into as usize] {
            Some((_, via)) if via == d => self.lowest(into),
            Some(low) if lowest_moved.is_none_or(|m| low.0 <= m.0) => Some(low),
            _ => lowest_moved,
        };
        self.low[d as usize] = None;
        let (pd, pi) = (self.pits[d as usize], self.pits[into as usize]);
        if pd.z < pi.z || (pd.z == pi.z && pd.at < pi.at) {
            self.pits[into as usize] = pd;
        }
        self.incomplete[into as usize] |= self.incomplete[d as usize];
        self.merged_into[d as usize] = into;
    }

    /// The dale each dale ended in.
    fn root(&self, mut d: u32) -> u32 {
        while self.merged_into[d as usize] != d {
            d = self.merged_into[d as usize];
        }
        d
    }

    fn into_segmentation(self, z: Heights, basin: Vec<u32>, unpruned: usize) -> Segmentation {
        let n = self.pits.len();
        let mut index = vec![NO_MOTIF; n];
        let mut motifs = Vec::new();
        let roots: Vec<u32> = (0..n as u32).map(|d| self.root(d)).collect();
        for &r in &roots {
            if index[r as usize] == NO_MOTIF {
                index[r as usize] = motifs.len() as u32;
                let pit = self.pits[r as usize];
                motifs.push(Motif {
                    critical: pit.at,
                    depth_at: pit.z,
                    saddle: self.low[r as usize].map_or(f64::INFINITY, |(s, _)| s),
                    points: 0,
                    volume: 0.0,
                    incomplete: self.incomplete[r as usize],
                });
            }
        }
        // each point's dale becomes its motif, in place
        let mut labels = basin;
        labels.par_iter_mut().for_each(|b| {
            if *b != NO_MOTIF {
                *b = index[roots[*b as usize] as usize];
            }
        });
        fill_volumes(&mut motifs, &labels, z);
        Segmentation {
            labels,
            motifs,
            unpruned,
        }
    }
}

/// Each motif's points and the water it holds up to its saddle (up to its
/// highest point for a motif without a saddle).
fn fill_volumes(motifs: &mut [Motif], labels: &[u32], z: Heights) {
    let mut top: Vec<f64> = motifs.iter().map(|m| m.saddle).collect();
    let unbounded: Vec<bool> = top.iter().map(|t| !t.is_finite()).collect();
    for (p, &m) in labels.iter().enumerate() {
        let h = z.at(p);
        if m != NO_MOTIF {
            motifs[m as usize].points += 1;
            if unbounded[m as usize] {
                let t = &mut top[m as usize];
                *t = if t.is_finite() { t.max(h) } else { h };
            }
        }
    }
    for (p, &m) in labels.iter().enumerate() {
        let h = z.at(p);
        if m != NO_MOTIF {
            motifs[m as usize].volume += (top[m as usize] - h).max(0.0);
        }
    }
}

/// Every pair of neighbouring points in different dales, once per pair of
/// dales, as (lower label, higher label, lowest pour height), sorted.
fn borders(l: &Lattice, z: Heights, basin: &[u32]) -> Vec<(u32, u32, f64)> {
    // each unordered pair of points once: the neighbours after the point in NEIGHBOURS' order
    const FORWARD: [usize; 4] = [4, 5, 6, 7];
    let rows: Vec<Vec<(u32, u32, f64)>> = (0..l.ny)
        .into_par_iter()
        .map(|j| {
            let mut out = Vec::new();
            for i in 0..l.nx {
                let p = j * l.nx + i;
                let a = basin[p];
                if a == NO_MOTIF {
                    continue;
                }
                for k in FORWARD {
                    let Some(q) = l.neighbour(i, j, k) else {
                        continue;
                    };
                    let b = basin[q];
                    if b != a && b != NO_MOTIF {
                        out.push((a.min(b), a.max(b), z.at(p).max(z.at(q))));
                    }
                }
            }
            // a boundary repeats its pair point after point: keep one, its lowest pour
            out.dedup_by(|later, kept| {
                let same = (later.0, later.1) == (kept.0, kept.1);
                if same {
                    kept.2 = kept.2.min(later.2);
                }
                same
            });
            out
        })
        .collect();
    // one allocation of the exact size (growing one would fault its pages in again and again)
    let mut pairs = Vec::with_capacity(rows.iter().map(Vec::len).sum());
    for row in rows {
        pairs.extend(row);
    }
    sort_pairs(&mut pairs);
    pairs
}

/// Per dale, whether it touches the edge of a field that does not wrap or a
/// missing point.
fn incomplete(l: &Lattice, z: Heights, basin: &[u32], dales: usize) -> Vec<bool> {
    let mut out = vec![false; dales];
    let mut mark = |p: usize| {
        if basin[p] != NO_MOTIF {
            out[basin[p] as usize] = true;
        }
    };
    if !l.periodic {
        for i in 0..l.nx {
            mark(i);
            mark((l.ny - 1) * l.nx + i);
        }
        for j in 0..l.ny {
            mark(j * l.nx);
            mark(j * l.nx + l.nx - 1);
        }
    }
    for p in (0..z.len()).filter(|&p| z.at(p).is_nan()) {
        for k in 0..8 {
            if let Some(q) = l.neighbour(p % l.nx, p / l.nx, k) {
                mark(q);
            }
        }
    }
    out
}

/// Sorts `pairs` and keeps one entry per pair of dales: the lowest pour height.
fn sort_pairs(pairs: &mut Vec<(u32, u32, f64)>) {
    pairs.par_sort_unstable_by(|x, y| (x.0, x.1).cmp(&(y.0, y.1)).then(x.2.total_cmp(&y.2)));
    pairs.dedup_by(|later, first| (later.0, later.1) == (first.0, first.1));
}
