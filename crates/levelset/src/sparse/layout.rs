//! The sparse layout: 8³-node bricks allocated only where a stage needs values.
//!
//! The grid of [`GridSpec`] is cut into bricks of 8 × 8 × 8 nodes (the last
//! brick along an axis may reach past the grid; its outside nodes exist in
//! memory and are never part of any set). A table over all bricks gives each
//! *active* brick a slot; node `l = x + 8y + 64z` of the brick in slot `s` has
//! the id `512 s + l`, and every field of the pipeline is a plain `Vec` indexed
//! by id. A brick's rows along x are eight consecutive values, the width of
//! the flow's vector lanes. Bricks that are not active hold no values: each
//! field says what they read as (the distance cap, ±γ by the brick's tag).
//!
//! Slots are handed out in increasing brick order at each activation, and
//! later activations append, so ids depend only on the inputs, never on the
//! thread count. Orders that decide results (tie-breaks, the mesh's vertex and
//! triangle order) use the dense index `i + n_x (j + n_y k)`, so that the
//! sparse stages reproduce the dense ones.

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use rayon::prelude::*;

use crate::grid::GridSpec;

/// Nodes along each axis of a brick.
pub const SIDE: usize = 8;
/// Nodes in a brick.
pub const BRICK_NODES: usize = SIDE * SIDE * SIDE;
/// No slot: the brick is not active.
pub(crate) const NO_SLOT: u32 = u32::MAX;

/// A set of a brick's nodes: word z holds plane z, bit x + 8y.
pub(crate) type Mask = [u64; SIDE];

/// One brick's values of a field.
pub(crate) type BrickValues = [f32; BRICK_NODES];

/// Row `r` (y + 8z) of a brick's values, with no bounds to check.
#[inline(always)]
pub(crate) fn brick_row(b: &BrickValues, r: usize) -> &[f32; SIDE] {
    let at = (r % (SIDE * SIDE)) * SIDE;
    b[at..at + SIDE].try_into().expect("a row of eight")
}

/// The empty mask.
pub(crate) const EMPTY_MASK: Mask = [0; SIDE];

/// Bits of the nodes with x = 0 in a plane word.
pub(crate) const X_LOW: u64 = 0x0101_0101_0101_0101;
/// Bits of the nodes with x = 7 in a plane word.
pub(crate) const X_HIGH: u64 = X_LOW << 7;
/// Bits of the nodes with y = 0 in a plane word.
pub(crate) const Y_LOW: u64 = 0xFF;
/// Bits of the nodes with y = 7 in a plane word.
pub(crate) const Y_HIGH: u64 = 0xFF << 56;

/// Whether a mask has no node.
#[inline]
pub(crate) fn is_empty(m: &Mask) -> bool {
    m.iter().all(|&w| w == 0)
}

/// The number of nodes in a mask.
#[inline]
pub(crate) fn count(m: &Mask) -> usize {
    m.iter().map(|w| w.count_ones() as usize).sum()
}

/// `m`'s nodes moved one node along direction `dir` (−x, +x, −y, +y, −z,
/// +z: each node gets its neighbour's bit that way) within the brick.
#[inline(always)]
pub(crate) fn shifted(m: &Mask, dir: usize) -> Mask {
    std::array::from_fn(|z| match dir {
        0 => (m[z] << 1) & !X_LOW,
        1 => (m[z] >> 1) & !X_HIGH,
        2 => m[z] << SIDE,
        3 => m[z] >> SIDE,
        4 => z.checked_sub(1).map_or(0, |below| m[below]),
        _ => m.get(z + 1).copied().unwrap_or(0),
    })
}

/// The local index of brick node (x, y, z).
#[inline(always)]
pub(crate) const fn local(x: usize, y: usize, z: usize) -> usize {
    x + SIDE * (y + SIDE * z)
}

/// Active bricks and their slots on a grid.
#[derive(Clone, Debug)]
pub struct Bricks {
    /// The grid the bricks cut.
    pub grid: GridSpec,
    /// Bricks along each axis.
    pub bdims: [usize; 3],
    /// Per brick (x fastest), its slot or [`NO_SLOT`].
    slot_of: Vec<u32>,
    /// Per slot, its brick.
    brick_of: Vec<u32>,
    /// Per slot, its brick's coordinates.
    coords_of: Vec<[u32; 3]>,
}

