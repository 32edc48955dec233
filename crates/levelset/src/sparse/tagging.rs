//! Tagging (§5.2, Algorithm 1) on the bricks of a sparse distance.
//!
//! The same result as [`crate::tagging`], node for node, for both rules: the
//! ε rule's exterior is the flood fill of {d ≥ ε} from the grid's faces; the
//! paper's rule accepts the flood fill of the far field {d ≥ cap} and decides
//! the rest of the ε flood fill, the *shell*, as Algorithm 1's queue would
//! (the dense module's docs give the argument).
//!
//! The flood fills work on bricks: a brick's nodes are a 512-bit mask (a
//! word per plane), a fill spreads inside a brick by shifting words, and the
//! nodes it reaches on a brick's faces seed the neighbouring bricks in the
//! next round (bricks of a round run in parallel; the filled set is the
//! connected set whatever the order). An inactive brick reads as the cap
//! everywhere, so a fill that reaches it takes all of it at once: its tag is
//! one bit.
//!
//! The dense module decides the shell in one sorted pass of decreasing
//! distance, which is sequential. Here the shell is decided by relaxation
//! (see `Shell`): Algorithm 1's acceptance rule is monotone in the
//! neighbours' tags and its outcome is the rule's least fixed point, so
//! bricks can raise their tags in parallel rounds until nothing changes, with
//! the same result. A node of an inactive brick next to the shell reads as
//! the cap, exterior if its brick is far field and interior if enclosed. A
//! far-field pocket behind a neck narrower than the cap (reached by the ε fill
//! but not the far fill) is made active first, as its nodes are decided one
//! by one.

use asperity_core::Progress;
use rayon::prelude::*;
use wide::f32x8;

use super::distance::SparseDistance;
use super::layout::{
    BRICK_NODES, BrickValues, Bricks, EMPTY_MASK, Mask, NO_SLOT, SIDE, X_HIGH, X_LOW, Y_HIGH,
    Y_LOW, brick_row, count, is_empty,
};
use crate::tagging::TagRule;

/// The result of tagging on bricks.
#[derive(Clone, Debug)]
pub struct SparseTags {
    /// Per node id, whether it is exterior (bit `id % 64` of word `id / 64`).
    exterior: Vec<u64>,
    /// Per brick, for the inactive ones: whether all its nodes are exterior.
    tiles: Vec<u64>,
    /// Nodes made exterior.
    pub exterior_count: usize,
    /// Nodes refused by the paper's neighbour rule.
    pub refused: usize,
}

#[inline(always)]
fn bit(bits: &[u64], i: usize) -> bool {
    bits[i / 64] >> (i % 64) & 1 == 1
}

#[inline(always)]
fn set_bit(bits: &mut [u64], i: usize) {
    bits[i / 64] |= 1 << (i % 64);
}

impl SparseTags {
    /// Whether node id `id` is exterior.
    #[inline(always)]
    pub(crate) fn node(&self, id: u32) -> bool {
        bit(&self.exterior, id as usize)
    }

    /// Whether inactive brick `bi` is exterior.
    #[inline(always)]
    pub(crate) fn tile(&self, bi: usize) -> bool {
        bit(&self.tiles, bi)
    }

    /// The exterior nodes of slot `s`.
    #[inline]
    pub(crate) fn mask(&self, s: usize) -> Mask {
        let words = &self.exterior[s * SIDE..(s + 1) * SIDE];
        std::array::from_fn(|z| words[z])
    }

    /// The inactive bricks' tags, one bit per brick.
    pub(crate) fn tiles_bits(&self) -> &[u64] {
        &self.tiles
    }

    /// Whether node `c` is exterior.
    pub fn at(&self, bricks: &Bricks, c: [usize; 3]) -> bool {
        match bricks.id(c) {
            Some(id) => self.node(id),
            None => self.tile(bricks.brick_index(c.map(|x| x / SIDE))),
        }
    }

    /// Gives the slots from `first` on (bricks just activated) their tiles'
    /// tags.
    pub(crate) fn extend(&mut self, bricks: &Bricks, first: usize) {
        self.exterior.resize(bricks.nodes() / 64, 0);
        for s in first..bricks.slots() {
            if self.tile(bricks.brick_of(s)) {
                let words = s * BRICK_NODES / 64..(s + 1) * BRICK_NODES / 64;
                self.exterior[words].fill(u64::MAX);
            }
        }
    }
}

