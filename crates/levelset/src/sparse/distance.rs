//! The closest-point distance (§5.2, Eq. 7) on active bricks only.
//!
//! The same wavefront as [`crate::distance`]'s closest-point method — every
//! node keeps the nearest point offered to it, offers travel outward to the 26
//! neighbours, the front stops at the cap — with nodes addressed by brick ids.
//! The bricks are those within the cap of a point ([`Bricks::around`] with
//! `wavefront_radius`), so every node the wavefront can reach has storage,
//! and the memory and the work follow the points' neighbourhood, not the box.
//! A node far from the data reads as the cap, as in the dense field.
//!
//! Each node ends with the same packed (d², point) as on the dense grid: the
//! offers and their order-free minimum are the same, only the addresses
//! differ (tested against the dense wavefront).

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use asperity_core::Progress;
use rayon::prelude::*;

use super::layout::{BRICK_NODES, Bricks, SIDE, local, wavefront_radius};
use crate::distance::{Claims, EMPTY, POINT_PREFETCH, axis_squares, dist2, lower, pack, unpack_d2};

/// Points handed to one seeding task.
const SEED_CHUNK: usize = 4096;

/// The bricks a closest-point wavefront from `points` capped at `cap` needs.
pub(crate) fn bricks_for(grid: &crate::GridSpec, points: &[[f64; 3]], cap: f64) -> Bricks {
    Bricks::around(grid, points, wavefront_radius(cap, grid.spacing))
}

/// Nodes per chunk of [`Cells`]: 256 bricks, 1 MiB of cells (three bricks in
/// the unit tests, so that their small grids cross chunk boundaries).
#[cfg(not(test))]
const CHUNK_NODES: usize = 256 * BRICK_NODES;
#[cfg(test)]
const CHUNK_NODES: usize = 3 * BRICK_NODES;

/// A wavefront's packed (d², point index) per node id, in chunks of
/// [`CHUNK_NODES`], so that a stage turning them into its own field frees each
/// chunk once it has read it: the cells (8 bytes a node) and the field they
/// become (4) are never both whole.
pub(crate) struct Cells {
    chunks: Vec<Vec<AtomicU64>>,
    len: usize,
}

impl Cells {
    /// `n` cells, all [`EMPTY`].
    fn new(n: usize) -> Self {
        let chunks = (0..n.div_ceil(CHUNK_NODES))
            .into_par_iter()
            .map(|c| {
                let len = CHUNK_NODES.min(n - c * CHUNK_NODES);
                (0..len).map(|_| AtomicU64::new(EMPTY)).collect()
            })
            .collect();
        Self { chunks, len: n }
    }

    /// The cell of node id `u`.
    #[inline(always)]
    fn cell(&self, u: usize) -> &AtomicU64 {
        &self.chunks[u / CHUNK_NODES][u % CHUNK_NODES]
    }

    /// The packed value of node id `u`.
    #[inline(always)]
    pub(crate) fn load(&self, u: usize) -> u64 {
        self.cell(u).load(Relaxed)
    }

    /// Node ids.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Hands each chunk, with the slot of its first brick, to `f` in order,
    /// freeing it once `f` returns.
    pub(crate) fn consume(self, mut f: impl FnMut(usize, &[AtomicU64])) {
        for (c, chunk) in self.chunks.into_iter().enumerate() {
            f(c * CHUNK_NODES / BRICK_NODES, &chunk);
        }
    }
}

