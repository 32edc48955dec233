//! The narrow tube as runs of consecutive nodes along x, grouped by plane.
//!
//! The tubes T and N of §5.2 (after Peng et al.'s fast local level set) are thin
//! shells around the front. Stored as runs along the x axis (nodes are x fastest),
//! every stencil read of a run is a contiguous load: the six neighbours of eight
//! consecutive nodes along any axis are eight consecutive floats. The flow kernels
//! in [`crate::evolve`](mod@crate::evolve) therefore evaluate eight nodes at once in vector registers,
//! and each plane's runs write only that plane, so the planes are updated in
//! parallel through disjoint `&mut` slices — no atomics, no locks.
//!
//! Runs are written here rather than taken from a sparse-volume crate: the flow
//! needs only this (lists per plane, a dilation by one node), and the dense grid
//! the other stages share stays the storage.

use rayon::prelude::*;

use crate::grid::GridSpec;

/// Nodes `start .. start + len` (flat indices) of one grid row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Run {
    /// First node.
    pub start: u32,
    /// Number of nodes.
    pub len: u32,
}

impl Run {
    fn end(self) -> u32 {
        self.start + self.len
    }
}

/// A set of nodes as sorted, disjoint runs, one list per plane `k`.
#[derive(Clone, Debug, Default)]
pub(crate) struct RunTube {
    /// `planes[k]`: the runs of plane k, by start.
    pub planes: Vec<Vec<Run>>,
}

impl RunTube {
    /// The number of nodes.
    pub fn nodes(&self) -> usize {
        self.planes.iter().flatten().map(|r| r.len as usize).sum()
    }

    /// Whether the tube has no nodes.
    pub fn is_empty(&self) -> bool {
        self.planes.iter().all(Vec::is_empty)
    }

    /// Every node at least `margin` nodes from each face: one run per row.
    pub fn interior_of(dims: [usize; 3], margin: usize) -> Self {
        let [nx, ny, nz] = dims;
        let planes = (0..nz)
            .map(|k| {
                if k < margin || k + margin >= nz || nx <= 2 * margin {
                    return Vec::new();
                }
                (margin..ny.saturating_sub(margin))
                    .map(|j| Run {
                        start: (margin + nx * (j + ny * k)) as u32,
                        len: (nx - 2 * margin) as u32,
                    })
                    .collect()
            })
            .collect();
        Self { planes }
    }

    /// The tube grown by one node along each axis (6-neighbourhood). Every node
    /// must be at least one node from each face.
    pub fn dilate(&self, grid: &GridSpec) -> Self {
        let [_, sy, sz] = grid.strides();
        let (sy, sz) = (sy as u32, sz as u32);
        let nz = self.planes.len();
        let planes = (0..nz)
            .into_par_iter()
            .map(|k| {
                let own = &self.planes[k][..];
                let below = if k > 0 { &self.planes[k - 1][..] } else { &[] };
                let above = self.planes.get(k + 1).map_or(&[][..], |p| &p[..]);
                // Five sorted streams: the plane's runs widened by one node, the
                // same runs one row down and up, and the neighbouring planes' runs.
                let mut sources = [
                    Shifted::new(own, 0, 1),
                    Shifted::new(own, -i64::from(sy), 0),
                    Shifted::new(own, i64::from(sy), 0),
                    Shifted::new(below, i64::from(sz), 0),
                    Shifted::new(above, -i64::from(sz), 0),
                ];
                merge(&mut sources)
            })
            .collect();
        Self { planes }
    }

    /// The tube grown by the 3 × 3 × 3 block (26-neighbourhood), the paper's N.
    /// Every node must be at least one node from each face.
    pub fn dilate_cube(&self, grid: &GridSpec) -> Self {
        let [_, sy, sz] = grid.strides();
        let (sy, sz) = (i64::from(sy as u32), i64::from(sz as u32));
        let nz = self.planes.len();
        let planes = (0..nz)
            .into_par_iter()
            .map(|k| {
                // Nine sorted streams: the rows j − 1, j, j + 1 of the planes
                // k − 1, k, k + 1, each widened by one node along x.
                let mut sources = Vec::with_capacity(9);
                for dk in -1i64..=1 {
                    let Some(runs) = (k as i64 + dk)
                        .try_into()
                        .ok()
                        .and_then(|q: usize| self.planes.get(q))
                    else {
                        continue;
                    };
                    for dj in -1i64..=1 {
                        sources.push(Shifted::new(runs, -(dk * sz + dj * sy), 1));
                    }
                }
                merge(&mut sources)
            })
            .collect();
        Self { planes }
    }
}

/// A sorted run list read with every run moved by `shift` nodes and widened by
/// `widen` nodes on both sides.
struct Shifted<'a> {
    runs: &'a [Run],
    shift: i64,
    widen: u32,
}

impl<'a> Shifted<'a> {
    fn new(runs: &'a [Run], shift: i64, widen: u32) -> Self {
        Self { runs, shift, widen }
    }

    fn peek(&self) -> Option<Run> {
        self.runs.first().map(|r| Run {
            start: (i64::from(r.start) + self.shift - i64::from(self.widen)) as u32,
            len: r.len + 2 * self.widen,
        })
    }
}