/// A flood fill on bricks: the filled nodes of the active bricks, the filled
/// inactive bricks, and the count of filled nodes in the grid.
struct Fill {
    nodes: Vec<Mask>,
    tiles: Vec<u64>,
    count: usize,
}

/// Spreads `seed` through `open` inside a brick (6-connected).
fn spread(open: &Mask, seed: Mask) -> Mask {
    let mut f: Mask = std::array::from_fn(|z| seed[z] & open[z]);
    // Within a plane: grow by one node along x and y until nothing changes.
    let plane = |mut w: u64, open: u64| loop {
        let g = (w | ((w << 1) & !X_LOW) | ((w >> 1) & !X_HIGH) | (w << SIDE) | (w >> SIDE)) & open;
        if g == w {
            return w;
        }
        w = g;
    };
    loop {
        let before = f;
        for z in (0..SIDE).chain((0..SIDE).rev()) {
            let mut w = f[z];
            if z > 0 {
                w |= f[z - 1] & open[z];
            }
            if z + 1 < SIDE {
                w |= f[z + 1] & open[z];
            }
            f[z] = plane(w, open[z]);
        }
        if f == before {
            return f;
        }
    }
}

/// The nodes of brick `b` on the grid's faces.
fn grid_faces(bricks: &Bricks, b: [usize; 3]) -> Mask {
    let dims = bricks.grid.dims;
    let inside = bricks.in_grid(b);
    let mut m = EMPTY_MASK;
    for (z, word) in m.iter_mut().enumerate() {
        for y in 0..SIDE {
            for x in 0..SIDE {
                let c = [b[0] * SIDE + x, b[1] * SIDE + y, b[2] * SIDE + z];
                if (0..3).any(|a| c[a] == 0 || c[a] + 1 == dims[a]) {
                    *word |= 1 << (x + SIDE * y);
                }
            }
        }
    }
    std::array::from_fn(|z| m[z] & inside[z])
}

/// The seeds that the nodes `new` of brick `bi` hand to its face neighbours.
fn face_seeds(bricks: &Bricks, bi: usize, new: &Mask, out: &mut Vec<(u32, Mask)>) {
    let b = bricks.brick_coords(bi);
    let mut send = |axis: usize, up: bool, m: Mask| {
        if is_empty(&m) {
            return;
        }
        let mut n = b;
        if up {
            n[axis] += 1;
            if n[axis] >= bricks.bdims[axis] {
                return;
            }
        } else {
            if n[axis] == 0 {
                return;
            }
            n[axis] -= 1;
        }
        out.push((bricks.brick_index(n) as u32, m));
    };
    send(0, false, new.map(|w| (w & X_LOW) << (SIDE - 1)));
    send(0, true, new.map(|w| (w & X_HIGH) >> (SIDE - 1)));
    send(1, false, new.map(|w| (w & Y_LOW) << (SIDE * (SIDE - 1))));
    send(1, true, new.map(|w| (w & Y_HIGH) >> (SIDE * (SIDE - 1))));
    let mut down = EMPTY_MASK;
    down[SIDE - 1] = new[0];
    send(2, false, down);
    let mut up = EMPTY_MASK;
    up[0] = new[SIDE - 1];
    send(2, true, up);
}

