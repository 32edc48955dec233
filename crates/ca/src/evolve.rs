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
//! - [`BitGrid`]: two-state rules on cyclic grids of any width, one bit per
//!   cell; the neighbourhood sum of 64 cells at a time comes from bit-sliced
//!   adders (horizontal 3-sums per row, reused by the three output rows that need
//!   them) and the table becomes a sum of products over the sum's bit planes. A
//!   width that is not a multiple of 64 leaves the row's last word partly
//!   filled: its spare bits are kept zero, and the wrap-around neighbours of the
//!   row's ends are taken from the cells themselves (until #26 such widths fell
//!   back to the byte path, 5–7 times slower). Rows are split over threads in
//!   fixed blocks, so the output does not depend on the thread count.
//!
//! [peridier]: https://www.mathematica-journal.com/2011/07/facetsurface-representation/ "Peridier: Rough-Surface Simulation and the Visualization of Nonsmooth Arrays of Data. The Mathematica Journal, 2011"

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

/// A two-state grid with one bit per cell: bit b of word k of row j is cell
/// (64k + b, j). Bits past `nx` in a row's last word are zero.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BitGrid {
    /// Cells per row.
    pub nx: usize,
    /// Words per row (`nx / 64` rounded up).
    pub words: usize,
    /// Rows.
    pub ny: usize,
    /// Row-major words.
    pub bits: Vec<u64>,
}

/// Rows per parallel block of the bit-sliced step.
const BLOCK: usize = 32;

/// Bit grids of fewer words than this (64 cells each) step on one thread: a
/// step of 2¹⁸ cells takes about as long as handing work to the pool and
/// waiting for it (measured: a 64² grid spent 90 % of its time in futex and
/// sched_yield when parallel).
pub(crate) const SEQUENTIAL_WORDS: usize = 4096;

impl BitGrid {
    /// Packs a 0/1 byte grid of `nx × ny` cells.
    ///
    /// # Panics
    /// If `nx` is 0 or the size does not match.
    pub fn from_bytes(cells: &[u8], nx: usize, ny: usize) -> Self {
        assert!(nx > 0 && cells.len() == nx * ny, "BitGrid size mismatch");
        let words = nx.div_ceil(64);
        let bits = cells
            .chunks_exact(nx)
            .flat_map(|row| {
                row.chunks(64).map(|c| {
                    c.iter()
                        .enumerate()
                        .fold(0u64, |w, (b, &v)| w | ((v != 0) as u64) << b)
                })
            })
            .collect();
        Self {
            nx,
            words,
            ny,
            bits,
        }
    }

    /// Unpacks to one byte per cell.
    pub fn to_bytes(&self) -> Vec<u8> {
        self.bits
            .chunks_exact(self.words)
            .flat_map(|row| (0..self.nx).map(move |i| (row[i / 64] >> (i % 64) & 1) as u8))
            .collect()
    }

    /// Valid cells of a row's last word (1–64).
    pub(crate) fn tail_bits(&self) -> u32 {
        (self.nx - 64 * (self.words - 1)) as u32
    }

    /// One step of the two-state `rule` (cyclic), into `dst`.
    ///
    /// # Panics
    /// If the rule has more than two states or `dst` has another shape.
    pub fn step_into(&self, rule: &Rule, dst: &mut BitGrid) {
        assert!(rule.states() == 2 && dst.bits.len() == self.bits.len());
        let luts = Luts::new(rule);
        let w = self.words;
        let simd = Simd::detect();
        if dst.bits.len() < SEQUENTIAL_WORDS {
            // A small grid: waking the thread pool costs more than the step.
            dst.bits
                .chunks_mut(BLOCK * w)
                .enumerate()
                .for_each(|(b, out)| simd.block(&luts, self, b, out));
            return;
        }
        dst.bits
            .par_chunks_mut(BLOCK * w)
            .enumerate()
            .for_each(|(b, out)| simd.block(&luts, self, b, out));
    }
}

/// The widest vector unit this CPU offers, chosen once per step. The kernel
/// is the same source compiled three times; the results are identical bit for
/// bit (integer logic only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Simd {
    Baseline,
    #[cfg(target_arch = "x86_64")]
    Avx2,
    #[cfg(target_arch = "x86_64")]
    Avx512,
}

