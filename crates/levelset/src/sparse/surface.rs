//! The initial level set on bricks: the signed distance to the tagged front,
//! clamped to ±γ (§5.2: "we recompute the distance function for the tagged
//! boundary … negating the distance function at all interior cells").
//!
//! As in the dense `evolve::from_tags` (feature `reference`): the front crosses every grid edge from
//! an exterior node to a non-exterior one, where d − ε changes sign along it
//! (or at its midpoint where the paper's rule stopped the front farther out),
//! and |φ| is the closest-point distance to these crossings, up to γ. The
//! crossings are listed in the dense order (the wavefront breaks ties between
//! equally near crossings by their index), and their wavefront runs on its own
//! bricks, those within γ of a crossing; bricks it needs that the distance did
//! not have are added to the layout. Everywhere else φ is ±γ: per node in the
//! active bricks, per brick (its tile) in the others.

use asperity_core::Progress;
use rayon::prelude::*;

use super::distance::{SparseDistance, bricks_for, cell_distance, closest_points};
use super::layout::{BRICK_NODES, Bricks, EMPTY_MASK, NO_SLOT, SIDE, shifted};
use super::tagging::SparseTags;
use crate::evolve::crossing_point;

/// A level-set function on bricks: φ < 0 inside, |φ| ≤ γ; inactive bricks
/// read as +γ (exterior) or −γ.
#[derive(Clone, Debug)]
pub struct SparseLevelSet {
    /// The bricks (the same slots as the distance's).
    pub bricks: Bricks,
    /// φ per node id.
    pub phi: Vec<f32>,
    /// Per brick, whether an inactive brick is exterior.
    pub(crate) tiles: Vec<u64>,
    /// The tube half-width γ.
    pub gamma: f32,
}

impl SparseLevelSet {
    /// φ of the inactive brick `bi`.
    #[inline(always)]
    pub(crate) fn background(&self, bi: usize) -> f32 {
        if self.tiles[bi / 64] >> (bi % 64) & 1 == 1 {
            self.gamma
        } else {
            -self.gamma
        }
    }

    /// The grid.
    pub fn grid(&self) -> &crate::GridSpec {
        &self.bricks.grid
    }

    /// The triangle mesh of {φ = 0} (marching cubes, see [`crate::sparse::extract`]).
    pub fn extract(
        &self,
        options: &crate::ExtractOptions,
    ) -> (asperity_core::TriMesh, crate::ExtractStats) {
        super::sparse_extract(self, options)
    }

    /// φ at node `c`.
    pub fn at(&self, c: [usize; 3]) -> f32 {
        match self.bricks.id(c) {
            Some(id) => self.phi[id as usize],
            None => self.background(self.bricks.brick_index(c.map(|x| x / SIDE))),
        }
    }

    /// φ on the whole grid, x fastest (for tests and small grids).
    pub fn to_dense(&self) -> Vec<f32> {
        let g = &self.bricks.grid;
        (0..g.len())
            .into_par_iter()
            .map(|u| self.at(g.coords(u)))
            .collect()
    }

    /// Activates the bricks `new` (sorted), φ = their tiles' ±γ; returns the
    /// first new slot.
    pub(crate) fn activate(&mut self, new: &[u32]) -> usize {
        let first = self.bricks.activate(new);
        for s in first..self.bricks.slots() {
            let v = self.background(self.bricks.brick_of(s));
            self.phi.extend(std::iter::repeat_n(v, BRICK_NODES));
        }
        first
    }
}

