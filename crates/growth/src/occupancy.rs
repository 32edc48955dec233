//! Bit-packed voxel occupancy with a coarse Chebyshev distance map, the data
//! structure behind the lattice walkers of [`crate::dla`] and the curved
//! substrates of [`crate::curved`].
//!
//! **Bits.** The lattice is cut into 4×4×4 blocks and each block is one `u64`
//! (bit `x | y<<2 | z<<4` of the block). A block is empty iff its word is zero, so
//! the block occupancy costs nothing extra, and a walker's six neighbours
//! mostly lie in the word it already has in cache.
//!
//! **Tiles.** Blocks are stored in tiles of 8×8×8 blocks (32³ cells, 4 KiB: one
//! memory page), tile after tile, rather than row by row. The cells near a
//! walker then share a page and mostly a cache line, and a sparse cluster
//! writes only the pages it occupies: the vectors start zeroed (untouched
//! pages cost no memory), so a 10⁷-particle cluster in a 2232³ lattice
//! (1.4 GB of bits if written) keeps about its own tiles resident. Axes one
//! block thick (the y of 2-D runs) are not tiled.
//!
//! **Distance maps.** One byte per block of 2^s cells holds the Chebyshev
//! distance, in blocks, to the nearest occupied block, capped. A walker in a
//! block at distance k is at least `2^s (k − 1) + 1` cells, and usually more,
//! from every occupied cell ([`DistanceMap::lower_bound`]), which is how far it
//! may jump in one move. Walkers use a fine map (4-cell blocks) and a coarse one
//! (32-cell blocks), each capped at 8 blocks: a hierarchy whose update is cheap
//! (a particle added to an occupied block costs nothing; a new block costs a few
//! shells of blocks around it) and whose bound reaches 224 cells. The maps are
//! tiled in 32-cell tiles too, and store `cap − distance`, so the far field is
//! zero and its pages are never written.
//!
//! Both structures are periodic in x and y when asked (plane mode), open
//! otherwise (cells outside the lattice are empty).
//!
//! **Sharing.** Words and map entries are atomics read and written with
//! relaxed ordering (plain loads and stores on x86-64), so walkers on other
//! threads may read a lattice while one thread adds particles to it (the
//! speculative walkers of [`crate::dla`]). [`Occupancy::set`] is an atomic
//! `or`, safe from any number of threads; [`DistanceMap::occupy`] lowers
//! entries with plain stores and wants one writer at a time. The vectors are
//! allocated zeroed by `bytemuck` (no page is written until a cell is).

use std::sync::atomic::{AtomicU8, AtomicU64, Ordering::Relaxed};

use asperity_core::MemoryBudget;

use crate::GrowthError;

/// The six face neighbours of a cell on the cubic lattice.
pub const FACE_NEIGHBOURS: [[i32; 3]; 6] = [
    [-1, 0, 0],
    [1, 0, 0],
    [0, -1, 0],
    [0, 1, 0],
    [0, 0, -1],
    [0, 0, 1],
];

/// Blocks stored tile by tile: tiles of 2^shift blocks along each axis that
/// has more than one block, tiles in x-fastest order, blocks x-fastest inside a
/// tile.
#[derive(Clone, Copy, Debug)]
struct Tiling {
    /// Blocks per axis.
    blocks: [usize; 3],
    /// log2 of the tile's extent in blocks, per axis (0 on a one-block axis).
    shift: [u32; 3],
    /// Tiles per axis.
    tiles: [usize; 3],
}

impl Tiling {
    fn new(blocks: [usize; 3], shift: u32) -> Self {
        let shift = blocks.map(|b| if b > 1 { shift } else { 0 });
        let tiles = [0, 1, 2].map(|a| blocks[a].div_ceil(1 << shift[a]));
        Self {
            blocks,
            shift,
            tiles,
        }
    }

    /// Entries, tiles padded to whole tiles.
    fn len(&self) -> usize {
        self.tiles.iter().product::<usize>() << self.shift.iter().sum::<u32>()
    }

    /// Entries of a tiled array over `blocks` (the padded count).
    fn estimate(blocks: [usize; 3], shift: u32) -> u128 {
        Self::new(blocks, shift).len() as u128
    }

