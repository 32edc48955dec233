//! Evolution of a 2-D cellular automaton: cyclic grids and Mathematica's
//! infinite background.
//!
//! Paper: [peridier] §"Cellular Automaton Basics" (one step = for each cell, sum
//! its neighbourhood and look the sum up in the rule's table) and the
//! `CellularAutomaton` calls behind `FacetSurfaceGridData`.
//!
//! # Two boundary modes, as Mathematica has them
//! - [`Boundary::Cyclic`]: an explicit grid whose edges wrap around (a torus).
//! - [`Boundary::Infinite`]: the initial pattern sits on an infinite background
//!   (0 at first). Each step the region that can differ from the background grows
//!   by one cell on every side, so after T steps a p×q pattern has become
//!   (p+2T)×(q+2T), and every step is reported on that final region, padded with
//!   the background of its step. If the rule turns an all-background
//!   neighbourhood into another state (table entry 0 non-zero), the background
//!   itself changes from step to step, as Mathematica's does.
//!
//! # Two implementations
//! - [`step_bytes`]: one byte per cell, any family and any number of states,
//!   rows in parallel. Also the reference for the fast path.
//! - [`BitGrid`]: two-state rules on cyclic grids whose width is a multiple of
//!   64, one bit per cell; the neighbourhood sum of 64 cells at a time comes from
//!   bit-sliced adders (horizontal 3-sums per row, reused by the three output rows
//!   that need them) and the table becomes a sum of products over the sum's bit
//!   planes. Rows are split over threads in fixed blocks, so the output does not
//!   depend on the thread count.
//!
//! [peridier]: ../shared/papers/peridier_ca-rough-surfaces-facet-visualization.txt

use rayon::prelude::*;

use crate::rule::{Family, Rule};

/// How the grid's edges behave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// Edges wrap around.
    Cyclic,
    /// The pattern sits on an infinite background; the region grows each step.
    Infinite,
}

/// One step of `rule` on a cyclic `nx × ny` byte grid (x fastest), `src` → `dst`.
///
/// # Panics
/// If the slices are not `nx·ny` long.
pub fn step_bytes(rule: &Rule, src: &[u8], dst: &mut [u8], nx: usize, ny: usize) {
    assert!(
        src.len() == nx * ny && dst.len() == nx * ny,
        "grid size mismatch"
    );
    let moore = rule.family().moore();
    dst.par_chunks_mut(nx).enumerate().for_each(|(j, out)| {
        let up = &src[((j + ny - 1) % ny) * nx..][..nx];
        let mid = &src[j * nx..][..nx];
        let down = &src[((j + 1) % ny) * nx..][..nx];
        for (i, o) in out.iter_mut().enumerate() {
            let (l, r) = ((i + nx - 1) % nx, (i + 1) % nx);
            let c = mid[i] as u32;
            let mut others = mid[l] as u32 + mid[r] as u32 + up[i] as u32 + down[i] as u32;
            if moore {
                others += up[l] as u32 + up[r] as u32 + down[l] as u32 + down[r] as u32;
            }
            *o = rule.next(c, others);
        }
    });
}

/// One step on a finite region surrounded by `background`: the result is the
/// region grown by one cell on each side, and the new background.
pub fn step_infinite(
    rule: &Rule,
    src: &[u8],
    nx: usize,
    ny: usize,
    background: u8,
) -> (Vec<u8>, usize, usize, u8) {
    let (mx, my) = (nx + 2, ny + 2);
    // Old cell (i, j) sits at (i + 2, j + 2) in a frame two cells wider on each
    // side, so every new cell's neighbourhood is inside the frame.
    let (fx, fy) = (nx + 4, ny + 4);
    let mut frame = vec![background; fx * fy];
    for j in 0..ny {
        frame[(j + 2) * fx + 2..][..nx].copy_from_slice(&src[j * nx..][..nx]);
    }
    let moore = rule.family().moore();
    let mut out = vec![0u8; mx * my];
    out.par_chunks_mut(mx).enumerate().for_each(|(j, row)| {
        let f = |x: usize, y: usize| frame[y * fx + x] as u32;
        for (i, o) in row.iter_mut().enumerate() {
            let (x, y) = (i + 1, j + 1);
            let c = f(x, y);
            let mut others = f(x - 1, y) + f(x + 1, y) + f(x, y - 1) + f(x, y + 1);
            if moore {
                others += f(x - 1, y - 1) + f(x + 1, y - 1) + f(x - 1, y + 1) + f(x + 1, y + 1);
            }
            *o = rule.next(c, others);
        }
    });
    let n_others = if moore { 8 } else { 4 };
    let b = background as u32;
    (out, mx, my, rule.next(b, b * n_others))
}

