//! The enclosed voids of a sampled surface, found from the topology of the
//! distance to its samples, so that neither the tagging nor the flow enters
//! them through the gaps between samples.
//!
//! Algorithm 1 of kim-machiraju-thompson (§5.2) floods {d ≥ ε} from the box,
//! and the flow of Eq. 6 moves the front at the speed d: both pass wherever
//! the samples leave a gap wider than ε or than the arrest distance. A random
//! sample of a surface has gaps several times its typical spacing, and a scan
//! has holes, so the front tunnels into the solid (the sphere of
//! 40 000 random points reconstructed with genus 1 646). What tells a gap from
//! an opening is the distance function's own shape: behind a gap in a closed
//! surface lies a region where d rises again — the solid's inside, whose
//! distance to the samples reaches its inner radius — while an opening leads
//! on to the outside. In the language of the flow complex (Giesen & John 2003,
//! "The flow complex: a data structure for geometric modeling"; Edelsbrunner's
//! Wrap, 2003), the inside is the stable manifold of the maxima of d that the
//! gaps' saddles separate from infinity.
//!
//! On the grid, this is a merge tree of the superlevel sets of d, computed by
//! a union–find over the nodes in decreasing d (the watershed by flooding):
//! each node joins the component of its highest neighbour; where two
//! components meet at level v, the one whose peak lies less than the depth τ
//! above v merges into the other (the elder rule of persistence, Edelsbrunner,
//! Letscher & Zomorodian 2002), and two components at least τ deep both stay.
//! The grid's faces belong to the exterior, infinitely deep. Every component
//! left other than the exterior is a *void*: its nodes are the inside of the
//! surface, down to the samples (a node below every saddle still joins the
//! component its steepest ascent leads to). Pockets shallower than τ between
//! noisy samples merge into a neighbour and are no void; the torus's hole, or
//! the space between a bunny's ears, reaches the box without climbing and is
//! exterior.
//!
//! The distance is capped, so a void deeper than the cap shows only the cap as
//! its peak: one whose capped depth is below τ when it meets the exterior is
//! *undecided*, and the pipeline computes the distance again with a larger cap.
//!
//! Nodes of inactive bricks read as the cap: each such brick is one element of
//! the union–find.

use rayon::prelude::*;

use super::distance::SparseDistance;
use super::layout::{BRICK_NODES, NO_SLOT, SIDE};

/// Not yet joined to any component.
const UNSET: u32 = u32::MAX;

/// What [`label_voids`] found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Voids {
    /// Per node id, whether it lies in a void (bit `id % 64` of word `id / 64`).
    pub(crate) nodes: Vec<u64>,
    /// Void components found.
    pub count: usize,
    /// Nodes in voids.
    pub void_nodes: usize,
    /// The highest level at which a void meets the exterior: the widest gap's
    /// half-width (world units; 0 without voids).
    pub widest_gap: f64,
    /// The level at which a component that the cap may have cut short merged
    /// into the exterior: a larger cap is needed to decide it.
    pub undecided: Option<f64>,
}

impl Voids {
    /// Whether node id `id` lies in a void.
    #[inline]
    pub(crate) fn contains(&self, id: usize) -> bool {
        self.nodes[id / 64] >> (id % 64) & 1 == 1
    }
}

/// Union–find over the nodes and the inactive bricks, with each root's peak.
struct Forest {
    parent: Vec<u32>,
    peak: Vec<f32>,
    exterior: u32,
}

impl Forest {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let p = self.parent[x as usize];
            self.parent[x as usize] = self.parent[p as usize];
            x = p;
        }
        x
    }
}

/// The grid's elements: node ids of active bricks, then one per brick (used
/// only for the inactive ones).
struct Elements<'a> {
    dist: &'a SparseDistance,
    nodes: usize,
}

