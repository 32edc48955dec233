//! Algorithm 1 on a dense grid: the reference the sparse tagging
//! (`sparse::tagging`) is checked against.

use asperity_core::Progress;
use rayon::prelude::*;

use crate::distance::DistanceField;
use crate::grid::GridSpec;

use super::TagRule;

/// Node states.
const INTERIOR: u8 = 0;
const EXTERIOR: u8 = 2;
const REFUSED: u8 = 3;

/// The result of tagging.
#[derive(Clone, Debug)]
pub struct Tags {
    /// True for exterior nodes (Ω̄), x fastest.
    pub exterior: Vec<bool>,
    /// Nodes made exterior.
    pub exterior_count: usize,
    /// Nodes refused by the paper's neighbour rule (they stay interior).
    pub refused: usize,
}

/// Runs Algorithm 1 on `dist` with offset `eps` (world units).
pub fn tag(dist: &DistanceField, eps: f64, rule: TagRule, progress: &dyn Progress) -> Tags {
    let grid = &dist.grid;
    let d = &dist.values;
    let n = grid.len();
    let eps = eps as f32;
    let far = dist.cap;
    progress.start(n as u64, "tagging");
    // The ε rule's result, and a superset of the paper rule's: the flood fill of
    // {d ≥ ε} from the faces.
    let mut reach = vec![INTERIOR; n];
    let reached = flood_from_faces(grid, d, eps, &mut reach);
    if rule == TagRule::Threshold {
        progress.finish();
        return Tags {
            exterior: reach.into_iter().map(|s| s == EXTERIOR).collect(),
            exterior_count: reached,
            refused: 0,
        };
    }
    // The paper's rule. The far field, tied at the cap, is all accepted: it is
    // the flood fill of {d ≥ cap}.
    let mut state = vec![INTERIOR; n];
    let mut exterior_count = 0usize;
    if far.is_finite() && far >= eps {
        exterior_count = flood_from_faces(grid, d, far, &mut state);
    }
    progress.advance(exterior_count as u64);
    // The rest of the ε flood fill, by decreasing distance (ties: smaller index
    // first, as the heap's keys).
    let plane = grid.dims[0] * grid.dims[1];
    let mut keys: Vec<u64> = (0..grid.dims[2])
        .into_par_iter()
        .flat_map_iter(|k| {
            let (reach, state) = (&reach, &state);
            (k * plane..(k + 1) * plane)
                .filter(move |&u| reach[u] == EXTERIOR && state[u] != EXTERIOR)
                .map(|u| (u64::from(d[u].to_bits()) << 32) | u64::from(u32::MAX - u as u32))
        })
        .collect();
    drop(reach);
    keys.par_sort_unstable_by(|a, b| b.cmp(a));
    let (accepted, refused) = descend(grid, d, &keys, &mut state, progress);
    exterior_count += accepted;
    progress.finish();
    Tags {
        exterior: state.into_iter().map(|s| s == EXTERIOR).collect(),
        exterior_count,
        refused,
    }
}

/// A member of a group of equal distances not yet reached.
const PENDING: u8 = 4;
/// A member of such a group waiting on the group's worklist.
const QUEUED: u8 = 5;

/// How many nodes ahead [`descend`] prefetches.
const PREFETCH_AHEAD: usize = 16;

/// Decides the nodes of `keys` (heap keys in decreasing order) under the
/// paper's rule; returns (accepted, refused).
///
/// The queue of Algorithm 1 pops in non-increasing distance under this rule: a
/// node is accepted only when no non-exterior neighbour is farther, so every node
/// it adds to ∂Ω is at most as far. When the pops reach a node's distance, its
/// farther neighbours are therefore settled for good; it is on ∂Ω iff it lies on
/// a face or next to an exterior node, and it is accepted iff no farther
/// neighbour is non-exterior. So one pass in key order decides every node, and
/// the nodes of equal distance are decided together: those reached, then those
/// next to them that are accepted, a small flood (their order does not matter,
/// as equal distances never refuse each other).
fn descend(
    grid: &GridSpec,
    d: &[f32],
    keys: &[u64],
    state: &mut [u8],
    progress: &dyn Progress,
) -> (usize, usize) {
    let mut run = Descent {
        grid,
        strides: grid.strides(),
        d,
        state,
        accepted: 0,
        refused: 0,
        work: Vec::new(),
    };
    let mut i = 0;
    while i < keys.len() {
        run.prefetch(keys.get(i + PREFETCH_AHEAD));
        let level = keys[i] >> 32;
        let mut j = i + 1;
        while j < keys.len() && keys[j] >> 32 == level {
            j += 1;
        }
        if j == i + 1 {
            run.decide_one(node(keys[i]));
        } else {
            run.decide_group(&keys[i..j]);
        }
        if i >> 20 != j >> 20 {
            progress.advance(1 << 20);
        }
        i = j;
    }
    (run.accepted, run.refused)
}