/// The nodes of {d ≥ `threshold`} connected to the grid's faces within it
/// (6-connected); inactive bricks read as `far`.
fn flood(bricks: &Bricks, d: &[f32], far: f32, threshold: f32) -> Fill {
    let open: Vec<Mask> = (0..bricks.slots())
        .into_par_iter()
        .map(|s| {
            let inside = bricks.in_grid(bricks.slot_coords(s));
            let values = &d[s * BRICK_NODES..(s + 1) * BRICK_NODES];
            std::array::from_fn(|z| {
                let mut w = 0u64;
                for (l, &v) in values[z * 64..(z + 1) * 64].iter().enumerate() {
                    w |= u64::from(v >= threshold) << l;
                }
                w & inside[z]
            })
        })
        .collect();
    let tiles_open = far >= threshold;
    let mut fill = Fill {
        nodes: vec![EMPTY_MASK; bricks.slots()],
        tiles: vec![0; bricks.brick_count().div_ceil(64)],
        count: 0,
    };
    let [bx, by, bz] = bricks.bdims;
    let mut seeds: Vec<(u32, Mask)> = (0..bricks.brick_count())
        .into_par_iter()
        .filter_map(|bi| {
            let b = bricks.brick_coords(bi);
            let edge = (0..3).any(|a| b[a] == 0 || b[a] + 1 == [bx, by, bz][a]);
            edge.then(|| (bi as u32, grid_faces(bricks, b)))
        })
        .collect();
    while !seeds.is_empty() {
        seeds.par_sort_unstable_by_key(|s| s.0);
        seeds.dedup_by(|later, first| {
            if later.0 == first.0 {
                for z in 0..SIDE {
                    first.1[z] |= later.1[z];
                }
                true
            } else {
                false
            }
        });
        let fresh: Vec<(u32, Mask)> = seeds
            .par_iter()
            .filter_map(|&(bi, seed)| {
                let s = bricks.slot_of(bi as usize);
                if s == NO_SLOT {
                    let reached = bit(&fill.tiles, bi as usize);
                    return (tiles_open && !reached)
                        .then(|| (bi, bricks.in_grid(bricks.brick_coords(bi as usize))));
                }
                let (open, done) = (&open[s as usize], &fill.nodes[s as usize]);
                let start: Mask = std::array::from_fn(|z| seed[z] & !done[z]);
                if is_empty(&std::array::from_fn(|z| start[z] & open[z])) {
                    return None;
                }
                let grown = spread(open, start);
                Some((bi, std::array::from_fn(|z| grown[z] & !done[z])))
            })
            .collect();
        for (bi, new) in &fresh {
            let s = bricks.slot_of(*bi as usize);
            if s == NO_SLOT {
                set_bit(&mut fill.tiles, *bi as usize);
            } else {
                for (w, n) in fill.nodes[s as usize].iter_mut().zip(new) {
                    *w |= n;
                }
            }
            fill.count += count(new);
        }
        seeds = fresh
            .par_iter()
            .flat_map_iter(|(bi, new)| {
                let mut out = Vec::new();
                face_seeds(bricks, *bi as usize, new, &mut out);
                out
            })
            .collect();
    }
    fill
}

/// Runs Algorithm 1 on the sparse distance `dist` with offset `eps` (world
/// units). Far-field pockets behind narrow necks are activated in `dist` (at
/// the cap) for the paper's rule.
pub fn sparse_tag(
    dist: &mut SparseDistance,
    eps: f64,
    rule: TagRule,
    progress: &dyn Progress,
) -> SparseTags {
    let eps = eps as f32;
    let far = dist.cap;
    progress.start(dist.bricks.grid.len() as u64, "tagging");
    let mut reach = flood(&dist.bricks, &dist.values, far, eps);
    if rule == TagRule::Threshold {
        progress.finish();
        return SparseTags {
            exterior: masks_to_bits(&reach.nodes, dist.bricks.nodes() / 64),
            tiles: reach.tiles,
            exterior_count: reach.count,
            refused: 0,
        };
    }
    // The paper's rule: the far field is all accepted.
    let mut far_fill = if far.is_finite() && far >= eps {
        flood(&dist.bricks, &dist.values, far, far)
    } else {
        Fill {
            nodes: vec![EMPTY_MASK; dist.bricks.slots()],
            tiles: vec![0; reach.tiles.len()],
            count: 0,
        }
    };
    // Pockets: inactive bricks reached by the ε fill only.
    let pockets: Vec<u32> = (0..dist.bricks.brick_count())
        .filter(|&bi| bit(&reach.tiles, bi) && !bit(&far_fill.tiles, bi))
        .map(|bi| bi as u32)
        .collect();
    if !pockets.is_empty() {
        let first = dist.bricks.slots();
        dist.activate(&pockets);
        for s in first..dist.bricks.slots() {
            reach
                .nodes
                .push(dist.bricks.in_grid(dist.bricks.slot_coords(s)));
            far_fill.nodes.push(EMPTY_MASK);
        }
    }
    let bricks = &dist.bricks;
    let d = &dist.values;
    progress.advance(far_fill.count as u64);
    // The rest of the ε fill: the shell, decided by relaxation.
    let shell: Vec<Mask> = (0..bricks.slots())
        .map(|s| std::array::from_fn(|z| reach.nodes[s][z] & !far_fill.nodes[s][z]))
        .collect();
    drop(reach);
    let mut ext = far_fill.nodes;
    let shells = Shell {
        bricks,
        d,
        far,
        far_tiles: &far_fill.tiles,
        shell: &shell,
    };
    let (accepted, refused) = shells.decide(&mut ext);
    progress.finish();
    SparseTags {
        exterior: masks_to_bits(&ext, bricks.nodes() / 64),
        tiles: far_fill.tiles,
        exterior_count: far_fill.count + accepted,
        refused,
    }
}