impl Elements<'_> {
    /// Node `id`'s grid coordinates, if it lies in the grid.
    fn coords(&self, id: usize) -> Option<[usize; 3]> {
        let b = &self.dist.bricks;
        let (s, l) = (id / BRICK_NODES, id % BRICK_NODES);
        let base = b.slot_coords(s);
        let c = [
            base[0] * SIDE + l % SIDE,
            base[1] * SIDE + (l / SIDE) % SIDE,
            base[2] * SIDE + l / (SIDE * SIDE),
        ];
        (0..3).all(|a| c[a] < b.grid.dims[a]).then_some(c)
    }

    /// The element at grid node `c`.
    fn at(&self, c: [usize; 3]) -> u32 {
        let b = &self.dist.bricks;
        match b.id(c) {
            Some(id) => id,
            None => (self.nodes + b.brick_index(c.map(|x| x / SIDE))) as u32,
        }
    }

    /// The 6-neighbours of element `e` (nodes or inactive bricks), and whether
    /// `e` lies on the grid's faces.
    fn neighbours(&self, e: usize, out: &mut Vec<u32>) -> bool {
        out.clear();
        let b = &self.dist.bricks;
        let (c, dims) = if e < self.nodes {
            (
                self.coords(e).expect("processed nodes lie in the grid"),
                b.grid.dims,
            )
        } else {
            (b.brick_coords(e - self.nodes), b.bdims)
        };
        let mut face = false;
        for a in 0..3 {
            for up in [false, true] {
                let mut n = c;
                if up {
                    if c[a] + 1 >= dims[a] {
                        face = true;
                        continue;
                    }
                    n[a] += 1;
                } else {
                    if c[a] == 0 {
                        face = true;
                        continue;
                    }
                    n[a] -= 1;
                }
                if e < self.nodes {
                    out.push(self.at(n));
                } else {
                    // An inactive brick meets its active neighbours when their
                    // nodes are processed (after it: it reads as the cap).
                    let nb = b.brick_index(n);
                    if b.slot_of(nb) == NO_SLOT {
                        out.push((self.nodes + nb) as u32);
                    }
                }
            }
        }
        face
    }

    fn value(&self, e: u32) -> f32 {
        let e = e as usize;
        if e < self.nodes {
            self.dist.values[e]
        } else {
            self.dist.cap
        }
    }
}

/// The voids of the capped distance `dist` at least `depth` deep (world
/// units), by the merge tree of the module docs.
pub fn label_voids(dist: &SparseDistance, depth: f64) -> Voids {
    let b = &dist.bricks;
    let nodes = b.nodes();
    let el = Elements { dist, nodes };
    let total = nodes + b.brick_count();
    let depth = depth as f32;
    // Inactive bricks first (all at the cap), then the nodes in the grid by
    // decreasing d, ties by id: an order that does not depend on the threads.
    let mut order: Vec<u64> = (0..nodes)
        .into_par_iter()
        .filter(|&id| el.coords(id).is_some())
        .map(|id| (u64::from(u32::MAX - dist.values[id].max(0.0).to_bits()) << 32) | id as u64)
        .collect();
    order.par_sort_unstable();
    let inactive = (0..b.brick_count()).filter(|&bi| b.slot_of(bi) == NO_SLOT);
    let mut forest = Forest {
        parent: vec![UNSET; total + 1],
        peak: vec![0.0; total + 1],
        exterior: total as u32,
    };
    forest.parent[total] = total as u32;
    forest.peak[total] = f32::INFINITY;
    let mut undecided: Option<f32> = None;
    let mut widest: f32 = 0.0;
    let mut around = Vec::with_capacity(7);
    let elements = inactive
        .map(|bi| (nodes + bi) as u32)
        .chain(order.iter().map(|&k| k as u32));
    for e in elements {
        let v = el.value(e);
        let face = el.neighbours(e as usize, &mut around);
        // The highest processed neighbour (the grid's faces are the highest).
        let mut best: Option<(f32, u32)> = face.then_some((f32::INFINITY, forest.exterior));
        for &n in &around {
            if forest.parent[n as usize] == UNSET {
                continue;
            }
            let key = (el.value(n), n);
            if best.is_none_or(|(bv, bn)| key.0 > bv || (key.0 == bv && key.1 < bn)) {
                best = Some(key);
            }
        }
        let Some((_, up)) = best else {
            forest.parent[e as usize] = e;
            forest.peak[e as usize] = v;
            continue;
        };
        let own = forest.find(up);
        forest.parent[e as usize] = own;
        // The processed neighbours' components (and the faces'), met at v.
        if face {
            around.push(forest.exterior);
        }
        for &n in &around {
            if forest.parent[n as usize] == UNSET {
                continue;
            }
            let (r, o) = (forest.find(n), forest.find(own));
            if r == o {
                continue;
            }
            let (pr, po) = (forest.peak[r as usize], forest.peak[o as usize]);
            let deep = |p: f32| p - v >= depth;
            if deep(pr) && deep(po) {
                if r == forest.exterior || o == forest.exterior {
                    widest = widest.max(v);
                }
                continue;
            }
            // The younger (lower peak; ties: the larger index) joins the elder.
            let (young, old) = if (pr, std::cmp::Reverse(r)) < (po, std::cmp::Reverse(o)) {
                (r, o)
            } else {
                (o, r)
            };
            // (Pieces of one plateau meeting at the cap itself are no saddle.)
            if old == forest.exterior && forest.peak[young as usize] >= dist.cap && v < dist.cap {
                undecided = Some(undecided.map_or(v, |u: f32| u.max(v)));
            }
            forest.parent[young as usize] = old;
        }
    }
    let exterior = forest.exterior;
    let mut roots = std::collections::BTreeSet::new();
    let mut bits = vec![0u64; nodes.div_ceil(64)];
    let mut void_nodes = 0;
    for &k in &order {
        let id = k as u32;
        let r = forest.find(id);
        if r != exterior {
            roots.insert(r);
            bits[id as usize / 64] |= 1 << (id % 64);
            void_nodes += 1;
        }
    }
    Voids {
        nodes: bits,
        count: roots.len(),
        void_nodes,
        widest_gap: f64::from(widest),
        undecided: undecided.map(f64::from),
    }
}