/// The node of a heap key.
#[inline(always)]
fn node(key: u64) -> usize {
    (u32::MAX - key as u32) as usize
}

/// No neighbour (beyond the grid).
const NONE: usize = usize::MAX;

/// The pass of [`descend`]: the state it updates and its counts.
struct Descent<'a> {
    grid: &'a GridSpec,
    strides: [usize; 3],
    d: &'a [f32],
    state: &'a mut [u8],
    accepted: usize,
    refused: usize,
    work: Vec<usize>,
}

impl Descent<'_> {
    /// The six face neighbours of `u` ([`NONE`] beyond the grid), and whether
    /// `u` lies on a face of the grid.
    #[inline(always)]
    fn neighbours(&self, u: usize) -> ([usize; 6], bool) {
        let c = self.grid.coords(u);
        let mut nb = [NONE; 6];
        for a in 0..3 {
            if c[a] > 0 {
                nb[2 * a] = u - self.strides[a];
            }
            if c[a] + 1 < self.grid.dims[a] {
                nb[2 * a + 1] = u + self.strides[a];
            }
        }
        (nb, self.grid.on_boundary(c))
    }

    /// On ∂Ω: on a face or next to an exterior node.
    #[inline(always)]
    fn reached(&self, (nb, face): ([usize; 6], bool)) -> bool {
        face || nb
            .into_iter()
            .filter(|v| *v != NONE)
            .any(|v| self.state[v] == EXTERIOR)
    }

    /// Line 4 of Algorithm 1: a farther neighbour is not exterior.
    #[inline(always)]
    fn refused_at(&self, u: usize, nb: [usize; 6]) -> bool {
        nb.into_iter()
            .filter(|v| *v != NONE)
            .any(|v| self.state[v] != EXTERIOR && self.d[v] > self.d[u])
    }

    /// The neighbourhood of the node a few places on: neighbourhoods are
    /// scattered over the shell, and a sorted list (unlike a heap) says which
    /// come next.
    #[inline(always)]
    fn prefetch(&self, ahead: Option<&u64>) {
        let Some(&ahead) = ahead else { return };
        let (w, s) = (node(ahead), self.strides);
        for at in [w, w.wrapping_sub(s[1]), w + s[1]] {
            asperity_core::memory_hints::prefetch(self.state, at);
            asperity_core::memory_hints::prefetch(self.d, at);
        }
        for at in [w.wrapping_sub(s[2]), w + s[2]] {
            asperity_core::memory_hints::prefetch(self.state, at);
            asperity_core::memory_hints::prefetch(self.d, at);
        }
    }

    /// Decides node `u`, alone at its distance.
    #[inline(always)]
    fn decide_one(&mut self, u: usize) {
        let around = self.neighbours(u);
        if self.reached(around) {
            if self.refused_at(u, around.0) {
                self.state[u] = REFUSED;
                self.refused += 1;
            } else {
                self.state[u] = EXTERIOR;
                self.accepted += 1;
            }
        }
    }

    /// Decides the nodes of equal distance together: those reached, then those
    /// next to them that are accepted (a small flood).
    fn decide_group(&mut self, group: &[u64]) {
        for &key in group {
            self.state[node(key)] = PENDING;
        }
        let mut work = std::mem::take(&mut self.work);
        work.extend(
            group
                .iter()
                .map(|&k| node(k))
                .filter(|&u| self.reached(self.neighbours(u))),
        );
        for &u in &work {
            self.state[u] = QUEUED;
        }
        while let Some(u) = work.pop() {
            let (nb, _) = self.neighbours(u);
            if self.refused_at(u, nb) {
                self.state[u] = REFUSED;
                self.refused += 1;
                continue;
            }
            self.state[u] = EXTERIOR;
            self.accepted += 1;
            for v in nb.into_iter().filter(|v| *v != NONE) {
                if self.state[v] == PENDING {
                    self.state[v] = QUEUED;
                    work.push(v);
                }
            }
        }
        self.work = work;
        for &key in group {
            if self.state[node(key)] == PENDING {
                self.state[node(key)] = INTERIOR;
            }
        }
    }
}