/// The ε shell (the ε fill less the far field) and what deciding it reads.
///
/// Under the paper's rule a node's fate depends only on its farther
/// neighbours (and on equal ones, through the group flood): it is exterior
/// iff every strictly farther neighbour is exterior and it is reached — it
/// has a farther neighbour (then exterior), lies on a face, or has an
/// exterior neighbour at the same distance. That rule is monotone in the
/// neighbours' tags, and the sequential descent's result is its least fixed
/// point (by induction in decreasing distance, each node's value is forced by
/// the ones before it). So the shell can be decided in any order by raising
/// tags from the far field until nothing changes: bricks in parallel rounds,
/// each brick relaxed to its own fixed point (on 512-bit masks, all its
/// nodes at once) against the previous round's tags of its neighbours. The
/// fixed point is unique, so the result does not depend on the order or the
/// thread count, and equals the descent's (tested).
struct Shell<'a> {
    bricks: &'a Bricks,
    d: &'a [f32],
    far: f32,
    far_tiles: &'a [u64],
    shell: &'a [Mask],
}

/// A brick's comparisons with its neighbours, per direction (−x, +x, −y,
/// +y, −z, +z): the nodes whose neighbour that way is strictly farther from
/// the data, and those whose neighbour is at least as far; and the nodes on
/// the grid's faces.
struct Slopes {
    farther: [Mask; 6],
    not_nearer: [Mask; 6],
    face: Mask,
}

/// `w`'s nodes moved one node along direction `dir` within a brick plane
/// word (x: one bit, y: eight); z moves between words and is done apart.
#[inline(always)]
fn shift_in_plane(w: u64, dir: usize) -> u64 {
    match dir {
        // Node u gets what its −x neighbour u − 1 has.
        0 => (w << 1) & !X_LOW,
        1 => (w >> 1) & !X_HIGH,
        2 => w << SIDE,
        _ => w >> SIDE,
    }
}