    #[inline(always)]
    fn index(&self, b: [usize; 3]) -> usize {
        let [sx, sy, sz] = self.shift;
        let tile = (b[0] >> sx) + self.tiles[0] * ((b[1] >> sy) + self.tiles[1] * (b[2] >> sz));
        let local = (b[0] & ((1 << sx) - 1))
            | (b[1] & ((1 << sy) - 1)) << sx
            | (b[2] & ((1 << sz) - 1)) << (sx + sy);
        (tile << (sx + sy + sz)) | local
    }
}

/// log2 of a tile's extent in cells (32).
const TILE_CELLS_SHIFT: u32 = 5;

/// Occupancy of a lattice of cells, one bit per cell, in 4×4×4 blocks.
#[derive(Debug)]
pub struct Occupancy {
    dims: [i32; 3],
    tiling: Tiling,
    periodic: bool,
    words: Vec<AtomicU64>,
    count: AtomicU64,
}

impl Occupancy {
    /// Bytes of the bits of a lattice of `dims` cells.
    pub fn estimate_bytes(dims: [usize; 3]) -> u128 {
        Tiling::estimate(dims.map(|d| d.div_ceil(4)), TILE_CELLS_SHIFT - 2) * 8
    }

    /// An empty lattice of `dims` cells, periodic in x and y if `periodic`.
    ///
    /// # Errors
    /// A zero or too-large dimension, or the memory budget.
    pub fn new(
        dims: [usize; 3],
        periodic: bool,
        budget: &MemoryBudget,
    ) -> Result<Self, GrowthError> {
        if dims.contains(&0) || dims.iter().any(|&d| d > (1 << 20)) {
            return Err(GrowthError::BadParameter(format!(
                "lattice size {}x{}x{} must be between 1 and 1048576 in each axis",
                dims[0], dims[1], dims[2]
            )));
        }
        if periodic && (!dims[0].is_multiple_of(4) || (dims[1] > 1 && !dims[1].is_multiple_of(4))) {
            return Err(GrowthError::BadParameter(format!(
                "a periodic lattice needs x and y sizes divisible by 4, got {}x{}",
                dims[0], dims[1]
            )));
        }
        budget.check_elements(Self::estimate_bytes(dims), 1, "lattice occupancy")?;
        let tiling = Tiling::new(dims.map(|d| d.div_ceil(4)), TILE_CELLS_SHIFT - 2);
        Ok(Self {
            dims: dims.map(|d| d as i32),
            tiling,
            periodic,
            // Zeroed memory comes untouched from the system: pages the cluster
            // never writes cost nothing.
            words: bytemuck::allocation::zeroed_vec(tiling.len()),
            count: AtomicU64::new(0),
        })
    }

    /// Lattice size in cells.
    pub fn dims(&self) -> [usize; 3] {
        self.dims.map(|d| d as usize)
    }

    /// Blocks per axis.
    pub fn blocks(&self) -> [usize; 3] {
        self.tiling.blocks
    }

    /// Whether x and y wrap around.
    pub fn periodic(&self) -> bool {
        self.periodic
    }

    /// Occupied cells.
    pub fn count(&self) -> u64 {
        self.count.load(Relaxed)
    }

    /// The cell `p` mapped into the lattice (x, y wrapped when periodic), or
    /// `None` outside it.
    #[inline(always)]
    pub fn canonical(&self, p: [i32; 3]) -> Option<[i32; 3]> {
        let [nx, ny, nz] = self.dims;
        let (x, y) = if self.periodic {
            (p[0].rem_euclid(nx), p[1].rem_euclid(ny))
        } else {
            (p[0], p[1])
        };
        if x < 0 || y < 0 || p[2] < 0 || x >= nx || y >= ny || p[2] >= nz {
            return None;
        }
        Some([x, y, p[2]])
    }

    #[inline(always)]
    fn word_bit(&self, p: [i32; 3]) -> (usize, u32) {
        let [x, y, z] = p.map(|v| v as usize);
        let w = self.tiling.index([x >> 2, y >> 2, z >> 2]);
        let b = (x & 3) | ((y & 3) << 2) | ((z & 3) << 4);
        (w, b as u32)
    }