impl Simd {
    fn detect() -> Self {
        if std::env::var_os("ASPERITY_NO_SIMD").is_some() {
            return Simd::Baseline;
        }
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return Simd::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return Simd::Avx2;
            }
        }
        Simd::Baseline
    }

    #[inline]
    fn block(self, luts: &Luts, grid: &BitGrid, b: usize, out: &mut [u64]) {
        match self {
            Simd::Baseline => block(luts, grid, b, out),
            // SAFETY: `detect` verified at run time that the CPU supports the
            // feature each function is compiled for; that is their only requirement.
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            Simd::Avx2 => unsafe { block_avx2(luts, grid, b, out) },
            #[cfg(target_arch = "x86_64")]
            #[allow(unsafe_code)]
            Simd::Avx512 => unsafe { block_avx512(luts, grid, b, out) },
        }
    }
}

/// [`block`] compiled for AVX2 (four 64-bit lanes).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn block_avx2(luts: &Luts, grid: &BitGrid, b: usize, out: &mut [u64]) {
    block(luts, grid, b, out);
}

/// [`block`] compiled for AVX-512 (eight 64-bit lanes).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn block_avx512(luts: &Luts, grid: &BitGrid, b: usize, out: &mut [u64]) {
    block(luts, grid, b, out);
}

/// Output rows `b·BLOCK …` of one step. Per row: the horizontal sums of the
/// next row (kept in a ring of three), then one fused pass that adds the three
/// rows' sums into bit planes and evaluates the table on them; both loops are
/// elementwise over the row's words, so the compiler vectorises them.
#[inline(always)]
fn block(luts: &Luts, grid: &BitGrid, b: usize, out: &mut [u64]) {
    let (src, w, ny) = (&grid.bits[..], grid.words, grid.ny);
    let tail = grid.tail_bits();
    let tail_mask = if tail == 64 { !0 } else { (1u64 << tail) - 1 };
    let j0 = b * BLOCK;
    let rows = out.len() / w;
    let row = |j: usize| &src[(j % ny) * w..][..w];
    let mut h: [(Vec<u64>, Vec<u64>); 3] = std::array::from_fn(|_| (vec![0; w], vec![0; w]));
    horizontal(row(j0 + ny - 1), &mut h[0], luts.moore, tail);
    horizontal(row(j0), &mut h[1], luts.moore, tail);
    for r in 0..rows {
        let j = j0 + r;
        horizontal(row(j + 1), &mut h[(r + 2) % 3], luts.moore, tail);
        let (above, centre, below) = (row(j + ny - 1), row(j), row(j + 1));
        let (up, mid, down) = (&h[r % 3], &h[(r + 1) % 3], &h[(r + 2) % 3]);
        // Equal-length slices let the compiler drop bounds checks and vectorise.
        let (u0, u1, m0, m1, d0, d1) = (
            &up.0[..w],
            &up.1[..w],
            &mid.0[..w],
            &mid.1[..w],
            &down.0[..w],
            &down.1[..w],
        );
        let (above, centre, below) = (&above[..w], &centre[..w], &below[..w]);
        let dst = &mut out[r * w..][..w];
        if luts.moore {
            for k in 0..w {
                let p = sum3x2((u0[k], u1[k]), (m0[k], m1[k]), (d0[k], d1[k]));
                dst[k] = luts.eval(p, centre[k]);
            }
        } else {
            for k in 0..w {
                let p = sum_von_neumann((m0[k], m1[k]), centre[k], above[k], below[k]);
                dst[k] = luts.eval(p, centre[k]);
            }
        }
        // The spare bits past the row's end stay zero.
        dst[w - 1] &= tail_mask;
    }
}

/// Sum of three 2-bit numbers (0..=9) as four bit planes.
#[inline(always)]
fn sum3x2((a0, a1): (u64, u64), (b0, b1): (u64, u64), (c0, c1): (u64, u64)) -> [u64; 4] {
    let s0 = a0 ^ b0 ^ c0;
    let k0 = (a0 & b0) | (c0 & (a0 ^ b0));
    let t = a1 ^ b1 ^ c1;
    let m = (a1 & b1) | (c1 & (a1 ^ b1));
    let cc = t & k0;
    [s0, t ^ k0, m ^ cc, m & cc]
}