/// The crossings of the tagged front in the dense order: per exterior node,
/// per axis, the edge down then the edge up.
fn crossings(dist: &SparseDistance, tags: &SparseTags, eps: f64) -> Vec<[f64; 3]> {
    let bricks = &dist.bricks;
    let grid = &bricks.grid;
    let dims = grid.dims;
    // Exterior or not, and d, at node `c` (its tile and the cap without storage).
    let node = |c: [usize; 3]| match bricks.id(c) {
        Some(u) => (tags.node(u), dist.values[u as usize]),
        None => (tags.tile(bricks.brick_index(c.map(|x| x / SIDE))), dist.cap),
    };
    // Each crossing's key: its exterior node's dense index · 6 + the edge's
    // direction (2 · axis + up), from each non-exterior node of an active
    // brick (every non-exterior node next to an exterior one is active) to
    // its exterior neighbours. Eight bytes a crossing are sorted, not the
    // points (the stage's largest list); the points follow from the keys.
    let mut keys: Vec<u64> = (0..bricks.slots())
        .into_par_iter()
        .flat_map_iter(|s| {
            let b = bricks.slot_coords(s);
            let inside = bricks.in_grid(b);
            // The non-exterior nodes with an exterior neighbour (a superset,
            // exact but for the grid's faces, which the loop checks).
            let ext = tags.mask(s);
            let across = bricks.across_faces(s, |t| tags.mask(t), |bi| tags.tile(bi));
            let mut near = EMPTY_MASK;
            for (dir, face) in across.iter().enumerate() {
                let moved = shifted(&ext, dir);
                for z in 0..SIDE {
                    near[z] |= moved[z] | face[z];
                }
            }
            let mut out = Vec::new();
            for z in 0..SIDE {
                let mut bits = near[z] & inside[z] & !ext[z];
                while bits != 0 {
                    let l = z * 64 + bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    let c = [
                        b[0] * SIDE + l % SIDE,
                        b[1] * SIDE + (l / SIDE) % SIDE,
                        b[2] * SIDE + l / 64,
                    ];
                    for a in 0..3 {
                        // u below v: the crossing is u's edge up; u above: its edge down.
                        for up in [true, false] {
                            let mut cu = c;
                            if up {
                                if c[a] == 0 {
                                    continue;
                                }
                                cu[a] -= 1;
                            } else {
                                if c[a] + 1 >= dims[a] {
                                    continue;
                                }
                                cu[a] += 1;
                            }
                            if node(cu).0 {
                                let dense = grid.index(cu[0], cu[1], cu[2]) as u64;
                                out.push(dense * 6 + (2 * a + usize::from(up)) as u64);
                            }
                        }
                    }
                }
            }
            out
        })
        .collect();
    keys.par_sort_unstable();
    keys.par_iter()
        .map(|&k| {
            let (cu, dir) = (grid.coords((k / 6) as usize), (k % 6) as usize);
            let (a, up) = (dir / 2, dir % 2 == 1);
            let mut c = cu;
            if up {
                c[a] += 1;
            } else {
                c[a] -= 1;
            }
            crossing_point(grid, cu, (a, up), (node(cu).1, node(c).1), eps)
        })
        .collect()
}