    /// Calls `f` with every occupied cell of the box `lo..=hi`, clipped to
    /// the lattice and not wrapped, block by block: an empty block costs one
    /// load, an occupied one a step per occupied cell.
    pub fn for_each_in_box(&self, lo: [i32; 3], hi: [i32; 3], mut f: impl FnMut([i32; 3])) {
        let lo = [0, 1, 2].map(|a| lo[a].max(0));
        let hi = [0, 1, 2].map(|a| hi[a].min(self.dims[a] - 1));
        if (0..3).any(|a| lo[a] > hi[a]) {
            return;
        }
        for bz in lo[2] >> 2..=hi[2] >> 2 {
            for by in lo[1] >> 2..=hi[1] >> 2 {
                for bx in lo[0] >> 2..=hi[0] >> 2 {
                    let index = self.tiling.index([bx, by, bz].map(|b| b as usize));
                    let mut word = self.words[index].load(Relaxed);
                    while word != 0 {
                        let b = word.trailing_zeros() as i32;
                        word &= word - 1;
                        let p = [4 * bx + (b & 3), 4 * by + (b >> 2 & 3), 4 * bz + (b >> 4)];
                        if (0..3).all(|a| lo[a] <= p[a] && p[a] <= hi[a]) {
                            f(p);
                        }
                    }
                }
            }
        }
    }

    /// Whether cell `p` is occupied (false outside the lattice).
    #[inline(always)]
    pub fn get(&self, p: [i32; 3]) -> bool {
        match self.canonical(p) {
            Some(q) => {
                let (w, b) = self.word_bit(q);
                self.words[w].load(Relaxed) >> b & 1 == 1
            }
            None => false,
        }
    }

    /// Occupies cell `p` (inside the lattice); returns whether its block was
    /// empty before, and the block's index. An atomic `or`: threads may set
    /// cells of one lattice at once.
    ///
    /// # Panics
    /// If `p` lies outside the lattice.
    #[inline]
    pub fn set(&self, p: [i32; 3]) -> (bool, usize) {
        let q = self.canonical(p).expect("cell inside the lattice");
        let (w, b) = self.word_bit(q);
        let old = self.words[w].fetch_or(1 << b, Relaxed);
        if old >> b & 1 == 0 {
            self.count.fetch_add(1, Relaxed);
        }
        (old == 0, w)
    }

    /// Whether any face neighbour of `p` is occupied: the 6 of the cubic lattice
    /// when `three_d`, else the 4 of the x–z plane (2-D runs live in that plane,
    /// z up, so a deposit on a line grows upward as in 3-D).
    #[inline(always)]
    pub fn touches(&self, p: [i32; 3], three_d: bool) -> bool {
        let [x, y, z] = p;
        let [nx, ny, nz] = self.dims;
        if x >= 1 && y >= 1 && z >= 1 && x < nx - 1 && y < ny - 1 && z < nz - 1 {
            // Interior: every neighbour is inside; no wrapping or range checks.
            let bit = |q: [i32; 3]| {
                let (w, b) = self.word_bit(q);
                self.words[w].load(Relaxed) >> b & 1
            };
            let mut any = bit([x - 1, y, z]) | bit([x + 1, y, z]);
            any |= bit([x, y, z - 1]) | bit([x, y, z + 1]);
            if three_d {
                any |= bit([x, y - 1, z]) | bit([x, y + 1, z]);
            }
            return any != 0;
        }
        self.get([x - 1, y, z])
            || self.get([x + 1, y, z])
            || self.get([x, y, z - 1])
            || self.get([x, y, z + 1])
            || (three_d && (self.get([x, y - 1, z]) || self.get([x, y + 1, z])))
    }

    /// Sets the face neighbours of `p` that lie inside the lattice (the 4 of
    /// the x–z plane unless `three_d`). A lattice that gets this for every
    /// occupied cell of another is its *contact set*: its bit at `w` equals
    /// the other's [`Occupancy::touches`] at `w` (the neighbour relation is
    /// symmetric), read from one word.
    pub fn set_neighbours(&self, p: [i32; 3], three_d: bool) {
        for e in FACE_NEIGHBOURS {
            if three_d || e[1] == 0 {
                let n = [p[0] + e[0], p[1] + e[1], p[2] + e[2]];
                if let Some(q) = self.canonical(n) {
                    self.set(q);
                }
            }
        }
    }

    /// The word of cell `p`'s block (0 outside the lattice), for loops that
    /// stay inside one block; [`Occupancy::bit_in_block`] picks `p`'s bit.
    #[inline(always)]
    pub fn block_word(&self, p: [i32; 3]) -> u64 {
        match self.canonical(p) {
            Some(q) => self.words[self.word_bit(q).0].load(Relaxed),
            None => 0,
        }
    }