/// The closest-point wavefront from `points` up to `cap` on the active bricks
/// of `space` (which must hold every node within the cap, see [`bricks_for`]):
/// per node id the packed (d², point index) of the nearest point found,
/// [`EMPTY`] beyond the cap; and the rounds.
pub(crate) fn closest_points(
    points: &[[f64; 3]],
    space: &Bricks,
    cap: f64,
    progress: &dyn Progress,
) -> (Cells, usize) {
    let n = space.nodes();
    let cells = Cells::new(n);
    let claims = Claims::new(n);
    seed(points, space, &cells, &claims);
    let cap2 = (cap * cap) as f32;
    let around = space.neighbourhoods();
    let wave = Wave {
        points,
        space,
        around: &around,
        cells: &cells,
        claims: &claims,
    };
    let expected_rounds = (cap / space.grid.spacing).ceil() as u64 + 2;
    progress.start(expected_rounds, "distance (closest point)");
    let mut rounds = 0;
    // The frontier is the claimed nodes, as bits, taken in id order: brick by
    // brick, so that the offers of one brick's nodes land in the same few
    // bricks.
    let mut frontier = vec![0u64; claims.words()];
    while claims.take_into(&mut frontier) {
        rounds += 1;
        // Read the frontier before anyone writes: the round is a pure function
        // of the previous one, whatever the thread count.
        // Only the points are kept (4 bytes a frontier node, the round's
        // largest buffer): a node's own squared distance is recomputed from
        // its point in `offer`, by the formula that stored it.
        let snapshot: Vec<Vec<u32>> = frontier
            .par_chunks(FRONTIER_WORDS)
            .enumerate()
            .map(|(c, words)| {
                let mut out = Vec::new();
                for_each_bit(c, words, |u| out.push(cells.load(u) as u32));
                out
            })
            .collect();
        frontier
            .par_chunks(FRONTIER_WORDS)
            .zip(snapshot.par_iter())
            .enumerate()
            .for_each(|(c, (words, vs))| {
                let mut i = 0;
                for_each_bit(c, words, |u| {
                    if let Some(&ahead) = vs.get(i + POINT_PREFETCH) {
                        asperity_core::memory_hints::prefetch(points, ahead as usize);
                    }
                    offer(&wave, (u as u32, vs[i]), cap2);
                    i += 1;
                });
            });
        progress.advance(1);
    }
    progress.finish();
    (cells, rounds)
}

/// Frontier bitmap words handed to one task.
const FRONTIER_WORDS: usize = 1024;

/// Calls `f` with each node of chunk `c`'s frontier `words`, in order.
#[inline(always)]
fn for_each_bit(c: usize, words: &[u64], mut f: impl FnMut(usize)) {
    for (k, &w) in words.iter().enumerate() {
        let base = (c * FRONTIER_WORDS + k) * 64;
        let mut bits = w;
        while bits != 0 {
            f(base + bits.trailing_zeros() as usize);
            bits &= bits - 1;
        }
    }
}

/// Gives the 2³ nodes of each point's cell their exact squared distance and
/// the point's index (the dense method's seeds, ring 0), claiming the nodes
/// that received a value.
fn seed(points: &[[f64; 3]], space: &Bricks, cells: &Cells, claims: &Claims) {
    let grid = &space.grid;
    let h = grid.spacing;
    let base_of = |p: &[f64; 3]| {
        [0, 1, 2].map(|a| {
            let cell = ((p[a] - grid.origin[a]) / h).max(0.0) as usize;
            cell.min(grid.dims[a].saturating_sub(2))
        })
    };
    points
        .par_chunks(SEED_CHUNK)
        .enumerate()
        .for_each(|(chunk, ps)| {
            for (k, p) in ps.iter().enumerate() {
                let idx = (chunk * SEED_CHUNK + k) as u32;
                let base = base_of(p);
                for z in base[2]..base[2] + 2 {
                    for y in base[1]..base[1] + 2 {
                        for x in base[0]..base[0] + 2 {
                            let Some(id) = space.id([x, y, z]) else {
                                debug_assert!(false, "seed node ({x}, {y}, {z}) is not active");
                                continue;
                            };
                            let d2 = dist2(grid.position(x, y, z), *p) as f32;
                            if lower(cells.cell(id as usize), pack(d2, idx)) {
                                claims.claim(id as usize);
                            }
                        }
                    }
                }
            }
        });
}

/// A local coordinate moved by `o` − 1 (o ∈ 0..3): the brick step (0, 1 or
/// 2 for −1, 0, +1) and the new local coordinate.
#[inline(always)]
fn wrap(l: usize, o: usize) -> (usize, usize) {
    match (l + o).checked_sub(1) {
        None => (0, SIDE - 1),
        Some(SIDE) => (2, 0),
        Some(x) => (1, x),
    }
}

/// What a wavefront's offers read and write: the points, the bricks and
/// the bricks around each slot, the packed cells and the claims of the next
/// frontier.
#[derive(Clone, Copy)]
struct Wave<'a> {
    points: &'a [[f64; 3]],
    space: &'a Bricks,
    around: &'a [[u32; 27]],
    cells: &'a Cells,
    claims: &'a Claims,
}