impl Shell<'_> {
    /// Raises the tags `ext` (the far field's, per slot) over the shell to
    /// the rule's fixed point, brick by brick in parallel rounds; returns
    /// the shell's accepted and refused nodes.
    fn decide(&self, ext: &mut [Mask]) -> (usize, usize) {
        let mut pending: Vec<u32> = (0..self.bricks.slots() as u32)
            .filter(|&s| !is_empty(&self.shell[s as usize]))
            .collect();
        // Each shell brick's comparisons with its neighbours, once (`at[s]` is
        // its place in `slopes`).
        let slopes: Vec<Slopes> = pending
            .par_iter()
            .map(|&s| self.slopes(s as usize))
            .collect();
        let mut at = vec![u32::MAX; self.bricks.slots()];
        for (i, &s) in pending.iter().enumerate() {
            at[s as usize] = i as u32;
        }
        while !pending.is_empty() {
            let fresh: Vec<(u32, Mask)> = pending
                .par_iter()
                .filter_map(|&s| {
                    let grown = self.relax_brick(s as usize, &slopes[at[s as usize] as usize], ext);
                    (grown != ext[s as usize]).then_some((s, grown))
                })
                .collect();
            let mut next = Vec::new();
            for (s, grown) in fresh {
                let new: Mask = std::array::from_fn(|z| grown[z] & !ext[s as usize][z]);
                ext[s as usize] = grown;
                self.touched(s as usize, &new, &mut next);
            }
            next.sort_unstable();
            next.dedup();
            pending = next;
        }
        (0..self.bricks.slots())
            .into_par_iter()
            .filter(|&s| at[s] != u32::MAX)
            .map(|s| self.counts(s, &slopes[at[s] as usize], ext))
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
    }

    /// For every node of slot `s`, the value `of` gives its neighbour in
    /// direction `dir` (inside the brick: `own`; else the neighbour brick's
    /// node, a whole inactive brick, or nothing beyond the grid), as masks:
    /// the nodes whose neighbour passes `test`.
    fn slopes(&self, s: usize) -> Slopes {
        let bricks = self.bricks;
        let b = bricks.slot_coords(s);
        let faces = bricks.face_slots(s);
        let brick = |s: usize| -> &BrickValues {
            self.d[s * BRICK_NODES..(s + 1) * BRICK_NODES]
                .try_into()
                .expect("a brick")
        };
        let d = brick(s);
        let mut out = Slopes {
            farther: [EMPTY_MASK; 6],
            not_nearer: [EMPTY_MASK; 6],
            face: grid_faces(bricks, b),
        };
        let far = [self.far; SIDE];
        for (dir, &other) in faces.iter().enumerate() {
            let (a, up) = (dir / 2, dir % 2 == 1);
            // The neighbour brick's values (an inactive one reads as the cap).
            let theirs = (other != NO_SLOT).then(|| brick(other as usize));
            // Row by row: the neighbours' row along x is the row shifted by
            // one with the end from the next brick, along y or z another row.
            for r in 0..SIDE * SIDE {
                let (y, z) = (r % SIDE, r / SIDE);
                let own = brick_row(d, r);
                let shifted: [f32; SIDE];
                let next = match (a, up) {
                    (0, _) => {
                        let end = if up { 0 } else { SIDE - 1 };
                        let edge = theirs.map_or(self.far, |t| brick_row(t, r)[end]);
                        shifted = std::array::from_fn(|x| match (up, x) {
                            (true, x) if x + 1 < SIDE => own[x + 1],
                            (false, x) if x > 0 => own[x - 1],
                            _ => edge,
                        });
                        &shifted
                    }
                    (1, true) if y + 1 < SIDE => brick_row(d, r + 1),
                    (1, false) if y > 0 => brick_row(d, r - 1),
                    (2, true) if z + 1 < SIDE => brick_row(d, r + SIDE),
                    (2, false) if z > 0 => brick_row(d, r - SIDE),
                    // The row across the face, in the next brick.
                    (1, _) => theirs.map_or(&far, |t| brick_row(t, r + SIDE - 1 - 2 * y)),
                    _ => theirs.map_or(&far, |t| brick_row(t, y + SIDE * (SIDE - 1 - z))),
                };
                let (next, own) = (f32x8::new(*next), f32x8::new(*own));
                let at = SIDE * y;
                out.farther[dir][z] |= u64::from(next.simd_gt(own).to_bitmask()) << at;
                out.not_nearer[dir][z] |= u64::from(next.simd_ge(own).to_bitmask()) << at;
            }
            // Only nodes in the grid whose neighbour that way is in the grid
            // too are decided.
            let decided = if up {
                bricks.within_upper(b, a)
            } else {
                bricks.within_lower(b, a)
            };
            for (w, &i) in decided.iter().enumerate() {
                out.farther[dir][w] &= i;
                out.not_nearer[dir][w] &= i;
            }
        }
        out
    }

    /// Per direction, the nodes of slot `s` on that face of the brick whose
    /// neighbour in the next brick is exterior (by `ext`, or the tile of an
    /// inactive brick).
    fn outside(&self, s: usize, ext: &[Mask]) -> [Mask; 6] {
        self.bricks
            .across_faces(s, |t| ext[t], |bi| bit(self.far_tiles, bi))
    }

    /// One evaluation of the rule on every node of a brick whose tags are
    /// `own`: (the nodes it accepts, the nodes reached but with a farther
    /// neighbour not exterior).
    #[inline(always)]
    fn rule(slopes: &Slopes, own: &Mask, outside: &[Mask; 6]) -> (Mask, Mask) {
        let mut accept = EMPTY_MASK;
        let mut refuse = EMPTY_MASK;
        for z in 0..SIDE {
            let mut all_farther = u64::MAX;
            let mut any_farther = 0u64;
            let mut reached = slopes.face[z];
            for (dir, out) in outside.iter().enumerate() {
                let nb = match dir {
                    0..=3 => shift_in_plane(own[z], dir),
                    4 => {
                        if z > 0 {
                            own[z - 1]
                        } else {
                            0
                        }
                    }
                    _ => {
                        if z + 1 < SIDE {
                            own[z + 1]
                        } else {
                            0
                        }
                    }
                } | out[z];
                let f = slopes.farther[dir][z];
                all_farther &= !f | nb;
                any_farther |= f;
                reached |= slopes.not_nearer[dir][z] & nb;
            }
            accept[z] = all_farther & (any_farther | reached);
            refuse[z] = !all_farther & reached;
        }
        (accept, refuse)
    }

    /// Slot `s`'s tags raised to the fixed point of its own shell nodes, its
    /// neighbours' tags as `ext` says.
    fn relax_brick(&self, s: usize, slopes: &Slopes, ext: &[Mask]) -> Mask {
        let shell = &self.shell[s];
        let mut own = ext[s];
        let outside = self.outside(s, ext);
        loop {
            let (accept, _) = Self::rule(slopes, &own, &outside);
            let next: Mask = std::array::from_fn(|z| own[z] | (accept[z] & shell[z]));
            if next == own {
                return own;
            }
            own = next;
        }
    }

    /// The slots whose shell may change now that the nodes `new` of slot `s`
    /// are exterior: the face neighbours that `new` touches.
    fn touched(&self, s: usize, new: &Mask, out: &mut Vec<u32>) {
        let faces = self.bricks.face_slots(s);
        let on_face = [
            new.iter().any(|w| w & X_LOW != 0),
            new.iter().any(|w| w & X_HIGH != 0),
            new.iter().any(|w| w & Y_LOW != 0),
            new.iter().any(|w| w & Y_HIGH != 0),
            new[0] != 0,
            new[SIDE - 1] != 0,
        ];
        for (f, &hit) in on_face.iter().enumerate() {
            let t = faces[f];
            if hit && t != NO_SLOT && !is_empty(&self.shell[t as usize]) {
                out.push(t);
            }
        }
    }

    /// The shell nodes of slot `s` accepted, and refused (reached, but a
    /// farther neighbour is not exterior), at the fixed point `ext`.
    fn counts(&self, s: usize, slopes: &Slopes, ext: &[Mask]) -> (usize, usize) {
        let (shell, own) = (&self.shell[s], &ext[s]);
        let (_, refuse) = Self::rule(slopes, own, &self.outside(s, ext));
        let accepted: Mask = std::array::from_fn(|z| shell[z] & own[z]);
        let refused: Mask = std::array::from_fn(|z| shell[z] & !own[z] & refuse[z]);
        (count(&accepted), count(&refused))
    }
}