impl Bricks {
    /// No active brick.
    pub fn new(grid: &GridSpec) -> Self {
        let bdims = grid.dims.map(|n| n.div_ceil(SIDE));
        Self {
            grid: *grid,
            bdims,
            slot_of: vec![NO_SLOT; bdims[0] * bdims[1] * bdims[2]],
            brick_of: Vec::new(),
            coords_of: Vec::new(),
        }
    }

    /// Every brick active: the dense grid in the brick layout.
    pub fn all(grid: &GridSpec) -> Self {
        let mut b = Self::new(grid);
        b.activate((0..b.brick_count() as u32).collect::<Vec<_>>().as_slice());
        b
    }

    /// The bricks with a node within `radius` of one of `points` (world units).
    pub fn around(grid: &GridSpec, points: &[[f64; 3]], radius: f64) -> Self {
        let mut b = Self::new(grid);
        let near = b.near(points, radius);
        b.activate(&near);
        b
    }

    /// These bricks with their slots in the order of `other`'s (which holds
    /// every one of them): a layout whose slots follow another's, so that a
    /// field on it can be read slot after slot while the other is written.
    pub(crate) fn in_slot_order_of(&self, other: &Bricks) -> Self {
        let mut b = Self::new(&self.grid);
        for s in 0..other.slots() {
            let bi = other.brick_of(s);
            if self.slot_of(bi) != NO_SLOT {
                b.push_slot(bi);
            }
        }
        debug_assert_eq!(b.slots(), self.slots(), "every brick is in `other`");
        b
    }

    /// Bricks in the grid.
    pub fn brick_count(&self) -> usize {
        self.slot_of.len()
    }

    /// Active bricks.
    pub fn slots(&self) -> usize {
        self.brick_of.len()
    }

    /// Node ids in use: 512 per active brick.
    pub fn nodes(&self) -> usize {
        self.brick_of.len() * BRICK_NODES
    }

    /// The linear index of brick `b`.
    #[inline(always)]
    pub(crate) fn brick_index(&self, b: [usize; 3]) -> usize {
        b[0] + self.bdims[0] * (b[1] + self.bdims[1] * b[2])
    }

    /// The brick coordinates of linear index `bi`.
    #[inline(always)]
    pub(crate) fn brick_coords(&self, bi: usize) -> [usize; 3] {
        let x = bi % self.bdims[0];
        let rest = bi / self.bdims[0];
        [x, rest % self.bdims[1], rest / self.bdims[1]]
    }

    /// The slot of brick `bi`, or [`NO_SLOT`].
    #[inline(always)]
    pub(crate) fn slot_of(&self, bi: usize) -> u32 {
        self.slot_of[bi]
    }

    /// The brick of slot `s`.
    #[inline(always)]
    pub(crate) fn brick_of(&self, s: usize) -> usize {
        self.brick_of[s] as usize
    }

    /// The coordinates of the brick in slot `s`.
    #[inline(always)]
    pub(crate) fn slot_coords(&self, s: usize) -> [usize; 3] {
        self.coords_of[s].map(|x| x as usize)
    }

    /// Activates the bricks `new` (sorted, no repeats; active ones are
    /// skipped), appending their slots in that order; returns the first new
    /// slot.
    pub(crate) fn activate(&mut self, new: &[u32]) -> usize {
        let first = self.brick_of.len();
        // Slots in Morton order of the bricks, so that neighbours along every
        // axis lie near each other in memory.
        let mut new = new.to_vec();
        new.sort_unstable_by_key(|&bi| morton(self.brick_coords(bi as usize)));
        for &bi in &new {
            if self.slot_of[bi as usize] == NO_SLOT {
                self.push_slot(bi as usize);
            }
        }
        first
    }

    /// Gives brick `bi` the next slot.
    fn push_slot(&mut self, bi: usize) {
        self.slot_of[bi] = self.brick_of.len() as u32;
        self.brick_of.push(bi as u32);
        self.coords_of.push(self.brick_coords(bi).map(|x| x as u32));
    }