/// The initial level set from the tags on `dist`'s bricks, with offset `eps`
/// and tube half-width `gamma` (world units). Bricks the front's neighbourhood
/// needs are activated in `dist` and `tags` too, so the three share slots.
pub fn sparse_initial(
    dist: &mut SparseDistance,
    tags: &mut SparseTags,
    eps: f64,
    gamma: f64,
    progress: &dyn Progress,
) -> SparseLevelSet {
    let crossings = crossings(dist, tags, eps);
    let gamma32 = gamma as f32;
    let grid = dist.bricks.grid;
    // Straight from the packed closest points to φ. |φ| is clamped at γ, so
    // the wavefront stops half a cell beyond it.
    let cap = gamma + 0.5 * grid.spacing;
    let near = bricks_for(&grid, &crossings, cap);
    let missing: Vec<u32> = (0..near.slots())
        .map(|s| near.brick_of(s) as u32)
        .filter(|&bi| dist.bricks.slot_of(bi as usize) == NO_SLOT)
        .collect::<Vec<_>>();
    let mut sorted = missing;
    sorted.sort_unstable();
    let first = dist.bricks.slots();
    dist.activate(&sorted);
    tags.extend(&dist.bricks, first);
    // The wavefront's slots in the order of the level set's, so that φ is
    // written slot after slot as the cells are read, chunk by chunk, each
    // chunk freed once read: the cells (8 bytes a node) and φ (4) are never
    // both whole.
    let near = near.in_slot_order_of(&dist.bricks);
    let (cells, _) = closest_points(&crossings, &near, cap, progress);
    drop(crossings);
    let bricks = &dist.bricks;
    let n = bricks.nodes();
    let at: Vec<u32> = (0..bricks.slots())
        .map(|s| near.slot_of(bricks.brick_of(s)))
        .collect();
    let signed = |id: usize, r: f32| if tags.node(id as u32) { r } else { -r };
    // With room for the bricks the flow may add and its two virtual slots.
    let mut phi = Vec::with_capacity(super::distance::headroom(n));
    cells.consume(|first, chunk| {
        let last = first + chunk.len() / BRICK_NODES;
        // Through the level set's slot of the chunk's last brick.
        let upto = bricks.slot_of(near.brick_of(last - 1)) as usize + 1;
        let from = phi.len();
        phi.par_extend((from..upto * BRICK_NODES).into_par_iter().map(|id| {
            let t = at[id / BRICK_NODES];
            let r = if t == NO_SLOT {
                gamma32
            } else {
                let t = t as usize;
                debug_assert!((first..last).contains(&t));
                let c = &chunk[(t - first) * BRICK_NODES + id % BRICK_NODES];
                cell_distance(c.load(std::sync::atomic::Ordering::Relaxed), gamma32)
            };
            signed(id, r)
        }));
    });
    // The bricks after the wavefront's last: ±γ.
    let from = phi.len();
    phi.par_extend((from..n).into_par_iter().map(|id| signed(id, gamma32)));
    SparseLevelSet {
        bricks: bricks.clone(),
        phi,
        tiles: tags.tiles_bits().to_vec(),
        gamma: gamma32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::{DistanceMethod, unsigned_distance};
    use crate::evolve::from_tags;
    use crate::grid::{GridSpec, Sizing};
    use crate::sparse::{sparse_distance, sparse_tag};
    use crate::tagging::{TagRule, tag};
    use asperity_core::{MemoryBudget, NoProgress};

    /// Two lumpy blobs and a thin ring of points.
    fn shape() -> Vec<[f64; 3]> {
        let mut pts = Vec::new();
        for a in 0..70 {
            for b in 0..140 {
                let th = std::f64::consts::PI * (a as f64 + 0.5) / 70.0;
                let ph = std::f64::consts::PI * b as f64 / 70.0;
                let r = 2.0 + 0.3 * (3.0 * ph).sin() * (2.0 * th).cos();
                let dir = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
                pts.push(dir.map(|x| r * x));
                pts.push([7.0 + 1.5 * dir[0], 1.0 + 1.5 * dir[1], 1.5 * dir[2]]);
            }
        }
        for t in 0..300 {
            let ph = 2.0 * std::f64::consts::PI * t as f64 / 300.0;
            pts.push([3.5 + 5.0 * ph.cos(), 6.0 + 5.0 * ph.sin(), -2.0]);
        }
        pts
    }

    /// φ equals the dense initial level set at every node, for both rules.
    #[test]
    fn sparse_initial_surface_equals_the_dense_one() {
        let pts = shape();
        for (res, rule) in [
            (64, TagRule::Paper),
            (90, TagRule::Threshold),
            (40, TagRule::Paper),
        ] {
            let grid = GridSpec::around(
                &pts,
                Sizing::Resolution(res),
                |h| (6.0 * h / h) as usize + 3,
                &MemoryBudget::unlimited(),
            )
            .unwrap();
            let h = grid.spacing;
            let (eps, gamma) = (3.0 * h, 3.0 * h);
            let cap = eps + gamma + 2.0 * h;
            let dense_d =
                unsigned_distance(&pts, &grid, DistanceMethod::ClosestPoint, cap, &NoProgress);
            let dense_tags = tag(&dense_d, eps, rule, &NoProgress);
            let want = from_tags(&dense_d, &dense_tags, eps, gamma, &NoProgress);
            let (mut d, _) = sparse_distance(&pts, &grid, cap, &NoProgress);
            let mut tags = sparse_tag(&mut d, eps, rule, &NoProgress);
            let got = sparse_initial(&mut d, &mut tags, eps, gamma, &NoProgress);
            assert!(got.bricks.slots() < got.bricks.brick_count());
            assert_eq!(got.bricks.slots(), d.bricks.slots());
            let dense = got.to_dense();
            for (u, (a, b)) in dense.iter().zip(&want.phi).enumerate() {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "res {res}: node {:?}: {a} vs {b}",
                    grid.coords(u)
                );
            }
        }
    }
}