/// Consecutive nodes `start .. start + len` of one row of a plane (indices
/// within the plane).
#[derive(Clone, Copy, Debug)]
struct Span {
    start: u32,
    len: u32,
}

/// Marks `EXTERIOR` the nodes of {d ≥ far} connected to the grid's faces within
/// it (6-connected) and returns their count. Each round fills every plane from
/// its seeds in parallel (4-connected, within the plane, by spans of a row at a
/// time: a scanline fill), then seeds the planes above and below with the open
/// nodes under the spans the fill reached; it ends when no plane gains a seed.
/// The result is the connected set whatever the order, so it does not depend on
/// the thread count.
fn flood_from_faces(grid: &GridSpec, d: &[f32], far: f32, state: &mut [u8]) -> usize {
    let [nx, ny, nz] = grid.dims;
    let plane = nx * ny;
    let whole = |j: usize| Span {
        start: (j * nx) as u32,
        len: nx as u32,
    };
    // Round 0's seeds: the faces (whole planes at the ends, else the first and
    // last rows and the two end nodes of every other row).
    let mut seeds: Vec<Vec<Span>> = (0..nz)
        .map(|k| {
            if k == 0 || k + 1 == nz {
                return (0..ny).map(whole).collect();
            }
            let mut s = vec![whole(0)];
            for j in 1..ny.saturating_sub(1) {
                s.push(Span {
                    start: (j * nx) as u32,
                    len: 1,
                });
                if nx > 1 {
                    s.push(Span {
                        start: (j * nx + nx - 1) as u32,
                        len: 1,
                    });
                }
            }
            if ny > 1 {
                s.push(whole(ny - 1));
            }
            s
        })
        .collect();
    let mut total = 0usize;
    loop {
        let filled: Vec<Vec<Span>> = state
            .par_chunks_mut(plane)
            .zip(seeds.par_iter())
            .enumerate()
            .map(|(k, (st, seeds))| fill_plane(st, &d[k * plane..(k + 1) * plane], far, nx, seeds))
            .collect();
        total += filled
            .iter()
            .flatten()
            .map(|s| s.len as usize)
            .sum::<usize>();
        let state = &*state;
        seeds = (0..nz)
            .into_par_iter()
            .map(|k| {
                let (st, dk) = (
                    &state[k * plane..(k + 1) * plane],
                    &d[k * plane..(k + 1) * plane],
                );
                let below = k.checked_sub(1).map(|b| &filled[b]);
                let above = filled.get(k + 1);
                let mut next = Vec::new();
                for span in below.into_iter().chain(above).flatten() {
                    open_runs(st, dk, far, *span, &mut next);
                }
                next
            })
            .collect();
        if seeds.iter().all(Vec::is_empty) {
            return total;
        }
    }
}

/// Whether node `m` of a plane is still open to the far-field fill.
#[inline]
fn open(st: &[u8], dk: &[f32], far: f32, m: usize) -> bool {
    st[m] == INTERIOR && dk[m] >= far
}

/// Appends the maximal open runs within `span` to `out`.
fn open_runs(st: &[u8], dk: &[f32], far: f32, span: Span, out: &mut Vec<Span>) {
    let (s, e) = (span.start as usize, (span.start + span.len) as usize);
    let mut m = s;
    while m < e {
        if !open(st, dk, far, m) {
            m += 1;
            continue;
        }
        let a = m;
        while m < e && open(st, dk, far, m) {
            m += 1;
        }
        out.push(Span {
            start: a as u32,
            len: (m - a) as u32,
        });
    }
}