    /// The id of node `c`, if its brick is active.
    #[inline(always)]
    pub(crate) fn id(&self, c: [usize; 3]) -> Option<u32> {
        let b = [c[0] / SIDE, c[1] / SIDE, c[2] / SIDE];
        let s = self.slot_of[self.brick_index(b)];
        (s != NO_SLOT)
            .then(|| s * BRICK_NODES as u32 + local(c[0] % SIDE, c[1] % SIDE, c[2] % SIDE) as u32)
    }

    /// The grid coordinates of node `id` (for tests).
    #[cfg(test)]
    pub(crate) fn coords(&self, id: u32) -> [usize; 3] {
        let id = id as usize;
        let b = self.slot_coords(id / BRICK_NODES);
        let l = id % BRICK_NODES;
        [
            b[0] * SIDE + l % SIDE,
            b[1] * SIDE + (l / SIDE) % SIDE,
            b[2] * SIDE + l / (SIDE * SIDE),
        ]
    }

    /// The nodes of the brick at `b` that lie in the grid.
    pub(crate) fn in_grid(&self, b: [usize; 3]) -> Mask {
        self.between(b, [0; 3], self.grid.dims)
    }

    /// The nodes of the brick at `b` at least `margin` nodes from every face
    /// of the grid.
    pub(crate) fn within(&self, b: [usize; 3], margin: usize) -> Mask {
        let hi = self.grid.dims.map(|n| n.saturating_sub(margin));
        self.between(b, [margin; 3], hi)
    }

    /// The nodes of the brick at `b` in the grid whose upper neighbour along
    /// `axis` is in the grid too.
    pub(crate) fn within_upper(&self, b: [usize; 3], axis: usize) -> Mask {
        let mut hi = self.grid.dims;
        hi[axis] -= 1;
        self.between(b, [0; 3], hi)
    }

    /// The nodes of the brick at `b` in the grid whose lower neighbour along
    /// `axis` is in the grid too.
    pub(crate) fn within_lower(&self, b: [usize; 3], axis: usize) -> Mask {
        let mut lo = [0; 3];
        lo[axis] = 1;
        self.between(b, lo, self.grid.dims)
    }

    /// The nodes of the brick at `b` whose grid coordinates lie in `lo..hi`
    /// along every axis.
    fn between(&self, b: [usize; 3], lo: [usize; 3], hi: [usize; 3]) -> Mask {
        let span = |a: usize| {
            let first = b[a] * SIDE;
            let l = lo[a].saturating_sub(first).min(SIDE);
            (l, hi[a].saturating_sub(first).min(SIDE).max(l))
        };
        let ((x0, x1), (y0, y1), (z0, z1)) = (span(0), span(1), span(2));
        let row = ((1u64 << x1) - 1) & !((1u64 << x0) - 1);
        let mut plane = 0u64;
        for y in y0..y1 {
            plane |= row << (SIDE * y);
        }
        std::array::from_fn(|z| if (z0..z1).contains(&z) { plane } else { 0 })
    }

    /// The slots of the six face neighbours of slot `s` (−x, +x, −y, +y, −z,
    /// +z), [`NO_SLOT`] where the neighbour is inactive or beyond the grid.
    pub(crate) fn face_slots(&self, s: usize) -> [u32; 6] {
        let b = self.slot_coords(s);
        std::array::from_fn(|f| {
            let (axis, up) = (f / 2, f % 2 == 1);
            let mut n = b;
            if up {
                n[axis] += 1;
                if n[axis] >= self.bdims[axis] {
                    return NO_SLOT;
                }
            } else {
                if n[axis] == 0 {
                    return NO_SLOT;
                }
                n[axis] -= 1;
            }
            self.slot_of[self.brick_index(n)]
        })
    }

    /// Per slot, the slots of the 27 bricks around it (offset (dx, dy, dz) ∈
    /// {−1, 0, 1}³ at index dx+1 + 3(dy+1) + 9(dz+1); [`NO_SLOT`] where
    /// inactive or beyond the grid).
    pub(crate) fn neighbourhoods(&self) -> Vec<[u32; 27]> {
        (0..self.slots())
            .into_par_iter()
            .map(|s| {
                let b = self.slot_coords(s);
                std::array::from_fn(|i| {
                    let o = [i % 3, (i / 3) % 3, i / 9];
                    let mut n = [0usize; 3];
                    for a in 0..3 {
                        match (b[a] + o[a]).checked_sub(1) {
                            Some(x) if x < self.bdims[a] => n[a] = x,
                            _ => return NO_SLOT,
                        }
                    }
                    self.slot_of[self.brick_index(n)]
                })
            })
            .collect()
    }