/// Offers the point of frontier node `u` (packed cell `v`) to its 26
/// neighbours, outward only; the neighbours it improves and claims go to `out`.
/// The dense method's `offer`, with neighbours found through the bricks
/// around `u`'s (`around`, see [`Bricks::neighbourhoods`]).
#[inline(always)]
fn offer(wave: &Wave, (u, idx): (u32, u32), cap2: f32) {
    let Wave {
        points,
        space,
        around,
        cells,
        claims,
    } = *wave;
    let grid = &space.grid;
    let p = points[idx as usize];
    let (s, l) = (u as usize / BRICK_NODES, u as usize % BRICK_NODES);
    let at = [l % SIDE, (l / SIDE) % SIDE, l / (SIDE * SIDE)];
    let b = space.slot_coords(s);
    let c = [0, 1, 2].map(|a| b[a] * SIDE + at[a]);
    let (sx, sy, sz) = (
        axis_squares(grid, c, p, 0),
        axis_squares(grid, c, p, 1),
        axis_squares(grid, c, p, 2),
    );
    // u's own squared distance to p, bit for bit the one stored with p (the
    // seeds' `dist2` and the offers sum the same squares in the same order).
    let d2_u = ((sx[1] + sy[1]) + sz[1]) as f32;
    let around = &around[s];
    for (oz, &z2) in sz.iter().enumerate() {
        let (bz, lz) = wrap(at[2], oz);
        for (oy, &y2) in sy.iter().enumerate() {
            let (by, ly) = wrap(at[1], oy);
            for (ox, &x2) in sx.iter().enumerate() {
                if (ox, oy, oz) == (1, 1, 1) {
                    continue;
                }
                let d2 = ((x2 + y2) + z2) as f32;
                // Nodes nearer to p than u were passed by p's wave already:
                // only offer p outward.
                if d2 >= cap2 || d2 < d2_u {
                    continue;
                }
                let (bx, lx) = wrap(at[0], ox);
                // In the grid (off-grid squares are infinite) and within the
                // cap, so active.
                let slot = around[bx + 3 * (by + 3 * bz)];
                if slot == super::layout::NO_SLOT {
                    debug_assert!(false, "a node within the cap is not active");
                    continue;
                }
                let node = slot as usize * BRICK_NODES + local(lx, ly, lz);
                if lower(cells.cell(node), pack(d2, idx)) {
                    claims.claim(node);
                }
            }
        }
    }
}

/// The capacity to give a field of `n` values that later stages extend: an
/// eighth more, and the flow's two virtual slots.
pub(crate) fn headroom(n: usize) -> usize {
    n + n / 8 + 2 * BRICK_NODES
}

/// The distance of a packed cell: √d² up to `cap`, the cap where no point came.
#[inline]
pub(crate) fn cell_distance(c: u64, cap: f32) -> f32 {
    if c == EMPTY {
        cap
    } else {
        unpack_d2(c).sqrt().min(cap)
    }
}

/// The unsigned distance on active bricks: per node id, `cap` beyond it.
#[derive(Clone, Debug)]
pub struct SparseDistance {
    /// The bricks.
    pub bricks: Bricks,
    /// d per node id.
    pub values: Vec<f32>,
    /// The cap: nodes of inactive bricks read as this.
    pub cap: f32,
    /// Wavefront rounds.
    pub rounds: usize,
}

impl SparseDistance {
    /// The distances of the wavefront's `cells` on `bricks`.
    pub(crate) fn from_cells(bricks: Bricks, cells: Cells, cap: f64, rounds: usize) -> Self {
        let cap32 = cap as f32;
        // With room for the bricks later stages add and the flow's virtual
        // slot, so that they need not move the field (room never written
        // costs no memory).
        let mut values = Vec::with_capacity(headroom(cells.len()));
        cells.consume(|_, chunk| {
            values.par_extend(
                chunk
                    .par_iter()
                    .map(|c| cell_distance(c.load(Relaxed), cap32)),
            );
        });
        Self {
            bricks,
            values,
            cap: cap32,
            rounds,
        }
    }

    /// d at node `c` (the cap on inactive bricks).
    pub fn at(&self, c: [usize; 3]) -> f32 {
        self.bricks
            .id(c)
            .map_or(self.cap, |id| self.values[id as usize])
    }

    /// Activates `new` bricks (sorted), their nodes at the cap.
    pub(crate) fn activate(&mut self, new: &[u32]) {
        self.bricks.activate(new);
        self.values.resize(self.bricks.nodes(), self.cap);
    }
}

/// The closest-point distance to `points` on `grid`, capped at `cap`, on the
/// bricks within the cap of a point; and the median sample spacing (see
/// `sample_spacing`) measured on the way.
pub fn sparse_distance(
    points: &[[f64; 3]],
    grid: &crate::GridSpec,
    cap: f64,
    progress: &dyn Progress,
) -> (SparseDistance, Option<f64>) {
    let bricks = bricks_for(grid, points, cap);
    let (cells, rounds) = closest_points(points, &bricks, cap, progress);
    let spacing = sample_spacing(points, &bricks, &cells, 2.0 * grid.spacing);
    let field = SparseDistance::from_cells(bricks, cells, cap, rounds);
    (field, spacing)
}