/// A two-state grid with one bit per cell, `nx` a multiple of 64: bit b of word
/// k of row j is cell (64k + b, j).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitGrid {
    /// Words per row.
    pub words: usize,
    /// Rows.
    pub ny: usize,
    /// Row-major words.
    pub bits: Vec<u64>,
}

/// Rows per parallel block of the bit-sliced step.
const BLOCK: usize = 32;

impl BitGrid {
    /// Packs a 0/1 byte grid (`nx` must be a multiple of 64).
    ///
    /// # Panics
    /// If `nx % 64 != 0` or the size does not match.
    pub fn from_bytes(cells: &[u8], nx: usize, ny: usize) -> Self {
        assert!(
            nx.is_multiple_of(64) && cells.len() == nx * ny,
            "BitGrid needs nx % 64 == 0"
        );
        let words = nx / 64;
        let bits = cells
            .chunks_exact(64)
            .map(|c| {
                c.iter()
                    .enumerate()
                    .fold(0u64, |w, (b, &v)| w | ((v != 0) as u64) << b)
            })
            .collect();
        Self { words, ny, bits }
    }

    /// Unpacks to one byte per cell.
    pub fn to_bytes(&self) -> Vec<u8> {
        self.bits
            .iter()
            .flat_map(|&w| (0..64).map(move |b| (w >> b & 1) as u8))
            .collect()
    }

    /// One step of the two-state `rule` (cyclic), into `dst`.
    ///
    /// # Panics
    /// If the rule has more than two states or `dst` has another shape.
    pub fn step_into(&self, rule: &Rule, dst: &mut BitGrid) {
        assert!(rule.states() == 2 && dst.bits.len() == self.bits.len());
        let luts = Luts::new(rule);
        let (w, ny) = (self.words, self.ny);
        let src = &self.bits;
        dst.bits
            .par_chunks_mut(BLOCK * w)
            .enumerate()
            .for_each(|(b, out)| {
                let j0 = b * BLOCK;
                let rows = out.len() / w;
                let mut hs: [Vec<(u64, u64)>; 3] = std::array::from_fn(|_| vec![(0, 0); w]);
                let row = |j: usize| &src[(j % ny) * w..][..w];
                horizontal(row(j0 + ny - 1), &mut hs[0], luts.moore);
                horizontal(row(j0), &mut hs[1], luts.moore);
                for r in 0..rows {
                    let j = j0 + r;
                    horizontal(row(j + 1), &mut hs[(r + 2) % 3], luts.moore);
                    let (up, mid, down) = (&hs[r % 3], &hs[(r + 1) % 3], &hs[(r + 2) % 3]);
                    let (above, centre, below) = (row(j + ny - 1), row(j), row(j + 1));
                    let dst_row = &mut out[r * w..][..w];
                    for k in 0..w {
                        dst_row[k] =
                            luts.apply(up[k], mid[k], down[k], [above[k], centre[k], below[k]]);
                    }
                }
            });
    }
}

/// Horizontal neighbourhood of each word: for Moore, the 3-sum (west + centre +
/// east) as two bit planes; for von Neumann, (west + east) as two planes.
#[inline]
fn horizontal(row: &[u64], out: &mut [(u64, u64)], moore: bool) {
    let w = row.len();
    for k in 0..w {
        let c = row[k];
        let prev = row[(k + w - 1) % w];
        let next = row[(k + 1) % w];
        let west = c << 1 | prev >> 63;
        let east = c >> 1 | next << 63;
        out[k] = if moore {
            (west ^ c ^ east, (west & c) | (east & (west ^ c)))
        } else {
            (west ^ east, west & east)
        };
    }
}