    /// Per direction (−x, +x, −y, +y, −z, +z), the nodes of slot `s` on that
    /// face whose neighbour across it is in the set: `mask(slot)` gives an
    /// active neighbour's set, `tile(brick)` whether an inactive one is all in
    /// it; nothing lies beyond the grid.
    pub(crate) fn across_faces(
        &self,
        s: usize,
        mask: impl Fn(usize) -> Mask,
        tile: impl Fn(usize) -> bool,
    ) -> [Mask; 6] {
        let b = self.slot_coords(s);
        let faces = self.face_slots(s);
        std::array::from_fn(|dir| {
            let (a, up) = (dir / 2, dir % 2 == 1);
            let beyond = if up {
                b[a] + 1 >= self.bdims[a]
            } else {
                b[a] == 0
            };
            if beyond {
                return EMPTY_MASK;
            }
            let theirs: Mask = if faces[dir] == NO_SLOT {
                let mut n = b;
                if up {
                    n[a] += 1;
                } else {
                    n[a] -= 1;
                }
                if tile(self.brick_index(n)) {
                    [u64::MAX; SIDE]
                } else {
                    EMPTY_MASK
                }
            } else {
                mask(faces[dir] as usize)
            };
            // Their face next to ours, moved onto our face.
            match dir {
                0 => theirs.map(|w| (w & X_HIGH) >> (SIDE - 1)),
                1 => theirs.map(|w| (w & X_LOW) << (SIDE - 1)),
                2 => theirs.map(|w| (w & Y_HIGH) >> (SIDE * (SIDE - 1))),
                3 => theirs.map(|w| (w & Y_LOW) << (SIDE * (SIDE - 1))),
                4 => {
                    let mut m = EMPTY_MASK;
                    m[0] = theirs[SIDE - 1];
                    m
                }
                _ => {
                    let mut m = EMPTY_MASK;
                    m[SIDE - 1] = theirs[0];
                    m
                }
            }
        })
    }

    /// The bricks, in increasing order, with a node within `radius` of one
    /// of `points` (a sphere–box test on each brick's nodes), whether active or
    /// not.
    pub(crate) fn near(&self, points: &[[f64; 3]], radius: f64) -> Vec<u32> {
        let grid = &self.grid;
        let h = grid.spacing;
        let marks: Vec<AtomicU64> = (0..self.brick_count().div_ceil(64))
            .map(|_| AtomicU64::new(0))
            .collect();
        let r2 = radius * radius;
        points.par_chunks(4096).for_each(|chunk| {
            for p in chunk {
                // The nodes within the cube of half-side `radius`, per axis.
                let range = |a: usize| {
                    let lo = ((p[a] - radius - grid.origin[a]) / h).ceil().max(0.0);
                    let hi = ((p[a] + radius - grid.origin[a]) / h).floor();
                    let last = (grid.dims[a] - 1) as f64;
                    (lo <= last && hi >= 0.0 && lo <= hi)
                        .then(|| (lo as usize / SIDE, hi.min(last) as usize / SIDE))
                };
                let (Some(bx), Some(by), Some(bz)) = (range(0), range(1), range(2)) else {
                    continue;
                };
                // The squared distance from p to the span of a brick's nodes
                // along axis a.
                let gap2 = |a: usize, b: usize| {
                    let lo = grid.origin[a] + (b * SIDE) as f64 * h;
                    let hi =
                        grid.origin[a] + ((b * SIDE + SIDE - 1).min(grid.dims[a] - 1)) as f64 * h;
                    let g = (lo - p[a]).max(p[a] - hi).max(0.0);
                    g * g
                };
                for z in bz.0..=bz.1 {
                    let gz = gap2(2, z);
                    for y in by.0..=by.1 {
                        let gy = gz + gap2(1, y);
                        if gy > r2 {
                            continue;
                        }
                        for x in bx.0..=bx.1 {
                            if gy + gap2(0, x) <= r2 {
                                let bi = self.brick_index([x, y, z]);
                                marks[bi / 64].fetch_or(1 << (bi % 64), Relaxed);
                            }
                        }
                    }
                }
            }
        });
        marks
            .iter()
            .enumerate()
            .flat_map(|(w, m)| {
                let mut bits = m.load(Relaxed);
                std::iter::from_fn(move || {
                    (bits != 0).then(|| {
                        let b = bits.trailing_zeros();
                        bits &= bits - 1;
                        (w * 64) as u32 + b
                    })
                })
            })
            .collect()
    }
}

