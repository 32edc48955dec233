//! Growing the flow's tubes from brick to brick: the regions of a brick that
//! reach each neighbour, the bricks a tube reaches, its growth along each
//! axis, and the activation of the bricks it enters.

use super::*;

/// The 27 regions of a brick by which side of it a neighbour lies on: for
/// offset (dx, dy, dz) ∈ {−1, 0, 1}³ (index dx+1 + 3(dy+1) + 9(dz+1)), the
/// nodes whose growth by one node reaches that neighbour.
pub(super) fn regions() -> [Mask; 27] {
    std::array::from_fn(|i| {
        let o = [i % 3, (i / 3) % 3, i / 9];
        let side = |o: usize, x: usize| match o {
            0 => x == 0,
            2 => x == SIDE - 1,
            _ => true,
        };
        let mut m = EMPTY_MASK;
        for (z, w) in m.iter_mut().enumerate() {
            for y in 0..SIDE {
                for x in 0..SIDE {
                    if side(o[0], x) && side(o[1], y) && side(o[2], z) {
                        *w |= 1 << (x + SIDE * y);
                    }
                }
            }
        }
        m
    })
}

/// The bricks without storage that T grown by `shape` reaches, sorted.
pub(super) fn reached(bricks: &Bricks, t: &[Mask], shape: Neighbourhood) -> Vec<u32> {
    let regions = regions();
    let mut out: Vec<u32> = (0..bricks.slots())
        .into_par_iter()
        .flat_map_iter(|s| {
            let m = &t[s];
            let mut found = Vec::new();
            if is_empty(m) {
                return found;
            }
            let b = bricks.slot_coords(s);
            for (i, region) in regions.iter().enumerate() {
                let o = [i % 3, (i / 3) % 3, i / 9];
                let off_axes = o.iter().filter(|&&x| x != 1).count();
                if off_axes == 0 || (shape == Neighbourhood::Axes && off_axes > 1) {
                    continue;
                }
                if (0..SIDE).all(|z| m[z] & region[z] == 0) {
                    continue;
                }
                let n: Option<[usize; 3]> = (0..3)
                    .map(|a| {
                        (b[a] + o[a])
                            .checked_sub(1)
                            .filter(|&x| x < bricks.bdims[a])
                    })
                    .collect::<Option<Vec<_>>>()
                    .map(|v| [v[0], v[1], v[2]]);
                if let Some(n) = n {
                    let bi = bricks.brick_index(n);
                    if bricks.slot_of(bi) == NO_SLOT {
                        found.push(bi as u32);
                    }
                }
            }
            found
        })
        .collect();
    out.par_sort_unstable();
    out.dedup();
    out
}

/// `m` grown by one node along `axis` within the brick, plus what the
/// neighbours below (`lo`) and above (`hi`) grow into it.
pub(super) fn grow_along(axis: usize, m: &Mask, lo: Option<&Mask>, hi: Option<&Mask>) -> Mask {
    let mut out = *m;
    match axis {
        0 => {
            for z in 0..SIDE {
                let w = m[z];
                out[z] |= ((w << 1) & !X_LOW) | ((w >> 1) & !X_HIGH);
                if let Some(lo) = lo {
                    out[z] |= (lo[z] & X_HIGH) >> (SIDE - 1);
                }
                if let Some(hi) = hi {
                    out[z] |= (hi[z] & X_LOW) << (SIDE - 1);
                }
            }
        }
        1 => {
            for z in 0..SIDE {
                let w = m[z];
                out[z] |= (w << SIDE) | (w >> SIDE);
                if let Some(lo) = lo {
                    out[z] |= (lo[z] & Y_HIGH) >> (SIDE * (SIDE - 1));
                }
                if let Some(hi) = hi {
                    out[z] |= (hi[z] & Y_LOW) << (SIDE * (SIDE - 1));
                }
            }
        }
        _ => {
            for z in 0..SIDE {
                if z > 0 {
                    out[z] |= m[z - 1];
                }
                if z + 1 < SIDE {
                    out[z] |= m[z + 1];
                }
            }
            if let Some(lo) = lo {
                out[0] |= lo[SIDE - 1];
            }
            if let Some(hi) = hi {
                out[SIDE - 1] |= hi[0];
            }
        }
    }
    out
}