/// Per-brick masks as one bit per node id.
fn masks_to_bits(masks: &[Mask], words: usize) -> Vec<u64> {
    let mut bits: Vec<u64> = masks.iter().flatten().copied().collect();
    bits.resize(words, 0);
    bits
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::{DistanceField, DistanceMethod, unsigned_distance};
    use crate::grid::{GridSpec, Sizing};
    use crate::sparse::distance::{bricks_for, closest_points};
    use crate::sparse::layout::local;
    use crate::tagging::tag;
    use asperity_core::{MemoryBudget, NoProgress};

    /// A cup (a sphere of radius 3 with its top cut off), a closed hollow ball
    /// with a cavity wider than the cap, and a loose point.
    fn shape() -> Vec<[f64; 3]> {
        let mut pts = Vec::new();
        let n = 60;
        for a in 0..n {
            for b in 0..n {
                let th = std::f64::consts::PI * (a as f64 + 0.5) / n as f64;
                let ph = 2.0 * std::f64::consts::PI * b as f64 / n as f64;
                let dir = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
                if dir[2] < 0.73 {
                    pts.push(dir.map(|x| 3.0 * x));
                }
                pts.push([9.0 + 2.5 * dir[0], 2.5 * dir[1], 2.5 * dir[2]]);
            }
        }
        pts.push([4.5, 4.0, -2.0]);
        pts
    }

    fn fields(pts: &[[f64; 3]], res: usize, cap: f64) -> (DistanceField, SparseDistance) {
        let grid = GridSpec::around(
            pts,
            Sizing::Resolution(res),
            |h| (1.0 / h) as usize + 3,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let dense = unsigned_distance(pts, &grid, DistanceMethod::ClosestPoint, cap, &NoProgress);
        let bricks = bricks_for(&grid, pts, cap);
        let (cells, rounds) = closest_points(pts, &bricks, cap, &NoProgress);
        (
            dense,
            SparseDistance::from_cells(bricks, cells, cap, rounds),
        )
    }

    /// Both rules give the dense exterior node for node, with the same counts,
    /// for caps below and above the cavity's and the cup's radii, and with
    /// distances rounded to 1/8 cell (many ties).
    #[test]
    fn sparse_tagging_equals_the_dense_tagging() {
        let pts = shape();
        let (mut refusals, mut sparse_cases) = (0, 0);
        for (res, cap_cells, round) in [
            (48, 4.0, false),
            (48, 8.0, true),
            (70, 6.0, false),
            (40, 14.0, false),
        ] {
            let probe = GridSpec::around(
                &pts,
                Sizing::Resolution(res),
                |h| (1.0 / h) as usize + 3,
                &MemoryBudget::unlimited(),
            )
            .unwrap();
            let cap = cap_cells * probe.spacing;
            let (mut dense, sparse) = fields(&pts, res, cap);
            let eighth = (probe.spacing / 8.0) as f32;
            let mut sparse = sparse;
            if round {
                for x in dense.values.iter_mut().chain(sparse.values.iter_mut()) {
                    *x = (*x / eighth).round() * eighth;
                }
            }
            sparse_cases += usize::from(sparse.bricks.slots() < sparse.bricks.brick_count());
            for rule in [TagRule::Paper, TagRule::Threshold] {
                for eps_cells in [1.5, 3.0] {
                    let eps = eps_cells * probe.spacing;
                    let want = tag(&dense, eps, rule, &NoProgress);
                    let mut field = sparse.clone();
                    let got = sparse_tag(&mut field, eps, rule, &NoProgress);
                    let g = &dense.grid;
                    for u in 0..g.len() {
                        let c = g.coords(u);
                        assert_eq!(
                            got.at(&field.bricks, c),
                            want.exterior[u],
                            "res {res}, cap {cap_cells}, {rule:?}, ε {eps_cells}: node {c:?}"
                        );
                    }
                    assert_eq!(got.exterior_count, want.exterior_count);
                    assert_eq!(got.refused, want.refused);
                    refusals += got.refused;
                }
            }
        }
        assert!(refusals > 0, "the comparison covers refusals");
        assert!(sparse_cases >= 2, "the comparison covers inactive bricks");
    }

    /// A hollow ball with a small hole: the far field inside is reached by
    /// the ε fill through the hole but not by the far fill (the hole is
    /// narrower than the cap), so its inactive bricks become active pockets.
    #[test]
    fn pockets_behind_narrow_necks_equal_the_dense_tagging() {
        let mut pts = Vec::new();
        let n = 160;
        for a in 0..n {
            for b in 0..2 * n {
                let th = std::f64::consts::PI * (a as f64 + 0.5) / n as f64;
                let ph = std::f64::consts::PI * b as f64 / n as f64;
                if th > 0.15 {
                    pts.push([
                        8.0 * th.sin() * ph.cos(),
                        8.0 * th.sin() * ph.sin(),
                        8.0 * th.cos(),
                    ]);
                }
            }
        }
        let (dense, sparse) = fields(&pts, 64, 2.2);
        let eps = 0.5;
        for rule in [TagRule::Paper, TagRule::Threshold] {
            let want = tag(&dense, eps, rule, &NoProgress);
            let mut field = sparse.clone();
            let got = sparse_tag(&mut field, eps, rule, &NoProgress);
            if rule == TagRule::Paper {
                assert!(
                    field.bricks.slots() > sparse.bricks.slots(),
                    "pockets were activated"
                );
            }
            let g = &dense.grid;
            for u in 0..g.len() {
                let c = g.coords(u);
                assert_eq!(
                    got.at(&field.bricks, c),
                    want.exterior[u],
                    "{rule:?}: node {c:?}"
                );
            }
            assert_eq!(
                (got.exterior_count, got.refused),
                (want.exterior_count, want.refused)
            );
        }
    }

    #[test]
    fn spreading_inside_a_brick_is_the_connected_set() {
        // Open: two slabs joined by one column; the seed in one slab fills both,
        // not the separate node.
        let mut open = EMPTY_MASK;
        for z in [1, 5] {
            open[z] = u64::MAX;
        }
        for plane in &mut open[2..5] {
            *plane |= 1 << local(3, 4, 0);
        }
        open[7] = 1;
        let mut seed = EMPTY_MASK;
        seed[1] = 1 << local(7, 7, 0);
        let f = spread(&open, seed);
        let mut want = open;
        want[7] = 0;
        assert_eq!(f, want);
    }
}