/// The Morton (Z-order) key of brick coordinates: their bits interleaved.
fn morton(b: [usize; 3]) -> u64 {
    let spread = |x: usize| {
        let mut x = x as u64 & 0x1F_FFFF;
        x = (x | x << 32) & 0x1F_0000_0000_FFFF;
        x = (x | x << 16) & 0x1F_0000_FF00_00FF;
        x = (x | x << 8) & 0x100F_00F0_0F00_F00F;
        x = (x | x << 4) & 0x10C3_0C30_C30C_30C3;
        (x | x << 2) & 0x1249_2492_4924_9249
    };
    spread(b[0]) | spread(b[1]) << 1 | spread(b[2]) << 2
}

/// The radius [`Bricks::around`] needs so that every node a closest-point
/// wavefront capped at `cap` writes is active: the cap (or the √3·h of the
/// seed cells, if larger) with a margin for the wavefront's `f32` rounding.
pub(crate) fn wavefront_radius(cap: f64, h: f64) -> f64 {
    cap.max(3f64.sqrt() * h) * (1.0 + 1e-5) + 1e-9 * h
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Sizing;
    use asperity_core::MemoryBudget;

    fn grid() -> GridSpec {
        GridSpec::around(
            &[[0.0; 3], [3.0, 2.0, 1.3]],
            Sizing::Resolution(30),
            |_| 2,
            &MemoryBudget::unlimited(),
        )
        .unwrap()
    }

    #[test]
    fn ids_and_coordinates_round_trip() {
        let g = grid();
        let b = Bricks::all(&g);
        for c in [
            [0, 0, 0],
            [7, 8, 9],
            [g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1],
        ] {
            assert_eq!(b.coords(b.id(c).unwrap()), c);
        }
        let inside: usize = (0..b.slots())
            .map(|s| count(&b.in_grid(b.slot_coords(s))))
            .sum();
        assert_eq!(inside, g.len());
    }

    #[test]
    fn nodes_within_a_margin_of_the_faces() {
        let g = grid();
        let b = Bricks::all(&g);
        for margin in [0, 1, 2, 9] {
            let got: usize = (0..b.slots())
                .map(|s| count(&b.within(b.slot_coords(s), margin)))
                .sum();
            let want = (0..3)
                .map(|a| g.dims[a].saturating_sub(2 * margin))
                .product::<usize>();
            assert_eq!(got, want, "margin {margin}");
        }
    }

    /// The activated bricks are exactly those with a node within the radius,
    /// by brute force over the nodes.
    #[test]
    fn bricks_near_points_are_those_with_a_node_within_the_radius() {
        let g = grid();
        let pts = [[0.2, 0.3, 0.1], [2.9, 1.9, 1.2], [1.5, 1.0, 0.6]];
        let r = 0.35;
        let b = Bricks::around(&g, &pts, r);
        let mut expected = vec![false; b.brick_count()];
        for u in 0..g.len() {
            let c = g.coords(u);
            let x = g.position(c[0], c[1], c[2]);
            if pts.iter().any(|p| crate::distance::dist2(x, *p) <= r * r) {
                expected[b.brick_index([c[0] / SIDE, c[1] / SIDE, c[2] / SIDE])] = true;
            }
        }
        let got: Vec<bool> = (0..b.brick_count())
            .map(|bi| b.slot_of(bi) != NO_SLOT)
            .collect();
        assert_eq!(got, expected);
        assert!(b.slots() > 3 && b.slots() < b.brick_count());
    }
}