/// `t` grown by one node along `axis` through the bricks, into `out`.
pub(super) fn grow_axis(bricks: &Bricks, t: &[Mask], axis: usize, out: &mut Vec<Mask>) {
    out.clear();
    out.par_extend((0..bricks.slots()).into_par_iter().map(|s| {
        let f = bricks.face_slots(s);
        let get = |slot: u32| (slot != NO_SLOT).then(|| &t[slot as usize]);
        grow_along(axis, &t[s], get(f[2 * axis]), get(f[2 * axis + 1]))
    }));
}

/// N: T grown by one node along each axis, or by the 3 × 3 × 3 block, into
/// `out` (`spare` holds the block's middle step). The buffers are kept from
/// step to step: fresh ones every step cost page faults, not just copies.
pub(super) fn grow(
    bricks: &Bricks,
    t: &[Mask],
    shape: Neighbourhood,
    out: &mut Vec<Mask>,
    spare: &mut Vec<Mask>,
) {
    match shape {
        Neighbourhood::Axes => {
            out.clear();
            out.par_extend((0..bricks.slots()).into_par_iter().map(|s| {
                let f = bricks.face_slots(s);
                let get = |slot: u32| (slot != NO_SLOT).then(|| &t[slot as usize]);
                let [x, y, z] =
                    [0, 1, 2].map(|a| grow_along(a, &t[s], get(f[2 * a]), get(f[2 * a + 1])));
                std::array::from_fn(|w| x[w] | y[w] | z[w])
            }));
        }
        Neighbourhood::Cube => {
            grow_axis(bricks, t, 0, out);
            grow_axis(bricks, out, 1, spare);
            grow_axis(bricks, spare, 2, out);
        }
    }
}

/// Adds `new` bricks (sorted) to the level set, the distance and the
/// scratch buffer, at their backgrounds.
pub(super) fn activate(
    ls: &mut SparseLevelSet,
    dist: &mut SparseDistance,
    scratch: &mut Vec<f32>,
    new: &[u32],
) {
    if new.is_empty() {
        return;
    }
    let first = ls.activate(new);
    dist.activate(new);
    scratch.extend_from_slice(&ls.phi[first * BRICK_NODES..]);
}

/// The flow's masks, one per slot: T, N, the previous step's N, the new T
/// being rebuilt, the nodes that fit the ENO stencil; `spare` holds the cube
/// neighbourhood's middle step. Kept from step to step (fresh buffers every
/// step cost page faults, not just copies).
#[derive(Default)]
pub(super) struct Tubes {
    pub(super) t: Vec<Mask>,
    pub(super) n: Vec<Mask>,
    pub(super) prev_n: Vec<Mask>,
    pub(super) new_t: Vec<Mask>,
    pub(super) fits: Vec<Mask>,
    pub(super) spare: Vec<Mask>,
    /// N's shape; `None` is the full grid (N = T).
    pub(super) shape: Option<Neighbourhood>,
}

impl Tubes {
    /// N for the current T, after adding the bricks it reaches (T and the
    /// fits grow with the slots); the old N becomes the previous one.
    pub(super) fn regrow(
        &mut self,
        ls: &mut SparseLevelSet,
        dist: &mut SparseDistance,
        scratch: &mut Vec<f32>,
    ) {
        std::mem::swap(&mut self.prev_n, &mut self.n);
        match self.shape {
            None => self.n.clone_from(&self.t),
            Some(shape) => {
                let new = reached(&ls.bricks, &self.t, shape);
                if !new.is_empty() {
                    activate(ls, dist, scratch, &new);
                    let b = &ls.bricks;
                    self.t.resize(b.slots(), EMPTY_MASK);
                    let from = self.fits.len();
                    self.fits
                        .extend((from..b.slots()).map(|s| b.within(b.slot_coords(s), 2)));
                }
                grow(&ls.bricks, &self.t, shape, &mut self.n, &mut self.spare);
            }
        }
        self.prev_n.resize(self.n.len(), EMPTY_MASK);
    }
}