    /// Asks the CPU for the word of cell `p` (canonical) ahead of a look-up.
    #[inline(always)]
    pub fn prefetch(&self, p: [i32; 3]) {
        asperity_core::memory_hints::prefetch(&self.words, self.word_bit(p).0);
    }

    /// Cell `p`'s bit in its block's word.
    #[inline(always)]
    pub fn bit_in_block(p: [i32; 3]) -> u32 {
        ((p[0] & 3) | ((p[1] & 3) << 2) | ((p[2] & 3) << 4)) as u32
    }
}

/// Capped Chebyshev distance, in blocks of 2^shift cells, from every block to
/// the nearest occupied one.
#[derive(Debug)]
pub struct DistanceMap {
    shift: u32,
    cap: u8,
    tiling: Tiling,
    periodic: bool,
    /// `cap − distance` per block, tiled: 0 far from the cluster, `cap` in an
    /// occupied block.
    closeness: Vec<AtomicU8>,
}

impl DistanceMap {
    /// The map of an empty lattice shaped like `occ`, with blocks of 2^`shift`
    /// cells and distances capped at `cap` blocks.
    ///
    /// # Panics
    /// If `cap` is 0, or periodic sizes are not multiples of the block size.
    pub fn new(occ: &Occupancy, shift: u32, cap: u8) -> Self {
        assert!(cap >= 1);
        let s = 1usize << shift;
        let dims = occ.dims();
        if occ.periodic() {
            assert!(
                dims[0].is_multiple_of(s) && (dims[1] == 1 || dims[1].is_multiple_of(s)),
                "periodic sizes must be multiples of the block size"
            );
        }
        let tiling = Tiling::new(
            dims.map(|d| d.div_ceil(s)),
            TILE_CELLS_SHIFT.saturating_sub(shift),
        );
        Self {
            shift,
            cap,
            tiling,
            periodic: occ.periodic(),
            closeness: bytemuck::allocation::zeroed_vec(tiling.len()),
        }
    }

    /// Bytes of a map with blocks of 2^`shift` cells over `dims` cells.
    pub fn estimate_bytes(dims: [usize; 3], shift: u32) -> u128 {
        Tiling::estimate(
            dims.map(|d| d.div_ceil(1 << shift)),
            TILE_CELLS_SHIFT.saturating_sub(shift),
        )
    }

    /// The largest bound the map can give, in cells.
    pub fn reach(&self) -> f64 {
        (((self.cap as i64 - 1) << self.shift) + 1) as f64
    }

    /// The distance of `p`'s block (canonical `p`) to the nearest occupied
    /// block, in blocks, capped: what [`DistanceMap::bound`],
    /// [`DistanceMap::is_near`] and [`DistanceMap::is_cap`] take.
    #[inline(always)]
    pub fn block_distance(&self, p: [i32; 3]) -> u8 {
        self.cap - self.closeness[self.entry(p)].load(Relaxed)
    }

    /// The cells whose occupation would lower `p`'s block distance `k` (a
    /// cube of blocks within k − 1 of p's block, as an inclusive box of cells
    /// that may reach past the lattice), or `None` when k is 0.
    #[inline(always)]
    pub fn influence(&self, p: [i32; 3], k: u8) -> Option<([i32; 3], [i32; 3])> {
        if k == 0 {
            return None;
        }
        let (sh, k) = (self.shift, k as i32);
        let b = p.map(|v| v >> sh);
        Some((b.map(|v| (v - k + 1) << sh), b.map(|v| ((v + k) << sh) - 1)))
    }

    #[inline(always)]
    fn entry(&self, p: [i32; 3]) -> usize {
        self.tiling.index(p.map(|v| (v as usize) >> self.shift))
    }

    /// Asks the CPU for `p`'s entry ahead of a look-up (canonical `p`).
    #[inline(always)]
    pub fn prefetch(&self, p: [i32; 3]) {
        asperity_core::memory_hints::prefetch(&self.closeness, self.entry(p));
    }

