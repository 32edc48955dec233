//! The initial offset surface by tagging (§5.2, Algorithm 1).
//!
//! Every node starts interior; the nodes on the faces of the grid (the bounding
//! box Γ₀ of the paper's Fig. 5) form the tagged boundary ∂Ω. A priority queue hands
//! out the boundary node farthest from the data; while that distance is at least ε
//! the node is tested and, if accepted, becomes exterior and its interior
//! neighbours (6-connected) join ∂Ω. The final ∂Ω approximates {d = ε}.
//!
//! Two acceptance rules:
//! * [`TagRule::Paper`] — Algorithm 1, line 4: accept only when no interior
//!   neighbour is farther from the data than the node itself. The front therefore
//!   descends the distance field and does not pass a neck (a saddle of d) into a
//!   pocket that widens again; a node refused once stays on the boundary. Ties
//!   (equal distances, e.g. the capped far field) count as "not farther".
//! * [`TagRule::Threshold`] — the ε rule only: accept every node with d ≥ ε. The
//!   exterior is then exactly the flood fill of {d ≥ ε} from the box, which the
//!   tests check against an independent breadth-first fill.
//!
//! With a capped distance (the closest-point method stops at the cap c) every node
//! beyond c looks equally far, so the paper's rule only sees necks narrower than 2c;
//! the pipeline sets c = ε + γ + 2h.
//!
//! Nodes at the distance cap are all tied at the maximum, so they are taken first
//! by a FIFO (cheap) before the binary heap takes over near the data; heap ties go
//! to the smaller node index, so the result is deterministic.

use std::collections::{BinaryHeap, VecDeque};

use asperity_core::Progress;

use crate::distance::DistanceField;

/// Which nodes Algorithm 1 accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TagRule {
    /// Algorithm 1 as published: the node must not have a farther interior neighbour.
    Paper,
    /// Only the ε rule: a flood fill of {d ≥ ε} from the box.
    Threshold,
}

/// Node states.
const INTERIOR: u8 = 0;
const BOUNDARY: u8 = 1;
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
    let mut state = vec![INTERIOR; n];
    let mut fifo: VecDeque<u32> = VecDeque::new();
    let mut heap: BinaryHeap<u64> = BinaryHeap::new();
    let key = |u: usize| (u64::from(d[u].to_bits()) << 32) | u64::from(u32::MAX - u as u32);
    let push =
        |u: usize, state: &mut [u8], fifo: &mut VecDeque<u32>, heap: &mut BinaryHeap<u64>| {
            state[u] = BOUNDARY;
            if d[u] >= far {
                fifo.push_back(u as u32);
            } else {
                heap.push(key(u));
            }
        };
    let [nx, ny, nz] = grid.dims;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if grid.on_boundary([i, j, k]) {
                    push(grid.index(i, j, k), &mut state, &mut fifo, &mut heap);
                }
            }
        }
    }
    progress.start(n as u64, "tagging");
    let strides = grid.strides();
    let mut exterior_count = 0usize;
    let mut refused = 0usize;
    let mut neighbours = [0usize; 6];
    loop {
        let u = if let Some(u) = fifo.pop_front() {
            u as usize
        } else if let Some(top) = heap.pop() {
            (u32::MAX - top as u32) as usize
        } else {
            break;
        };
        if d[u] < eps {
            break;
        }
        let c = grid.coords(u);
        let mut count = 0;
        for a in 0..3 {
            if c[a] > 0 {
                neighbours[count] = u - strides[a];
                count += 1;
            }
            if c[a] + 1 < grid.dims[a] {
                neighbours[count] = u + strides[a];
                count += 1;
            }
        }
        let nb = &neighbours[..count];
        if rule == TagRule::Paper && nb.iter().any(|&v| state[v] != EXTERIOR && d[v] > d[u]) {
            state[u] = REFUSED;
            refused += 1;
            continue;
        }
        state[u] = EXTERIOR;
        exterior_count += 1;
        if exterior_count.is_multiple_of(1 << 20) {
            progress.advance(1 << 20);
        }
        for &v in nb {
            if state[v] == INTERIOR {
                push(v, &mut state, &mut fifo, &mut heap);
            }
        }
    }
    progress.finish();
    Tags {
        exterior: state.into_iter().map(|s| s == EXTERIOR).collect(),
        exterior_count,
        refused,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