/// (west + east) + centre + up + down (0..=5) as bit planes.
#[inline(always)]
fn sum_von_neumann((a0, a1): (u64, u64), c: u64, u: u64, d: u64) -> [u64; 4] {
    let x = c ^ u ^ d;
    let y = (c & u) | (d & (c ^ u));
    let k0 = a0 & x;
    let t = a1 ^ y;
    [a0 ^ x, t ^ k0, (a1 & y) | (t & k0), 0]
}

/// Horizontal neighbourhood of each word into two planes: for Moore the 3-sum
/// west + centre + east, for von Neumann west + east. The row wraps around:
/// with `tail` valid bits in its last word (1–64, the rest zero), the west
/// neighbour of cell 0 is that word's bit `tail − 1` and the east neighbour of
/// that bit is cell 0.
#[inline(always)]
fn horizontal(row: &[u64], out: &mut (Vec<u64>, Vec<u64>), moore: bool, tail: u32) {
    let w = row.len();
    let (o0, o1) = (&mut out.0[..w], &mut out.1[..w]);
    let mut put = |k: usize, west: u64, c: u64, east: u64| {
        if moore {
            o0[k] = west ^ c ^ east;
            o1[k] = (west & c) | (east & (west ^ c));
        } else {
            o0[k] = west ^ east;
            o1[k] = west & east;
        }
    };
    let west_of = |prev: u64, c: u64| c << 1 | prev >> 63;
    let east_of = |c: u64, next: u64| c >> 1 | next << 63;
    // A word whose bit 63 is the row's last cell, and the east side of the last
    // word (its spare bits are zero, so shifting them in adds nothing).
    let last_cell_at_63 = row[w - 1] << (64 - tail);
    let tail_east = |c: u64| c >> 1 | (row[0] & 1) << (tail - 1);
    if w == 1 {
        let c = row[0];
        put(0, west_of(last_cell_at_63, c), c, tail_east(c));
        return;
    }
    put(
        0,
        west_of(last_cell_at_63, row[0]),
        row[0],
        east_of(row[0], row[1]),
    );
    for k in 1..w - 1 {
        put(
            k,
            west_of(row[k - 1], row[k]),
            row[k],
            east_of(row[k], row[k + 1]),
        );
    }
    put(
        w - 1,
        west_of(row[w - 2], row[w - 1]),
        row[w - 1],
        tail_east(row[w - 1]),
    );
}

/// The rule as a boolean function of the neighbourhood sum's bit planes
/// p0…p3, in a fixed-shape form that needs no branches: with a_i the four
/// combinations of (p0, p1) and b_i the three reachable combinations of (p2, p3)
/// (sums 0–3, 4–7, 8–9), f = Σ_i b_i · (Σ_j a_j · M[i][j]) where the mask
/// M[i][j] is all ones when the table gives 1 for the sum 4i + j.
struct Luts {
    moore: bool,
    /// Whether the new state depends on the centre beyond the total sum.
    outer: bool,
    /// Masks for centre 0 and centre 1.
    m0: [[u64; 4]; 3],
    m1: [[u64; 4]; 3],
}

impl Luts {
    fn new(rule: &Rule) -> Self {
        let t = rule.table();
        let fam = rule.family();
        let outer = matches!(fam, Family::Outer9 | Family::Outer5);
        let max = if fam.moore() { 9 } else { 5 };
        let (mut m0, mut m1) = ([[0u64; 4]; 3], [[0u64; 4]; 3]);
        for s in 0..=max {
            // Total sum s with centre 0: others = s; with centre 1: others = s − 1.
            let (i0, i1) = if outer {
                (Some(2 * s), (s >= 1).then(|| 2 * s - 1))
            } else {
                (Some(s), Some(s))
            };
            if i0.and_then(|i| t.get(i)) == Some(&1) {
                m0[s / 4][s % 4] = !0;
            }
            if s >= 1 && i1.and_then(|i| t.get(i)) == Some(&1) {
                m1[s / 4][s % 4] = !0;
            }
        }
        // Totalistic rules: the two tables agree wherever both are reachable.
        let m1 = if outer { m1 } else { m0 };
        Self {
            moore: fam.moore(),
            outer,
            m0,
            m1,
        }
    }