    /// Records that cell `p` (canonical) became occupied. Shells of blocks around
    /// its block are lowered to their Chebyshev distance k until a whole shell
    /// needs no change: the capped distance is 1-Lipschitz, so no farther shell
    /// can need one either.
    ///
    /// Entries are lowered with plain (relaxed) stores while readers may look:
    /// one writer at a time.
    pub fn occupy(&self, p: [i32; 3]) {
        let w = self.entry(p);
        if self.closeness[w].load(Relaxed) == self.cap {
            return;
        }
        self.closeness[w].store(self.cap, Relaxed);
        let nb = self.tiling.blocks.map(|v| v as i64);
        let c = p.map(|v| ((v as usize) >> self.shift) as i64);
        let periodic = self.periodic;
        // Coordinate c + d along axis a, wrapped or None outside.
        let at = |a: usize, d: i64| -> Option<usize> {
            let v = c[a] + d;
            if periodic && a < 2 {
                Some(v.rem_euclid(nb[a]) as usize)
            } else if v < 0 || v >= nb[a] {
                None
            } else {
                Some(v as usize)
            }
        };
        let tiling = self.tiling;
        for k in 1..self.cap as i64 {
            let close = self.cap - k as u8;
            let mut changed = false;
            for dz in -k..=k {
                let Some(z) = at(2, dz) else { continue };
                for dy in -k..=k {
                    let Some(y) = at(1, dy) else { continue };
                    let inner = dz.abs() < k && dy.abs() < k;
                    let mut visit = |dx: i64| {
                        if let Some(x) = at(0, dx) {
                            let e = &self.closeness[tiling.index([x, y, z])];
                            if e.load(Relaxed) < close {
                                e.store(close, Relaxed);
                                changed = true;
                            }
                        }
                    };
                    if inner {
                        visit(-k);
                        visit(k);
                    } else {
                        for dx in -k..=k {
                            visit(dx);
                        }
                    }
                }
            }
            if !changed {
                break;
            }
        }
    }

    /// A lower bound on the Euclidean distance (in cells) from cell `p` (inside
    /// the lattice, canonical) to the nearest occupied cell: 0 when p's own block
    /// is occupied. With k = the block distance, every occupied cell lies outside
    /// the cube of blocks within k − 1 of p's block, so the bound is p's distance
    /// to that cube's faces (along the axes that have more than one block).
    #[inline(always)]
    pub fn lower_bound(&self, p: [i32; 3]) -> f64 {
        self.bound(p, self.block_distance(p))
    }

    /// [`DistanceMap::lower_bound`] at `p` given its block distance `k`.
    #[inline(always)]
    pub fn bound(&self, p: [i32; 3], k: u8) -> f64 {
        let sh = self.shift;
        let k = k as i32;
        if k == 0 {
            return 0.0;
        }
        let mut d = i32::MAX;
        #[allow(clippy::needless_range_loop)] // three parallel arrays
        for a in 0..3 {
            if self.tiling.blocks[a] > 1 {
                let b = p[a] >> sh;
                let hi = ((b + k) << sh) - p[a];
                let lo = p[a] - ((b - k + 1) << sh) + 1;
                d = d.min(hi).min(lo);
            }
        }
        d as f64
    }

    /// Whether block distance `k` is within one block of an occupied block
    /// (the bound is then small and a finer map should be asked).
    #[inline(always)]
    pub fn is_near(k: u8) -> bool {
        k <= 1
    }