/// Gives back their distance (unmarks) the void nodes nearer than `below` to
/// the samples: the tagging saw every void node marked, so that its flood
/// stays out of the voids however near the samples they come; the flow then
/// holds only the deep ones (see [`freeze`]).
pub fn release(dist: &mut SparseDistance, voids: &Voids, below: f64) {
    let below = below as f32;
    dist.values.par_iter_mut().enumerate().for_each(|(id, v)| {
        if *v < 0.0 && -*v < below && voids.contains(id) {
            *v = -*v;
        }
    });
}

/// Per vertex at `positions`, whether a corner of its grid cell carries the
/// thin parts' obstacle (marked, nearer than `reach`; see [`freeze`]): the
/// vertex lies on a side of a thin part.
pub fn thin_vertices(dist: &SparseDistance, positions: &[[f64; 3]], reach: f64) -> Vec<bool> {
    let g = &dist.bricks.grid;
    let reach = reach as f32;
    positions
        .par_iter()
        .map(|p| {
            let base: [usize; 3] = std::array::from_fn(|a| {
                (((p[a] - g.origin[a]) / g.spacing).floor().max(0.0) as usize)
                    .min(g.dims[a].saturating_sub(2))
            });
            (0..8).any(|k| {
                let c = [
                    base[0] + (k & 1),
                    base[1] + (k >> 1 & 1),
                    base[2] + (k >> 2),
                ];
                let d = dist.at(c);
                d < 0.0 && -d < reach
            })
        })
        .collect()
}

/// What [`freeze`] needs to find the thin parts: per node id its nearest
/// point, the points, and the obstacle's reach.
pub type Thin<'a> = (&'a [u32], &'a [[f64; 3]], f64);

/// How far from the samples the thin parts' obstacle reaches: δ + 2h, so
/// that the nodes on both sides of the level set {d = δ} carry it.
pub fn obstacle_reach(delta: f64, h: f64) -> f64 {
    delta + 2.0 * h
}