/// The median distance between the nearest points of neighbouring nodes that
/// differ (Voronoi neighbours), over nodes within `near` of the data on every
/// ⌊n_z/16⌋-th plane: the typical sample spacing. The same nodes and pairs as
/// the dense pipeline's measure, so the same median.
pub(crate) fn sample_spacing(
    points: &[[f64; 3]],
    space: &Bricks,
    cells: &Cells,
    near: f64,
) -> Option<f64> {
    let grid = &space.grid;
    let nearest = |id: Option<u32>| {
        id.map_or(u32::MAX, |id| {
            let c = cells.load(id as usize);
            if c == EMPTY { u32::MAX } else { c as u32 }
        })
    };
    let near2 = (near * near) as f32;
    let stride = (grid.dims[2] / 16).max(1);
    let mut gaps: Vec<f32> = (0..space.slots())
        .into_par_iter()
        .flat_map_iter(|s| {
            let b = space.slot_coords(s);
            (0..SIDE)
                .map(move |z| b[2] * SIDE + z)
                .filter(move |&k| k < grid.dims[2] && k.is_multiple_of(stride))
                .flat_map(move |k| {
                    (0..SIDE * SIDE).filter_map(move |r| {
                        let c = [b[0] * SIDE + r % SIDE, b[1] * SIDE + r / SIDE, k];
                        (c[0] < grid.dims[0] && c[1] < grid.dims[1]).then_some(c)
                    })
                })
        })
        .filter_map(|c| {
            let id = space.id(c)?;
            let v = cells.load(id as usize);
            (v != EMPTY && unpack_d2(v) < near2).then_some((c, v as u32))
        })
        .flat_map_iter(|(c, p)| {
            (0..3).filter_map(move |a| {
                if c[a] + 1 >= grid.dims[a] {
                    return None;
                }
                let mut n = c;
                n[a] += 1;
                let q = nearest(space.id(n));
                if q == p || q == u32::MAX {
                    return None;
                }
                let (x, y) = (points[p as usize], points[q as usize]);
                Some(
                    (((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt())
                        as f32,
                )
            })
        })
        .collect();
    if gaps.is_empty() {
        return None;
    }
    let mid = gaps.len() / 2;
    let (_, m, _) = gaps.select_nth_unstable_by(mid, f32::total_cmp);
    Some(f64::from(*m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::{DistanceMethod, unsigned_distance};
    use crate::grid::{GridSpec, Sizing};
    use asperity_core::{MemoryBudget, NoProgress};
    use rand::{Rng, SeedableRng};

    fn cloud(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..n)
            .map(|_| {
                // Clustered: most of the box stays far from the points.
                let centre = [(n % 3) as f64 * 4.0, 1.0, 2.0];
                let c = if rng.random::<f64>() < 0.5 {
                    centre
                } else {
                    [9.0, 7.0, 5.0]
                };
                [0, 1, 2].map(|a| c[a] + rng.random::<f64>() * 1.5)
            })
            .collect()
    }

    /// Every node equals the dense wavefront's: distance and nearest point.
    #[test]
    fn sparse_wavefront_equals_the_dense_one() {
        for (n, res, seed) in [(400, 48, 1), (2000, 70, 2), (50, 33, 3)] {
            let pts = cloud(n, seed);
            let grid = GridSpec::around(
                &pts,
                Sizing::Resolution(res),
                |_| 5,
                &MemoryBudget::unlimited(),
            )
            .unwrap();
            let cap = 4.0 * grid.spacing;
            let dense =
                unsigned_distance(&pts, &grid, DistanceMethod::ClosestPoint, cap, &NoProgress);
            let bricks = bricks_for(&grid, &pts, cap);
            assert!(
                bricks.slots() < bricks.brick_count(),
                "the test needs inactive bricks"
            );
            let (cells, rounds) = closest_points(&pts, &bricks, cap, &NoProgress);
            assert_eq!(rounds, dense.sweeps);
            let near = dense.nearest.as_ref().unwrap();
            for (u, &nearest) in near.iter().enumerate() {
                let c = grid.coords(u);
                let (d, p) = match bricks.id(c) {
                    Some(id) => {
                        let v = cells.load(id as usize);
                        (
                            cell_distance(v, cap as f32),
                            if v == EMPTY { u32::MAX } else { v as u32 },
                        )
                    }
                    None => (cap as f32, u32::MAX),
                };
                assert_eq!(d.to_bits(), dense.values[u].to_bits(), "node {c:?}");
                assert_eq!(p, nearest, "node {c:?}");
            }
        }
    }
}