/// Fills one plane (4-connected) from the open nodes of `seeds`, a row span at
/// a time; returns the spans filled.
fn fill_plane(st: &mut [u8], dk: &[f32], far: f32, nx: usize, seeds: &[Span]) -> Vec<Span> {
    let ny = st.len() / nx;
    let mut stack: Vec<Span> = Vec::new();
    for &span in seeds {
        open_runs(st, dk, far, span, &mut stack);
    }
    let mut filled = Vec::new();
    while let Some(seed) = stack.pop() {
        let m = seed.start as usize;
        if !open(st, dk, far, m) {
            continue;
        }
        // Widen to the whole open run of the row.
        let row = m - m % nx;
        let (mut a, mut b) = (m, m + 1);
        while a > row && open(st, dk, far, a - 1) {
            a -= 1;
        }
        while b < row + nx && open(st, dk, far, b) {
            b += 1;
        }
        st[a..b].fill(EXTERIOR);
        filled.push(Span {
            start: a as u32,
            len: (b - a) as u32,
        });
        let j = row / nx;
        let len = (b - a) as u32;
        if j > 0 {
            let start = (a - nx) as u32;
            open_runs(st, dk, far, Span { start, len }, &mut stack);
        }
        if j + 1 < ny {
            let start = (a + nx) as u32;
            open_runs(st, dk, far, Span { start, len }, &mut stack);
        }
    }
    filled
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::{BinaryHeap, VecDeque};

    const BOUNDARY: u8 = 1;
    use crate::distance::{DistanceMethod, unsigned_distance};
    use crate::grid::{GridSpec, Sizing};
    use asperity_core::{MemoryBudget, NoProgress};

    /// Points on a sphere of radius 3 with a cup cut out, plus a separate blob.
    fn shape() -> Vec<[f64; 3]> {
        let mut pts = Vec::new();
        let n = 60;
        for a in 0..n {
            for b in 0..n {
                let th = std::f64::consts::PI * (a as f64 + 0.5) / n as f64;
                let ph = 2.0 * std::f64::consts::PI * b as f64 / n as f64;
                let p = [
                    3.0 * th.sin() * ph.cos(),
                    3.0 * th.sin() * ph.sin(),
                    3.0 * th.cos(),
                ];
                if p[2] < 2.2 {
                    pts.push(p);
                }
            }
        }
        pts.push([6.0, 0.0, 0.0]);
        pts
    }

    /// Breadth-first flood fill of {d ≥ ε} from the boundary: the reference.
    fn flood(dist: &DistanceField, eps: f32) -> Vec<bool> {
        let g = &dist.grid;
        let mut ext = vec![false; g.len()];
        let mut queue = VecDeque::new();
        for (u, e) in ext.iter_mut().enumerate() {
            if g.on_boundary(g.coords(u)) && dist.values[u] >= eps {
                *e = true;
                queue.push_back(u);
            }
        }
        while let Some(u) = queue.pop_front() {
            let c = g.coords(u);
            for a in 0..3 {
                for s in [-1i64, 1] {
                    let mut q = c;
                    let x = c[a] as i64 + s;
                    if x < 0 || x >= g.dims[a] as i64 {
                        continue;
                    }
                    q[a] = x as usize;
                    let v = g.index(q[0], q[1], q[2]);
                    if !ext[v] && dist.values[v] >= eps {
                        ext[v] = true;
                        queue.push_back(v);
                    }
                }
            }
        }
        ext
    }

    fn field(res: usize) -> DistanceField {
        let pts = shape();
        let grid = GridSpec::around(
            &pts,
            Sizing::Resolution(res),
            |h| (2.0 / h) as usize + 4,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        unsigned_distance(&pts, &grid, DistanceMethod::ClosestPoint, 10.0, &NoProgress)
    }

    /// Algorithm 1 with one binary heap and nothing else (no flood fills, no
    /// sorted pass): the reference for the fast paths. The exterior and the
    /// refused count.
    fn heap_only(dist: &DistanceField, eps: f32, rule: TagRule) -> (Vec<bool>, usize) {
        let g = &dist.grid;
        let d = &dist.values;
        let key = |u: usize| (u64::from(d[u].to_bits()) << 32) | u64::from(u32::MAX - u as u32);
        let mut state = vec![INTERIOR; g.len()];
        let mut heap = BinaryHeap::new();
        let mut refused = 0;
        for (u, s) in state.iter_mut().enumerate() {
            if g.on_boundary(g.coords(u)) {
                *s = BOUNDARY;
                heap.push(key(u));
            }
        }
        while let Some(top) = heap.pop() {
            let u = (u32::MAX - top as u32) as usize;
            if d[u] < eps {
                break;
            }
            let c = g.coords(u);
            let nb: Vec<usize> = (0..3)
                .flat_map(|a| {
                    let s = g.strides()[a];
                    [
                        (c[a] > 0).then(|| u - s),
                        (c[a] + 1 < g.dims[a]).then(|| u + s),
                    ]
                })
                .flatten()
                .collect();
            if rule == TagRule::Paper && nb.iter().any(|&v| state[v] != EXTERIOR && d[v] > d[u]) {
                state[u] = REFUSED;
                refused += 1;
                continue;
            }
            state[u] = EXTERIOR;
            for v in nb {
                if state[v] == INTERIOR {
                    state[v] = BOUNDARY;
                    heap.push(key(v));
                }
            }
        }
        (state.into_iter().map(|s| s == EXTERIOR).collect(), refused)
    }

    /// The flood fills and the sorted pass give the result of the plain heap,
    /// for caps that leave a large far field, pockets beyond the cap inside the
    /// shape, a cap beyond the cup's centre (where the paper's rule refuses),
    /// no cap at all, distances rounded to 1/8 cell (many ties), and both rules.
    #[test]
    fn fast_paths_equal_the_plain_algorithm() {
        let pts = shape();
        let grid = GridSpec::around(
            &pts,
            Sizing::Resolution(36),
            |h| (2.0 / h) as usize + 4,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let mut fields = Vec::new();
        for cap in [0.5, 0.9, 1.6, 10.0] {
            fields.push(unsigned_distance(
                &pts,
                &grid,
                DistanceMethod::ClosestPoint,
                cap,
                &NoProgress,
            ));
        }
        let mut uncapped = fields[2].clone();
        uncapped.cap = f32::INFINITY;
        let eighth = (grid.spacing / 8.0) as f32;
        let rounded = |f: &DistanceField| {
            let mut f = f.clone();
            for x in &mut f.values {
                *x = (*x / eighth).round() * eighth;
            }
            f
        };
        let ties = [rounded(&fields[1]), rounded(&fields[3])];
        fields.push(uncapped);
        fields.extend(ties);
        let mut refusals = 0;
        for (i, f) in fields.iter().enumerate() {
            for rule in [TagRule::Paper, TagRule::Threshold] {
                for eps in [0.3, 0.45] {
                    let fast = tag(f, eps, rule, &NoProgress);
                    let (reference, refused) = heap_only(f, eps as f32, rule);
                    assert_eq!(fast.exterior, reference, "field {i}, {rule:?}, eps {eps}");
                    assert_eq!(
                        fast.exterior_count,
                        reference.iter().filter(|&&e| e).count()
                    );
                    assert_eq!(fast.refused, refused, "field {i}, {rule:?}, eps {eps}");
                    refusals += refused;
                }
            }
        }
        // The paper's rule did refuse nodes: the comparison covers refusals.
        assert!(refusals > 0);
    }

    #[test]
    fn threshold_rule_equals_a_flood_fill() {
        let f = field(40);
        for eps in [0.3, 0.6, 1.0] {
            let t = tag(&f, eps, TagRule::Threshold, &NoProgress);
            let reference = flood(&f, eps as f32);
            assert_eq!(t.exterior, reference, "eps {eps}");
            assert_eq!(t.refused, 0);
            assert!(t.exterior_count > f.grid.len() / 3);
        }
    }

    #[test]
    fn paper_rule_stops_at_necks_and_is_a_subset_of_the_flood_fill() {
        let f = field(40);
        let eps = 0.4;
        let paper = tag(&f, eps, TagRule::Paper, &NoProgress);
        let fill = tag(&f, eps, TagRule::Threshold, &NoProgress);
        // Every node the paper's rule accepts has d ≥ ε and is reachable, so it is
        // in the flood fill; the cup's inside is entered through its mouth (d
        // decreases into it at first) but the rule refuses the nodes where d grows
        // again, so the paper's exterior is strictly smaller here.
        for (p, f) in paper.exterior.iter().zip(&fill.exterior) {
            assert!(!p || *f);
        }
        assert!(paper.refused > 0);
        assert!(paper.exterior_count < fill.exterior_count);
        // The cup's centre (a local maximum of d behind the neck) is reached by the
        // flood fill through the mouth but not by the paper's rule.
        let g = &f.grid;
        let centre = [0, 1, 2].map(|a| ((0.0 - g.origin[a]) / g.spacing).round() as usize);
        let u = g.index(centre[0], centre[1], centre[2]);
        assert!(!paper.exterior[u] && fill.exterior[u]);
    }
}