/// Merges sorted run streams into one sorted list, joining runs that overlap or
/// touch. Runs of different rows never touch when every node is at least one
/// node from the x faces.
fn merge(sources: &mut [Shifted]) -> Vec<Run> {
    let total = sources.iter().map(|s| s.runs.len()).sum::<usize>();
    let mut out: Vec<Run> = Vec::with_capacity(total / 2);
    loop {
        let mut best: Option<(usize, Run)> = None;
        for (i, s) in sources.iter().enumerate() {
            if let Some(r) = s.peek()
                && best.is_none_or(|(_, b)| r.start < b.start)
            {
                best = Some((i, r));
            }
        }
        let Some((i, r)) = best else {
            return out;
        };
        sources[i].runs = &sources[i].runs[1..];
        match out.last_mut() {
            Some(last) if r.start <= last.end() => {
                let end = last.end().max(r.end());
                last.len = end - last.start;
            }
            _ => out.push(r),
        }
    }
}

/// Appends node `u` to a run list being built in increasing order.
#[inline]
pub(crate) fn push_node(runs: &mut Vec<Run>, u: usize) {
    let u = u as u32;
    match runs.last_mut() {
        Some(last) if last.end() == u => last.len += 1,
        _ => runs.push(Run { start: u, len: 1 }),
    }
}

/// Appends the nodes `u + l` for the set bits `l < n` of `bits`, in order.
#[inline]
pub(crate) fn push_lanes(runs: &mut Vec<Run>, u: usize, bits: u32, n: usize) {
    if bits == (1 << n) - 1 {
        let u = u as u32;
        match runs.last_mut() {
            Some(last) if last.end() == u => last.len += n as u32,
            _ => runs.push(Run {
                start: u,
                len: n as u32,
            }),
        }
        return;
    }
    let mut rest = bits;
    while rest != 0 {
        let l = rest.trailing_zeros() as usize;
        push_node(runs, u + l);
        rest &= rest - 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Sizing;
    use asperity_core::MemoryBudget;
    use std::collections::BTreeSet;

    fn grid() -> GridSpec {
        GridSpec::around(
            &[[0.0; 3], [1.0, 0.8, 0.6]],
            Sizing::Resolution(12),
            |_| 3,
            &MemoryBudget::unlimited(),
        )
        .unwrap()
    }

    fn nodes(t: &RunTube) -> BTreeSet<usize> {
        t.planes
            .iter()
            .flatten()
            .flat_map(|r| r.start as usize..(r.start + r.len) as usize)
            .collect()
    }

    /// Runs sorted and apart, each within one row of its own plane.
    fn well_formed(t: &RunTube, g: &GridSpec) {
        for (k, plane) in t.planes.iter().enumerate() {
            for w in plane.windows(2) {
                assert!(w[0].end() < w[1].start, "runs sorted and apart");
            }
            for r in plane {
                assert_eq!(g.coords(r.start as usize)[2], k);
                let last = g.coords((r.end() - 1) as usize);
                assert_eq!(last[1], g.coords(r.start as usize)[1], "one row per run");
            }
        }
    }

    /// Dilation equals the 6-neighbourhood union computed node by node.
    #[test]
    fn dilation_is_the_six_neighbourhood() {
        let g = grid();
        let s = g.strides();
        // A scattered set: a diagonal line, a small block and single nodes.
        let mut set = BTreeSet::new();
        for t in 2..10 {
            set.insert(g.index(t, t.min(g.dims[1] - 3), 2 + t % 3));
        }
        for k in 4..7 {
            for j in 3..6 {
                for i in 5..9 {
                    set.insert(g.index(i, j, k));
                }
            }
        }
        set.insert(g.index(g.dims[0] - 2, 1, 1));
        let mut tube = RunTube {
            planes: vec![Vec::new(); g.dims[2]],
        };
        for &u in &set {
            push_node(&mut tube.planes[g.coords(u)[2]], u);
        }
        assert_eq!(nodes(&tube), set);
        let grown = tube.dilate(&g);
        let mut expected = BTreeSet::new();
        for &u in &set {
            for v in [u, u - 1, u + 1, u - s[1], u + s[1], u - s[2], u + s[2]] {
                expected.insert(v);
            }
        }
        assert_eq!(nodes(&grown), expected);
        assert_eq!(grown.nodes(), expected.len());
        well_formed(&grown, &g);
    }

    /// The cube dilation equals the 26-neighbourhood union node by node.
    #[test]
    fn cube_dilation_is_the_26_neighbourhood() {
        let g = grid();
        let s = g.strides();
        let mut set = BTreeSet::new();
        for t in 2..9 {
            set.insert(g.index(t, (t + 1).min(g.dims[1] - 3), 2 + t % 4));
        }
        set.insert(g.index(3, 3, 3));
        set.insert(g.index(g.dims[0] - 2, g.dims[1] - 2, g.dims[2] - 2));
        let mut tube = RunTube {
            planes: vec![Vec::new(); g.dims[2]],
        };
        for &u in &set {
            push_node(&mut tube.planes[g.coords(u)[2]], u);
        }
        let grown = tube.dilate_cube(&g);
        let mut expected = BTreeSet::new();
        for &u in &set {
            for dk in -1i64..=1 {
                for dj in -1i64..=1 {
                    for di in -1i64..=1 {
                        let v = u as i64 + di + dj * s[1] as i64 + dk * s[2] as i64;
                        expected.insert(v as usize);
                    }
                }
            }
        }
        assert_eq!(nodes(&grown), expected);
        well_formed(&grown, &g);
    }

    #[test]
    fn interior_leaves_the_margin() {
        let g = grid();
        let t = RunTube::interior_of(g.dims, 2);
        let [nx, ny, nz] = g.dims;
        assert_eq!(t.nodes(), (nx - 4) * (ny - 4) * (nz - 4));
        assert!(nodes(&t).iter().all(|&u| {
            let c = g.coords(u);
            (0..3).all(|a| c[a] >= 2 && c[a] + 2 < g.dims[a])
        }));
    }
}