    /// Whether block distance `k` is the cap (the cluster may be much farther).
    #[inline(always)]
    pub fn is_cap(&self, k: u8) -> bool {
        k == self.cap
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_and_blocks() {
        let o = Occupancy::new([10, 9, 7], false, &MemoryBudget::unlimited()).unwrap();
        assert!(!o.get([3, 4, 5]));
        let (empty, w) = o.set([3, 4, 5]);
        assert!(empty);
        assert!(o.get([3, 4, 5]));
        assert!(!o.get([4, 4, 5]));
        assert_eq!(w, o.tiling.index([0, 1, 1]));
        assert!(!o.set([3, 5, 5]).0);
        assert_eq!(o.count(), 2);
        assert!(o.touches([3, 4, 6], false));
        assert!(o.touches([3, 3, 5], true));
        assert!(!o.touches([3, 3, 5], false));
        assert!(o.touches([2, 4, 5], false));
        assert!(!o.get([-1, 4, 5]));
        let p = Occupancy::new([8, 8, 4], true, &MemoryBudget::unlimited()).unwrap();
        p.set([0, 0, 1]);
        assert!(p.get([8, -8, 1]));
        assert!(p.touches([-1, 0, 1], true));
        assert!(Occupancy::new([0, 8, 4], false, &MemoryBudget::unlimited()).is_err());
        assert!(Occupancy::new([6, 8, 4], true, &MemoryBudget::unlimited()).is_err());
        assert!(Occupancy::new([1024, 1024, 1024], false, &MemoryBudget::new(1 << 20)).is_err());
    }

    #[test]
    fn distance_bound_is_a_true_lower_bound() {
        // Random occupied cells; compare the bound to the brute-force distance.
        let dims = [40usize, 32, 28];
        for periodic in [false, true] {
            let o = Occupancy::new(dims, periodic, &MemoryBudget::unlimited()).unwrap();
            let m = DistanceMap::new(&o, 2, 32);
            let m3 = DistanceMap::new(&o, 3, 3);
            let mut rng = crate::rng::fast_rng(3, 0);
            let mut cells = Vec::new();
            for _ in 0..6 {
                let p = [0, 1, 2].map(|a| crate::rng::below(&mut rng, dims[a] as u64) as i32);
                o.set(p);
                m.occupy(p);
                m3.occupy(p);
                cells.push(p);
            }
            let mut tight = 0;
            for z in 0..28 {
                for y in 0..32 {
                    for x in 0..40 {
                        let p = [x, y, z];
                        let exact = cells
                            .iter()
                            .map(|c| {
                                let mut s = 0.0;
                                for a in 0..3 {
                                    let mut d = (p[a] - c[a]).abs();
                                    if periodic && a < 2 {
                                        d = d.min(dims[a] as i32 - d);
                                    }
                                    s += (d * d) as f64;
                                }
                                s.sqrt()
                            })
                            .fold(f64::INFINITY, f64::min);
                        let lb = m.lower_bound(p);
                        assert!(lb <= exact + 1e-12, "{p:?}: bound {lb} > distance {exact}");
                        let lb3 = m3.lower_bound(p);
                        assert!(
                            lb3 <= exact + 1e-12,
                            "{p:?}: bound {lb3} > distance {exact}"
                        );
                        if lb >= 0.5 * exact {
                            tight += 1;
                        }
                    }
                }
            }
            // The bound is useful, not just valid: within a factor 2 for most cells.
            assert!(tight > 40 * 32 * 28 / 2, "{tight}");
        }
    }

    #[test]
    fn tiles_give_every_block_its_own_entry() {
        for (blocks, shift) in [
            ([13, 9, 20], 3),
            ([30, 1, 17], 3),
            ([5, 6, 7], 2),
            ([4, 4, 4], 0),
        ] {
            let t = Tiling::new(blocks, shift);
            let mut seen = vec![false; t.len()];
            for z in 0..blocks[2] {
                for y in 0..blocks[1] {
                    for x in 0..blocks[0] {
                        let e = t.index([x, y, z]);
                        assert!(!seen[e], "{blocks:?}: block {x},{y},{z} shares entry {e}");
                        seen[e] = true;
                    }
                }
            }
            // Padding only rounds up to whole tiles (none on a one-block axis).
            let padded: usize = (0..3)
                .map(|a| blocks[a].div_ceil(1 << t.shift[a]) << t.shift[a])
                .product();
            assert_eq!(t.len(), padded);
        }
    }

    #[test]
    fn contact_set_equals_touches() {
        // The DLA walker reads contact bits instead of six neighbours: the two
        // must agree on every cell, at the lattice edges and across the wrap.
        for (dims, periodic, three_d) in [
            ([24usize, 20, 36], false, true),
            ([32, 16, 12], true, true),
            ([40, 1, 28], false, false),
        ] {
            let budget = MemoryBudget::unlimited();
            let occ = Occupancy::new(dims, periodic, &budget).unwrap();
            let contact = Occupancy::new(dims, periodic, &budget).unwrap();
            let mut rng = crate::rng::fast_rng(11, 0);
            for _ in 0..60 {
                let p = [0, 1, 2].map(|a| crate::rng::below(&mut rng, dims[a] as u64) as i32);
                occ.set(p);
                contact.set_neighbours(p, three_d);
            }
            for z in -1..=dims[2] as i32 {
                for y in -1..=dims[1] as i32 {
                    for x in -1..=dims[0] as i32 {
                        let w = [x, y, z];
                        let bit = contact.block_word(w) >> Occupancy::bit_in_block(w) & 1 == 1;
                        let inside = occ.canonical(w).is_some();
                        assert_eq!(bit, inside && occ.touches(w, three_d), "{dims:?} {w:?}");
                    }
                }
            }
        }
    }
}