    #[inline(always)]
    fn eval(&self, p: [u64; 4], centre: u64) -> u64 {
        let (n0, n1, n2, n3) = (!p[0], !p[1], !p[2], !p[3]);
        let a = [n0 & n1, p[0] & n1, n0 & p[1], p[0] & p[1]];
        let b = [n2 & n3, p[2] & n3, n2 & p[3]];
        let f = |m: &[[u64; 4]; 3]| {
            let g = |i: usize| {
                (a[0] & m[i][0]) | (a[1] & m[i][1]) | (a[2] & m[i][2]) | (a[3] & m[i][3])
            };
            (b[0] & g(0)) | (b[1] & g(1)) | (b[2] & g(2))
        };
        let f0 = f(&self.m0);
        if !self.outer {
            return f0;
        }
        (f0 & !centre) | (f(&self.m1) & centre)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::seeded;
    use rand::Rng;

    #[test]
    fn vector_kernels_equal_the_baseline() {
        let mut rng = seeded(5);
        for (family, code) in [
            (Family::Totalistic9, 450u128),
            (Family::Outer9, 224),
            (Family::Totalistic5, 37),
            (Family::Outer5, 777),
        ] {
            let rule = Rule::new(family, 2, code).unwrap();
            let (nx, ny) = (256, 70);
            let cells: Vec<u8> = (0..nx * ny).map(|_| rng.random_range(0..2)).collect();
            let g = BitGrid::from_bytes(&cells, nx, ny);
            let luts = Luts::new(&rule);
            let w = g.words;
            let mut base = vec![0u64; g.bits.len()];
            let mut fast = vec![0u64; g.bits.len()];
            for (b, out) in base.chunks_mut(BLOCK * w).enumerate() {
                Simd::Baseline.block(&luts, &g, b, out);
            }
            let simd = Simd::detect();
            for (b, out) in fast.chunks_mut(BLOCK * w).enumerate() {
                simd.block(&luts, &g, b, out);
            }
            assert_eq!(base, fast, "{family:?} {code} with {simd:?}");
            // And both equal the byte-per-cell step.
            let mut bytes = vec![0u8; nx * ny];
            step_bytes(&rule, &cells, &mut bytes, nx, ny);
            assert_eq!(
                BitGrid {
                    nx,
                    words: w,
                    ny,
                    bits: base
                }
                .to_bytes(),
                bytes
            );
        }
    }

    #[test]
    fn any_width_equals_the_byte_step() {
        // Widths around the word size, and a one-word row that wraps on itself:
        // the bit grid must wrap exactly like the byte step, for several steps.
        let mut rng = seeded(9);
        for (family, code) in [
            (Family::Totalistic9, 450u128),
            (Family::Outer9, 224),
            (Family::Totalistic5, 37),
            (Family::Outer5, 777),
        ] {
            let rule = Rule::new(family, 2, code).unwrap();
            for (nx, ny) in [(1, 3), (5, 7), (63, 9), (65, 4), (100, 40), (191, 5)] {
                let mut cells: Vec<u8> = (0..nx * ny).map(|_| rng.random_range(0..2)).collect();
                let mut g = BitGrid::from_bytes(&cells, nx, ny);
                assert_eq!(g.to_bytes(), cells);
                let mut next = g.clone();
                let mut bytes = vec![0u8; nx * ny];
                for step in 0..4 {
                    g.step_into(&rule, &mut next);
                    std::mem::swap(&mut g, &mut next);
                    step_bytes(&rule, &cells, &mut bytes, nx, ny);
                    std::mem::swap(&mut cells, &mut bytes);
                    assert_eq!(
                        g.to_bytes(),
                        cells,
                        "{family:?} {code} {nx}x{ny} step {step}"
                    );
                    let tail = g.tail_bits();
                    if tail < 64 {
                        assert!(
                            g.bits.chunks(g.words).all(|r| r[g.words - 1] >> tail == 0),
                            "spare bits stay zero"
                        );
                    }
                }
            }
        }
    }
}