/// The table as sums of products over the neighbourhood sum's bit planes.
struct Luts {
    moore: bool,
    /// Whether the new state depends on the centre beyond the total sum.
    outer: bool,
    /// Bit v set: new state 1 for total sum v when the centre is 0 / 1.
    when0: u16,
    when1: u16,
}

impl Luts {
    fn new(rule: &Rule) -> Self {
        let t = rule.table();
        let fam = rule.family();
        let outer = matches!(fam, Family::Outer9 | Family::Outer5);
        let max = if fam.moore() { 9 } else { 5 };
        let (mut when0, mut when1) = (0u16, 0u16);
        for s in 0..=max {
            // Total sum s with centre 0: others = s; with centre 1: others = s − 1.
            let (i0, i1) = if outer {
                (Some(2 * s), (s >= 1).then(|| 2 * s - 1))
            } else {
                (Some(s), Some(s))
            };
            if i0.and_then(|i| t.get(i)) == Some(&1) {
                when0 |= 1 << s;
            }
            if s >= 1 && i1.and_then(|i| t.get(i)) == Some(&1) {
                when1 |= 1 << s;
            }
        }
        // Totalistic rules: centre 1 needs total ≥ 1, so the two tables agree
        // wherever both are reachable.
        Self {
            moore: fam.moore(),
            outer,
            when0,
            when1: if outer { when1 } else { when0 },
        }
    }

    #[inline(always)]
    fn apply(&self, up: (u64, u64), mid: (u64, u64), down: (u64, u64), raw: [u64; 3]) -> u64 {
        let [up_c, centre, down_c] = raw;
        let p = if self.moore {
            sum3x2(up, mid, down)
        } else {
            sum_von_neumann(mid, centre, up_c, down_c)
        };
        let f0 = lookup(p, self.when0);
        if !self.outer {
            return f0;
        }
        let f1 = lookup(p, self.when1);
        (f0 & !centre) | (f1 & centre)
    }
}

/// Sum of three 2-bit numbers (0..=9) as four bit planes.
#[inline(always)]
fn sum3x2((a0, a1): (u64, u64), (b0, b1): (u64, u64), (c0, c1): (u64, u64)) -> [u64; 4] {
    let s0 = a0 ^ b0 ^ c0;
    let k0 = (a0 & b0) | (c0 & (a0 ^ b0));
    let t = a1 ^ b1 ^ c1;
    let m = (a1 & b1) | (c1 & (a1 ^ b1));
    let s1 = t ^ k0;
    let cc = t & k0;
    [s0, s1, m ^ cc, m & cc]
}

/// (west + east) + centre + up + down (0..=5) as bit planes.
#[inline(always)]
fn sum_von_neumann((a0, a1): (u64, u64), c: u64, u: u64, d: u64) -> [u64; 4] {
    let x = c ^ u ^ d;
    let y = (c & u) | (d & (c ^ u));
    let s0 = a0 ^ x;
    let k0 = a0 & x;
    let t = a1 ^ y;
    [s0, t ^ k0, (a1 & y) | (t & k0), 0]
}

/// OR over the sums v with bit v of `table` set of [planes == v].
#[inline(always)]
fn lookup(p: [u64; 4], table: u16) -> u64 {
    let n = [!p[0], !p[1], !p[2], !p[3]];
    let mut acc = 0;
    let mut bits = table;
    while bits != 0 {
        let v = bits.trailing_zeros();
        bits &= bits - 1;
        let pick = |b: u32| {
            if v >> b & 1 == 1 {
                p[b as usize]
            } else {
                n[b as usize]
            }
        };
        acc |= pick(0) & pick(1) & pick(2) & pick(3);
    }
    acc
}