/// Marks nodes for the flow by making their distance negative
/// (`−max(d, f32::MIN_POSITIVE)`: the kernels read |d| as the distance and
/// the sign as the mark):
/// * every node of a void at least `hold_from` from the samples, to be held
///   (nearer ones are left to the flow, which comes to rest on the samples
///   and across the gaps between them: a held node there would stop the
///   front on the grid's nodes, in steps);
/// * with `thin` = (nearest point per node id, the points, the reach), every
///   node within the reach of a sample that has no void node within two
///   nodes of it — a sample of a thin part or an open surface, which the
///   front would otherwise close on from both sides until nothing is left
///   inside — to carry the obstacle of `zhao_rate` (`hold_from` must lie
///   beyond the reach, so the kernels tell the two marks apart by |d|).
///
/// Returns the nodes marked for being thin.
pub fn freeze(
    dist: &mut SparseDistance,
    voids: &Voids,
    thin: Option<Thin>,
    hold_from: f64,
) -> usize {
    let b = dist.bricks.clone();
    let h = b.grid.spacing;
    let el = Elements {
        dist,
        nodes: b.nodes(),
    };
    let near_void = |c: [usize; 3]| {
        let lo = c.map(|x| x.saturating_sub(2));
        let hi: [usize; 3] = std::array::from_fn(|a| (c[a] + 2).min(b.grid.dims[a] - 1));
        (lo[2]..=hi[2]).any(|z| {
            (lo[1]..=hi[1]).any(|y| {
                (lo[0]..=hi[0]).any(|x| {
                    b.id([x, y, z])
                        .is_some_and(|id| voids.contains(id as usize))
                })
            })
        })
    };
    // Per point: whether the inside of the surface lies next to it.
    let backed: Option<Vec<bool>> = thin.map(|(_, points, _)| {
        points
            .par_iter()
            .map(|p| {
                let c: [usize; 3] = std::array::from_fn(|a| {
                    (((p[a] - b.grid.origin[a]) / h).round().max(0.0) as usize)
                        .min(b.grid.dims[a] - 1)
                });
                near_void(c)
            })
            .collect()
    });
    let hold_from = hold_from as f32;
    let marks: Vec<(bool, bool)> = (0..b.nodes())
        .into_par_iter()
        .map(|id| {
            if el.coords(id).is_none() {
                return (false, false);
            }
            let d = el.dist.values[id];
            if voids.contains(id) {
                return (d >= hold_from, false);
            }
            let t = match (thin, &backed) {
                (Some((nearest, _, reach)), Some(backed)) => {
                    let p = nearest[id];
                    f64::from(d) < reach && p != u32::MAX && !backed[p as usize]
                }
                _ => false,
            };
            (t, t)
        })
        .collect();
    let mut thin_count = 0;
    for (v, &(mark, was_thin)) in dist.values.iter_mut().zip(&marks) {
        if mark {
            *v = -v.max(f32::MIN_POSITIVE);
            thin_count += usize::from(was_thin);
        }
    }
    thin_count
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{GridSpec, Sizing};
    use crate::sparse::distance::sparse_distance;
    use asperity_core::{MemoryBudget, NoProgress};
    use rand::{Rng, SeedableRng};

    fn sphere(n: usize, seed: u64, r: f64) -> Vec<[f64; 3]> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                loop {
                    let v: [f64; 3] = std::array::from_fn(|_| rng.random::<f64>() * 2.0 - 1.0);
                    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    if l > 0.1 && l <= 1.0 {
                        break v.map(|x| r * x / l);
                    }
                }
            })
            .collect()
    }

    fn distance(pts: &[[f64; 3]], res: usize, cap_cells: f64) -> SparseDistance {
        let grid = GridSpec::around(
            pts,
            Sizing::Resolution(res),
            |_| 12,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        sparse_distance(pts, &grid, cap_cells * grid.spacing, &NoProgress).0
    }

    /// A sparse random sphere encloses one void (its inside, centre
    /// included), whose widest gap is below the sample spacing's few
    /// multiples; the outside is exterior.
    #[test]
    fn a_sampled_sphere_encloses_one_void() {
        let pts = sphere(3000, 1, 1.0);
        let d = distance(&pts, 48, 12.0);
        let h = d.bricks.grid.spacing;
        let v = label_voids(&d, 3.0 * h);
        assert_eq!(v.count, 1);
        assert!(v.undecided.is_none());
        assert!(
            v.widest_gap > 0.0 && v.widest_gap < 0.15,
            "{}",
            v.widest_gap
        );
        let at = |p: [f64; 3]| {
            let c = [0, 1, 2].map(|a| ((p[a] - d.bricks.grid.origin[a]) / h).round() as usize);
            d.bricks.id(c).map(|id| v.contains(id as usize))
        };
        assert_eq!(at([0.0, 0.0, 0.9]), Some(true), "inside the shell");
        assert_eq!(at([0.0, 0.0, 1.1]), Some(false), "outside the shell");
    }

    /// An open patch and a torus's hole enclose nothing but the torus's tube.
    #[test]
    fn openings_are_no_voids() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        let patch: Vec<[f64; 3]> = (0..4000)
            .map(|_| {
                let (x, y) = (
                    rng.random::<f64>() * 2.0 - 1.0,
                    rng.random::<f64>() * 2.0 - 1.0,
                );
                [x, y, 0.2 * (3.0 * x).sin()]
            })
            .collect();
        let d = distance(&patch, 48, 10.0);
        let v = label_voids(&d, 3.0 * d.bricks.grid.spacing);
        assert_eq!((v.count, v.void_nodes), (0, 0));
        let torus: Vec<[f64; 3]> = (0..20_000)
            .map(|_| {
                let (u, w) = (
                    rng.random::<f64>() * std::f64::consts::TAU,
                    rng.random::<f64>() * std::f64::consts::TAU,
                );
                let q = 1.0 + 0.35 * w.cos();
                [q * u.cos(), q * u.sin(), 0.35 * w.sin()]
            })
            .collect();
        let d = distance(&torus, 64, 10.0);
        let v = label_voids(&d, 3.0 * d.bricks.grid.spacing);
        assert_eq!(v.count, 1, "the tube");
    }

    /// A void deeper than the cap reports that a larger cap is needed.
    #[test]
    fn a_cap_below_the_gap_leaves_the_void_undecided() {
        let pts = sphere(400, 3, 1.0);
        let d = distance(&pts, 48, 4.0);
        let v = label_voids(&d, 3.0 * d.bricks.grid.spacing);
        assert_eq!(v.count, 0);
        assert!(v.undecided.is_some());
    }
}
