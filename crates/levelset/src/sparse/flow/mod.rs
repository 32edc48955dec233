//! The narrow-band convection flow (§5.1–5.2, Eqs. 6, 10–12) on bricks.
//!
//! The same step as the dense `evolve` (feature `reference`) — TVD-RK2 advance of φ_t = d|∇φ| on the
//! tube T, redistancing by Eq. 11 on N, clamping by Eq. 12, the new T from N
//! — computed by the same lane kernels, so every node gets the same bits as on
//! the dense grid (tested). What differs is the storage:
//!
//! * The tubes are node masks per brick (512 bits, a word per plane), so a
//!   brick's row of eight nodes is one vector of lanes and the row's bits say
//!   which lanes are in the tube; N is T grown by one node through the masks
//!   of the brick and its neighbours.
//! * A stencil reads its rows along y and z from the brick or its face
//!   neighbours, and its shifted rows along x from the row and the ends of the
//!   neighbours' rows, through a per-brick frame of fixed-size brick arrays.
//!   A neighbour without storage reads as its background (±γ for φ by its
//!   tag, the cap for d): *virtual* slots past the real ones hold those
//!   values during a step, so a read never branches on storage.
//! * When N reaches a brick without storage (the front moves outward, or the
//!   tube grows into a brick the distance did not need) the brick is added to
//!   the layout first, at its background.
//! * Each pass runs over the bricks in parallel, from one buffer into the
//!   other (Jacobi), one pass after the other: the order of the dense module's
//!   reference schedule, which its fused sweep reproduces bit for bit. The
//!   dense plan's last pass, the rebuild of T (φ at the node itself only),
//!   runs inside the pass before it, and its copy of φ into the scratch
//!   buffer (so that the two agree outside T when the next step reads the
//!   scratch) inside the next step's advance, on the previous N: four passes
//!   a step instead of five, with the same values wherever they are read.
//!   (A brick layer is eight planes: the dense code's fusion of all passes
//!   into one sweep over slabs of planes would not stay in cache here.)

use asperity_core::Progress;
use rayon::prelude::*;

use super::distance::SparseDistance;
use super::layout::{
    BRICK_NODES, BrickValues, Bricks, EMPTY_MASK, Mask, NO_SLOT, SIDE, X_HIGH, X_LOW, Y_HIGH,
    Y_LOW, brick_row, count, is_empty,
};
use super::surface::SparseLevelSet;
use crate::evolve::{
    Band, Buf, EvolveParams, EvolveStats, LANES, MIN_NODES, Movement, Neighbourhood, Op, Stencil,
    Step, StepStats, hi, rate, redistanced, step_ops, stopped, time_step,
};
use crate::lanes::{Kernel, Lanes, dispatch};

mod tubes;

use tubes::*;

/// A brick's neighbours for the stencils: per face (−x, +x, −y, +y, −z, +z)
/// the slot a stencil reads there — the neighbour's, or past the real slots
/// a *virtual* slot of background values when the neighbour has no storage:
/// in φ's buffers slot `S` holds +γ and `S + 1` holds −γ, in d's slot `S`
/// holds the cap (`S` the number of real slots).
#[derive(Clone, Copy, Debug)]
struct Around {
    phi: [u32; 6],
    d: [u32; 6],
}

fn compute_arounds(ls: &SparseLevelSet) -> Vec<Around> {
    let b = &ls.bricks;
    let virtual_slot = b.slots() as u32;
    (0..b.slots())
        .into_par_iter()
        .map(|s| {
            let slots = b.face_slots(s);
            let c = b.slot_coords(s);
            let phi = std::array::from_fn(|f| {
                if slots[f] != NO_SLOT {
                    return slots[f];
                }
                let (axis, up) = (f / 2, f % 2 == 1);
                let mut n = c;
                if up {
                    n[axis] += 1;
                } else if n[axis] > 0 {
                    n[axis] -= 1;
                }
                let exterior = n[axis] >= b.bdims[axis] || ls.background(b.brick_index(n)) > 0.0;
                virtual_slot + u32::from(!exterior)
            });
            let d = slots.map(|x| if x == NO_SLOT { virtual_slot } else { x });
            Around { phi, d }
        })
        .collect()
}

/// Pads φ's buffers with their two virtual slots (+γ, −γ), or d's with its
/// one (the cap).
fn pad(field: &mut Vec<f32>, values: &[f32]) {
    for &v in values {
        field.extend(std::iter::repeat_n(v, BRICK_NODES));
    }
}

/// A buffer as bricks (its length is a whole number of bricks).
#[inline(always)]
fn as_bricks(field: &[f32]) -> &[BrickValues] {
    field.as_chunks::<BRICK_NODES>().0
}

/// Row `r` (y + 8z) of a brick: eight values, with no bounds to check.
#[inline(always)]
fn row_of<V: Lanes>(b: &BrickValues, r: usize) -> V {
    V::new(*brick_row(b, r))
}

/// Where one brick's stencils read one buffer: the brick's own values and,
/// for y′ and z′ from −2 to 9, the brick holding row y′ (z′) — its own or a
/// neighbour's (possibly virtual); and its x neighbours.
struct Frame<'a> {
    field: &'a [f32],
    s: usize,
    own: &'a BrickValues,
    ys: [&'a BrickValues; 12],
    zs: [&'a BrickValues; 12],
    left: &'a BrickValues,
    right: &'a BrickValues,
    /// For the curvature term: reads any node.
    reader: &'a Reader<'a>,
}

impl<'a> Frame<'a> {
    #[inline(always)]
    fn new(field: &'a [f32], s: usize, faces: &[u32; 6], reader: &'a Reader<'a>) -> Self {
        let bricks = as_bricks(field);
        let own = &bricks[s];
        let spread = |lo: u32, hi: u32| {
            let (lo, hi) = (&bricks[lo as usize], &bricks[hi as usize]);
            std::array::from_fn(|i| match i {
                0 | 1 => lo,
                10 | 11 => hi,
                _ => own,
            })
        };
        Frame {
            field,
            s,
            own,
            ys: spread(faces[2], faces[3]),
            zs: spread(faces[4], faces[5]),
            left: &bricks[faces[0] as usize],
            right: &bricks[faces[1] as usize],
            reader,
        }
    }

    /// Row `r` of the brick.
    #[inline(always)]
    fn row(&'a self, r: usize) -> Row<'a> {
        Row {
            frame: self,
            y: r % SIDE,
            z: r / SIDE,
        }
    }
}

/// One row of eight nodes of a brick, as a [`Stencil`] on one buffer.
struct Row<'a> {
    frame: &'a Frame<'a>,
    y: usize,
    z: usize,
}

impl Row<'_> {
    /// The row shifted by `k` nodes along x (|k| ≤ 2), the ends from the x
    /// neighbours.
    #[inline(always)]
    fn shifted_x<V: Lanes>(&self, k: isize) -> V {
        let f = self.frame;
        let at = SIDE * ((self.y + SIDE * self.z) % (SIDE * SIDE));
        let n = k.unsigned_abs();
        let mut v = [0f32; LANES];
        if k > 0 {
            v[..SIDE - n].copy_from_slice(&f.own[at + n..at + SIDE]);
            v[SIDE - n..].copy_from_slice(&f.right[at..at + n]);
        } else {
            v[n..].copy_from_slice(&f.own[at..at + SIDE - n]);
            v[..n].copy_from_slice(&f.left[at + SIDE - n..at + SIDE]);
        }
        V::new(v)
    }
}

impl<V: Lanes> Stencil<V> for Row<'_> {
    #[inline(always)]
    fn centre(&self) -> V {
        row_of(self.frame.own, self.y + SIDE * self.z)
    }

    #[inline(always)]
    fn along(&self, axis: usize, k: isize) -> V {
        let f = self.frame;
        match axis {
            0 => self.shifted_x(k),
            1 => {
                let y = self.y.wrapping_add_signed(k);
                row_of(f.ys[y.wrapping_add(2) % 12], (y % SIDE) + SIDE * self.z)
            }
            _ => {
                let z = self.z.wrapping_add_signed(k);
                row_of(f.zs[z.wrapping_add(2) % 12], self.y + SIDE * (z % SIDE))
            }
        }
    }

    fn curvature(&self, l: usize, h: f64) -> (f64, f64) {
        let f = self.frame;
        let b = f.reader.bricks.slot_coords(f.s);
        let c = [b[0] * SIDE + l, b[1] * SIDE + self.y, b[2] * SIDE + self.z];
        crate::curvature::curvature_from(
            |o| {
                let at = std::array::from_fn(|a| c[a].wrapping_add_signed(o[a]));
                f64::from(f.reader.at(f.field, at))
            },
            h,
        )
    }
}

/// Reads any node of a φ buffer (the curvature term's diagonal stencil).
struct Reader<'a> {
    bricks: &'a Bricks,
    ls: &'a SparseLevelSet,
}

impl Reader<'_> {
    fn at(&self, field: &[f32], c: [usize; 3]) -> f32 {
        match self.bricks.id(c) {
            Some(id) => field[id as usize],
            None => self
                .ls
                .background(self.bricks.brick_index(c.map(|x| x / SIDE))),
        }
    }
}

/// Lane masks by their bits: every bit of lane l set where bit l is.
static LANE_MASKS: [[f32; LANES]; 256] = {
    let mut t = [[0f32; LANES]; 256];
    let mut bits = 0;
    while bits < 256 {
        let mut l = 0;
        while l < LANES {
            if bits >> l & 1 == 1 {
                t[bits][l] = f32::from_bits(u32::MAX);
            }
            l += 1;
        }
        bits += 1;
    }
    t
};

/// The lanes of `bits` as a mask.
#[inline(always)]
fn lane_mask<V: Lanes>(bits: u32) -> V {
    V::new(LANE_MASKS[bits as usize & 0xFF])
}

/// Writes the lanes of `mask` of `v` into row `r` of `dst`; returns the row
/// as written.
#[inline(always)]
fn store_masked<V: Lanes>(dst: &mut BrickValues, r: usize, mask: V, v: V) -> V {
    let at = (r % (SIDE * SIDE)) * SIDE;
    let out: &mut [f32; LANES] = (&mut dst[at..at + LANES]).try_into().expect("eight");
    let row = mask.select(v, V::new(*out));
    *out = row.to_array();
    row
}

/// The rows of a mask with nodes: (row y + 8z, its eight bits).
#[inline(always)]
fn rows(m: &Mask) -> impl Iterator<Item = (usize, u32)> + '_ {
    (0..SIDE).flat_map(move |z| {
        let w = m[z];
        (0..SIDE).filter_map(move |y| {
            let bits = (w >> (SIDE * y)) as u32 & 0xFF;
            (bits != 0).then_some((y + SIDE * z, bits))
        })
    })
}

/// What a pass needs besides its buffers.
struct Ctx<'a> {
    c: Step<'a>,
    arounds: &'a [Around],
    t: &'a [Mask],
    n: &'a [Mask],
    /// The previous step's N (where the scratch buffer differs from φ).
    prev_n: &'a [Mask],
    /// Nodes that fit the ENO stencil (two nodes from every face), per slot.
    fits: &'a [Mask],
    reader: Reader<'a>,
}

impl<'a> Ctx<'a> {
    /// Slot `s`'s frame on a φ buffer.
    #[inline(always)]
    fn phi_frame(&'a self, field: &'a [f32], s: usize) -> Frame<'a> {
        Frame::new(field, s, &self.arounds[s].phi, &self.reader)
    }

    /// Slot `s`'s frame on the distance.
    #[inline(always)]
    fn d_frame(&'a self, s: usize) -> Frame<'a> {
        Frame::new(self.c.d, s, &self.arounds[s].d, &self.reader)
    }
}

/// What one brick's pass gives back.
enum Out {
    Nothing,
    Moved(Movement),
    Rebuilt(Mask, f32),
}

/// One pass on one brick, as a [`Kernel`]: `dst` is the brick's slice of the
/// buffer written, `src` the whole buffer read. With `rebuild` (the pass that
/// writes the step's final φ on N) it also gives the brick's new T.
struct Brick<'a> {
    ctx: &'a Ctx<'a>,
    op: Op,
    rebuild: bool,
    s: usize,
    src: &'a [f32],
    dst: &'a mut BrickValues,
}

/// The bits of row `r` in mask `m`.
#[inline(always)]
fn row_bits(m: &Mask, r: usize) -> u32 {
    (m[r / SIDE] >> (SIDE * (r % SIDE))) as u32 & 0xFF
}

/// The union of two masks.
#[inline(always)]
fn union(a: &Mask, b: &Mask) -> Mask {
    std::array::from_fn(|z| a[z] | b[z])
}

impl Kernel for Brick<'_> {
    type Output = Out;

    #[inline(always)]
    fn run<V: Lanes>(self) -> Out {
        let Brick {
            ctx,
            op,
            rebuild,
            s,
            src,
            dst,
        } = self;
        let c = &ctx.c;
        let mut new_t = Rebuilt::<V>::new();
        // Every pass but the clamp reads the other buffer.
        let frame = (op != Op::Clamp).then(|| ctx.phi_frame(src, s));
        let frame = frame.as_ref();
        let d_frame = ctx.d_frame(s);
        match op {
            Op::Advance => {
                // The scratch equals φ outside T when the step reads it, as in
                // the dense flow: the last step's N, where the scratch still
                // holds a redistancing iterate, gets φ back here.
                let (t, prev) = (&ctx.t[s], &ctx.prev_n[s]);
                for (r, _) in rows(&union(t, prev)) {
                    let (tb, copy) = (row_bits(t, r), row_bits(prev, r) & !row_bits(t, r));
                    if copy != 0 {
                        let v = row_of::<V>(frame.expect("a source").own, r);
                        store_masked(dst, r, lane_mask::<V>(copy), v);
                    }
                    if tb == 0 {
                        continue;
                    }
                    let st = frame.expect("a source").row(r);
                    let d = d_frame.row(r);
                    let v = if c.zhao {
                        rate::<V, true>(c, &st, &d, tb)
                    } else {
                        rate::<V, false>(c, &st, &d, tb)
                    };
                    let v = Stencil::<V>::centre(&st) + V::splat(c.dt) * v;
                    store_masked(dst, r, lane_mask::<V>(tb), v);
                }
                return Out::Nothing;
            }
            Op::Finish => {
                let mut moved = (0u64, 0u64);
                for (r, bits) in rows(&ctx.t[s]) {
                    let st = frame.expect("a source").row(r);
                    let d = d_frame.row(r);
                    let l = if c.zhao {
                        rate::<V, true>(c, &st, &d, bits)
                    } else {
                        rate::<V, false>(c, &st, &d, bits)
                    };
                    let v = Stencil::<V>::centre(&st) + V::splat(c.dt) * l;
                    let old = row_of::<V>(dst, r);
                    let new = V::splat(0.5) * (old + v);
                    let valid = lane_mask::<V>(bits);
                    let near = old.abs().simd_lt(V::splat(c.h)) & valid;
                    let m = ((new - old).abs() * V::splat(c.inv_h)).fast_min(V::splat(1e3));
                    let fixed = near.select(m * V::splat(65536.0), V::splat(0.0));
                    moved.0 += fixed.trunc_sum();
                    moved.1 += u64::from(near.to_bitmask().count_ones());
                    store_masked(dst, r, valid, new);
                }
                return Out::Moved(moved);
            }
            Op::Redistance { clamp, .. } => {
                for (r, bits) in rows(&ctx.n[s]) {
                    let st = frame.expect("a source").row(r);
                    let mut v = redistanced::<V>(c, &st);
                    if clamp {
                        v = v.fast_max(V::splat(-c.gamma)).fast_min(V::splat(c.gamma));
                    }
                    let v = store_masked(dst, r, lane_mask::<V>(bits), v);
                    if rebuild {
                        new_t.row(ctx, s, r, bits, v);
                    }
                }
            }
            Op::CopyBack => {
                for (r, bits) in rows(&ctx.n[s]) {
                    let v = row_of::<V>(frame.expect("a source").own, r);
                    let v = store_masked(dst, r, lane_mask::<V>(bits), v);
                    if rebuild {
                        new_t.row(ctx, s, r, bits, v);
                    }
                }
            }
            Op::Clamp => {
                for (r, bits) in rows(&ctx.n[s]) {
                    let v = row_of::<V>(dst, r);
                    let v = v.fast_max(V::splat(-c.gamma)).fast_min(V::splat(c.gamma));
                    let v = store_masked(dst, r, lane_mask::<V>(bits), v);
                    if rebuild {
                        new_t.row(ctx, s, r, bits, v);
                    }
                }
            }
            Op::Rebuild => unreachable!("the rebuild runs within the last pass"),
        }
        if rebuild {
            let (t, vmax) = new_t.finish();
            Out::Rebuilt(t, vmax)
        } else {
            Out::Nothing
        }
    }
}

/// A brick's new T being built row by row: the nodes of N that fit the ENO
/// stencil with |φ| < γ (all of them on the full grid), and the largest
/// speed there.
struct Rebuilt<V> {
    t: Mask,
    vmax: V,
}

impl<V: Lanes> Rebuilt<V> {
    #[inline(always)]
    fn new() -> Self {
        Self {
            t: EMPTY_MASK,
            vmax: V::splat(0.0),
        }
    }

    /// Row `r` of slot `s`, its candidates `bits`, φ there `p`.
    #[inline(always)]
    fn row(&mut self, ctx: &Ctx, s: usize, r: usize, bits: u32, p: V) {
        let c = &ctx.c;
        let fit = row_bits(&ctx.fits[s], r) & bits;
        if fit == 0 {
            return;
        }
        let mut keep = lane_mask::<V>(fit);
        if !c.keep_all {
            keep = p.abs().simd_lt(V::splat(c.gamma)) & keep;
        }
        let kept = keep.to_bitmask();
        if kept != 0 {
            let d = row_of::<V>(&as_bricks(c.d)[s], r);
            self.vmax = self
                .vmax
                .fast_max(keep.select(c.speeds(p, d), V::splat(0.0)));
            self.t[r / SIDE] |= u64::from(kept) << (SIDE * (r % SIDE));
        }
    }

    #[inline(always)]
    fn finish(self) -> (Mask, f32) {
        (self.t, self.vmax.to_array().into_iter().fold(0.0, hi))
    }
}

/// The first T: the rows of every brick rebuilt from φ as it is.
fn first_tube(ctx: &Ctx, phi: &[f32]) -> (Vec<Mask>, f32) {
    struct First<'a> {
        ctx: &'a Ctx<'a>,
        s: usize,
        phi: &'a [f32],
    }
    impl Kernel for First<'_> {
        type Output = (Mask, f32);
        #[inline(always)]
        fn run<V: Lanes>(self) -> (Mask, f32) {
            let (ctx, s) = (self.ctx, self.s);
            let mut t = Rebuilt::<V>::new();
            for (r, bits) in rows(&ctx.fits[s]) {
                let p = row_of::<V>(&as_bricks(self.phi)[s], r);
                t.row(ctx, s, r, bits, p);
            }
            t.finish()
        }
    }
    let (t, v): (Vec<Mask>, Vec<f32>) = (0..ctx.fits.len())
        .into_par_iter()
        .map(|s| dispatch(First { ctx, s, phi }))
        .unzip();
    (t, v.into_iter().fold(0.0, hi))
}

/// One pass over every brick: the movement (Finish), or with `rebuild` the
/// new T (into `new_t`) and its largest speed.
fn pass(
    ctx: &Ctx,
    (op, rebuild): (Op, bool),
    (phi, scratch): (&mut [f32], &mut [f32]),
    new_t: &mut [Mask],
) -> (Movement, f32) {
    let (src_buf, _, dst_buf) = op.access();
    let (src, dst): (&[f32], &mut [f32]) = match (src_buf, dst_buf) {
        (Buf::Phi, Buf::Scratch) => (phi, scratch),
        (Buf::Scratch, Buf::Phi) => (scratch, phi),
        // Clamp: in place.
        _ => (&[], phi),
    };
    dst.as_chunks_mut::<BRICK_NODES>()
        .0
        .par_iter_mut()
        .zip(new_t.par_iter_mut())
        .enumerate()
        .map(|(s, (dst, t))| {
            let busy = match op {
                Op::Advance => !(is_empty(&ctx.t[s]) && is_empty(&ctx.prev_n[s])),
                Op::Finish => !is_empty(&ctx.t[s]),
                _ => !is_empty(&ctx.n[s]),
            };
            if !busy {
                if rebuild {
                    *t = EMPTY_MASK;
                }
                return ((0, 0), 0.0);
            }
            let out = dispatch(Brick {
                ctx,
                op,
                rebuild,
                s,
                src,
                dst,
            });
            match out {
                Out::Moved(m) => (m, 0.0),
                Out::Rebuilt(mask, vmax) => {
                    *t = mask;
                    ((0, 0), vmax)
                }
                Out::Nothing => ((0, 0), 0.0),
            }
        })
        .reduce(
            || ((0, 0), 0.0),
            |a, b| ((a.0.0 + b.0.0, a.0.1 + b.0.1), hi(a.1, b.1)),
        )
}

/// Evolves `ls` by the flow for `params.iterations` steps with the speed
/// `dist` (which shares its bricks, and gains the bricks the tube reaches);
/// `on_step` sees the level set every `params.snapshot_every` steps. The same
/// result as the dense `evolve` (feature `reference`) on the dense grid.
pub fn sparse_evolve(
    ls: &mut SparseLevelSet,
    dist: &mut SparseDistance,
    params: &EvolveParams,
    progress: &dyn Progress,
    on_step: &mut dyn FnMut(&StepStats, &SparseLevelSet),
) -> EvolveStats {
    let grid = ls.bricks.grid;
    if grid.dims.iter().any(|&n| n < MIN_NODES) {
        return EvolveStats {
            steps: Vec::new(),
            converged: true,
        };
    }
    assert_eq!(
        ls.bricks.slots(),
        dist.bricks.slots(),
        "φ and d share their bricks"
    );
    // The dense plan's passes; its rebuild runs within the last of them, and
    // its copy of φ into the scratch within the next step's advance.
    let ops: Vec<Op> = step_ops(params.redistance_iterations)
        .into_iter()
        .filter(|&op| op != Op::Rebuild)
        .collect();
    let h = grid.spacing;
    let (mut scratch, mut tubes, mut vmax) = first_tubes(ls, dist, params);
    let mut arounds: Vec<Around> = Vec::new();
    progress.start(params.iterations as u64, "convection flow");
    let mut stats = EvolveStats {
        steps: Vec::new(),
        converged: false,
    };
    for step in 1..=params.iterations {
        if stopped(params, vmax) || tubes.t.iter().all(is_empty) {
            stats.converged = true;
            break;
        }
        let dt = time_step(params, h, vmax);
        let tube = tubes.t.iter().map(count).sum();
        tubes.new_t.resize(tubes.t.len(), EMPTY_MASK);
        if arounds.len() != ls.bricks.slots() {
            arounds = compute_arounds(ls);
        }
        let (moved, new_vmax) = step_passes(
            (ls, dist, &mut scratch),
            (&tubes.t, &tubes.n, &tubes.prev_n, &tubes.fits),
            &arounds,
            (params, &ops, dt),
            &mut tubes.new_t,
        );
        let front_movement = if moved.1 > 0 {
            moved.0 as f64 / 65536.0 / moved.1 as f64
        } else {
            0.0
        };
        let s = StepStats {
            step,
            dt,
            front_movement,
            tube,
        };
        stats.steps.push(s);
        std::mem::swap(&mut tubes.t, &mut tubes.new_t);
        vmax = new_vmax;
        tubes.regrow(ls, dist, &mut scratch);
        if params
            .snapshot_every
            .is_some_and(|k| k > 0 && step.is_multiple_of(k))
        {
            on_step(&s, ls);
        }
        progress.advance(1);
        if params.tolerance.is_some_and(|tol| front_movement < tol) {
            stats.converged = true;
            break;
        }
    }
    progress.finish();
    stats
}

/// The flow's start: the scratch buffer (a copy of φ; with a full band,
/// every brick activated first), the first T and N, and T's largest speed.
fn first_tubes(
    ls: &mut SparseLevelSet,
    dist: &mut SparseDistance,
    params: &EvolveParams,
) -> (Vec<f32>, Tubes, f32) {
    let full = params.band == Band::Full;
    // Room for the virtual slots the steps append (see `pad`) and for bricks
    // the tube may add, so that no step moves a buffer (a move holds the
    // old and the new copy at once; room never written costs no memory).
    let mut scratch = Vec::with_capacity(super::distance::headroom(ls.phi.len()));
    scratch.extend_from_slice(&ls.phi);
    if full {
        let all: Vec<u32> = (0..ls.bricks.brick_count() as u32).collect();
        activate(ls, dist, &mut scratch, &all);
    }
    let b = &ls.bricks;
    let fits: Vec<Mask> = (0..b.slots())
        .into_par_iter()
        .map(|s| b.within(b.slot_coords(s), 2))
        .collect();
    let (t, vmax) = {
        let arounds = compute_arounds(ls);
        let ctx = context(ls, dist, (&[], &[], &[], &fits), &arounds, params, 0.0);
        first_tube(&ctx, &ls.phi)
    };
    let mut tubes = Tubes {
        t,
        fits,
        shape: (!full).then_some(params.neighbourhood),
        ..Tubes::default()
    };
    // The scratch equals φ everywhere at the start: no previous N.
    tubes.regrow(ls, dist, &mut scratch);
    (scratch, tubes, vmax)
}

/// One step's passes `ops` over every brick, on φ padded with the virtual
/// slots the stencils read for bricks without storage: φ advanced, the new T
/// in `new_t`; returns the front's movement and the new T's largest speed.
fn step_passes(
    (ls, dist, scratch): (&mut SparseLevelSet, &mut SparseDistance, &mut Vec<f32>),
    masks: (&[Mask], &[Mask], &[Mask], &[Mask]),
    arounds: &[Around],
    (params, ops, dt): (&EvolveParams, &[Op], f64),
    new_t: &mut [Mask],
) -> (Movement, f32) {
    let mut phi = std::mem::take(&mut ls.phi);
    let real = phi.len();
    let gamma = ls.gamma;
    pad(&mut phi, &[gamma, -gamma]);
    pad(scratch, &[gamma, -gamma]);
    pad(&mut dist.values, &[dist.cap]);
    let ctx = context(ls, dist, masks, arounds, params, dt);
    let (mut moved, mut vmax) = ((0, 0), 0.0);
    for (i, &op) in ops.iter().enumerate() {
        let (m, v) = pass(&ctx, (op, i + 1 == ops.len()), (&mut phi, scratch), new_t);
        moved = (moved.0 + m.0, moved.1 + m.1);
        vmax = hi(vmax, v);
    }
    phi.truncate(real);
    scratch.truncate(real);
    dist.values.truncate(real);
    ls.phi = phi;
    (moved, vmax)
}

/// The constants and masks of a step with time step `dt`.
fn context<'a>(
    ls: &'a SparseLevelSet,
    dist: &'a SparseDistance,
    (t, n, prev_n, fits): (&'a [Mask], &'a [Mask], &'a [Mask], &'a [Mask]),
    arounds: &'a [Around],
    params: &EvolveParams,
    dt: f64,
) -> Ctx<'a> {
    let mut c = Step::new(&ls.bricks.grid, ls.gamma, params, &dist.values);
    c.dt = dt as f32;
    Ctx {
        c,
        arounds,
        t,
        n,
        prev_n,
        fits,
        reader: Reader {
            bricks: &ls.bricks,
            ls,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::{DistanceMethod, unsigned_distance};
    use crate::evolve::{Flow, Scheme, evolve, from_tags};
    use crate::grid::{GridSpec, Sizing};
    use crate::sparse::{sparse_distance, sparse_initial, sparse_tag};
    use crate::tagging::{TagRule, tag};
    use asperity_core::{MemoryBudget, NoProgress};

    /// A rough blob with a dent and a loose cluster of points.
    fn shape() -> Vec<[f64; 3]> {
        let mut pts = Vec::new();
        for a in 0..60 {
            for b in 0..120 {
                let th = std::f64::consts::PI * (a as f64 + 0.5) / 60.0;
                let ph = std::f64::consts::PI * b as f64 / 60.0;
                let r = 2.5 + 0.4 * (5.0 * ph).sin() * (3.0 * th).sin()
                    - if th < 0.6 { 0.8 } else { 0.0 };
                pts.push([
                    r * th.sin() * ph.cos(),
                    r * th.sin() * ph.sin(),
                    r * th.cos(),
                ]);
            }
        }
        for i in 0..40 {
            let t = i as f64 * 0.37;
            pts.push([
                5.0 + 0.6 * t.sin(),
                3.0 + 0.5 * (2.0 * t).cos(),
                -1.0 + 0.02 * i as f64,
            ]);
        }
        pts
    }

    /// The flow's φ and its per-step statistics equal the dense flow's, bit
    /// for bit, for each flow, scheme, redistancing count, neighbourhood and
    /// band.
    #[test]
    fn sparse_flow_equals_the_dense_flow() {
        let pts = shape();
        let grid = GridSpec::around(
            &pts,
            Sizing::Resolution(56),
            |_| 12,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let h = grid.spacing;
        let (eps, gamma) = (3.0 * h, 3.0 * h);
        let cap = eps + gamma + 2.0 * h;
        let dense_d =
            unsigned_distance(&pts, &grid, DistanceMethod::ClosestPoint, cap, &NoProgress);
        let dense_tags = tag(&dense_d, eps, TagRule::Paper, &NoProgress);
        let start = from_tags(&dense_d, &dense_tags, eps, gamma, &NoProgress);
        let (mut d0, _) = sparse_distance(&pts, &grid, cap, &NoProgress);
        let mut tags = sparse_tag(&mut d0, eps, TagRule::Paper, &NoProgress);
        let ls0 = sparse_initial(&mut d0, &mut tags, eps, gamma, &NoProgress);
        let base = EvolveParams {
            iterations: 12,
            arrest: 0.6 * h,
            ..EvolveParams::paper(h)
        };
        let cases = [
            EvolveParams {
                neighbourhood: Neighbourhood::Axes,
                ..base
            },
            base,
            EvolveParams {
                scheme: Scheme::Upwind,
                redistance_iterations: 1,
                neighbourhood: Neighbourhood::Axes,
                ..base
            },
            EvolveParams {
                redistance_iterations: 0,
                ..base
            },
            EvolveParams {
                redistance_iterations: 3,
                flow: Flow::Zhao,
                ..base
            },
            EvolveParams {
                flow: Flow::Regularized { weight: 0.5 * h },
                iterations: 4,
                ..base
            },
            EvolveParams {
                band: Band::Full,
                iterations: 3,
                ..base
            },
            EvolveParams {
                iterations: 40,
                arrest: 0.0,
                neighbourhood: Neighbourhood::Axes,
                ..base
            },
        ];
        let mut grown = 0;
        for (i, params) in cases.iter().enumerate() {
            let mut want = start.clone();
            let mut shots_dense = Vec::new();
            let p = EvolveParams {
                snapshot_every: Some(5),
                ..*params
            };
            let want_stats = evolve(&mut want, &dense_d, &p, &NoProgress, &mut |s, l| {
                shots_dense.push((s.step, l.phi.clone()))
            });
            let (mut ls, mut d) = (ls0.clone(), d0.clone());
            let mut shots = Vec::new();
            let got_stats = sparse_evolve(&mut ls, &mut d, &p, &NoProgress, &mut |s, l| {
                shots.push((s.step, l.to_dense()))
            });
            assert_eq!(got_stats, want_stats, "case {i}");
            let got = ls.to_dense();
            for (u, (a, b)) in got.iter().zip(&want.phi).enumerate() {
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "case {i}: node {:?}: {a} vs {b}",
                    grid.coords(u)
                );
            }
            assert_eq!(shots, shots_dense, "case {i}: snapshots");
            assert_eq!(ls.bricks.slots(), d.bricks.slots());
            let changed = want
                .phi
                .iter()
                .zip(&start.phi)
                .filter(|(a, b)| a != b)
                .count();
            assert!(
                changed > 1000,
                "case {i}: the flow moved φ at {changed} nodes"
            );
            grown += usize::from(ls.bricks.slots() > ls0.bricks.slots());
            eprintln!(
                "case {i}: {changed} nodes changed, bricks {} -> {}, steps {}",
                ls0.bricks.slots(),
                ls.bricks.slots(),
                got_stats.steps.len()
            );
        }
        assert!(
            grown >= 1,
            "the tube reached bricks the distance did not have"
        );
    }

    /// A front far from the data (where d is the cap) moving inward through
    /// bricks the distance never had: each step adds the bricks the tube
    /// reaches, and φ still equals the dense flow's.
    #[test]
    fn the_tube_adds_the_bricks_it_reaches() {
        let pts: Vec<[f64; 3]> = (0..300)
            .map(|i| {
                let t = i as f64 * 0.61;
                let r = 0.5 * ((i % 7) as f64 / 7.0);
                [r * t.cos(), r * t.sin(), 0.4 * (t * 0.3).sin()]
            })
            .collect();
        let grid = GridSpec::around(
            &pts,
            Sizing::Spacing(0.1),
            |_| 30,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        let (h, cap, gamma, radius) = (grid.spacing, 0.6, 0.3f32, 2.5);
        let sphere = |c: [usize; 3]| {
            let x = grid.position(c[0], c[1], c[2]);
            let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            ((r - radius) as f32).clamp(-gamma, gamma)
        };
        let dense_d =
            unsigned_distance(&pts, &grid, DistanceMethod::ClosestPoint, cap, &NoProgress);
        let mut want = crate::evolve::LevelSet {
            grid,
            phi: (0..grid.len()).map(|u| sphere(grid.coords(u))).collect(),
            gamma,
        };
        let (mut d, _) = sparse_distance(&pts, &grid, cap, &NoProgress);
        // The bricks with a node within γ + h of the sphere.
        let front: Vec<u32> = (0..d.bricks.brick_count())
            .filter(|&bi| {
                let b = d.bricks.brick_coords(bi);
                let m = d.bricks.in_grid(b);
                (0..BRICK_NODES).any(|l| {
                    m[l / 64] >> (l % 64) & 1 == 1 && {
                        let c = [
                            b[0] * SIDE + l % SIDE,
                            b[1] * SIDE + (l / SIDE) % SIDE,
                            b[2] * SIDE + l / 64,
                        ];
                        sphere(c).abs() < gamma
                    }
                })
            })
            .map(|bi| bi as u32)
            .collect();
        d.activate(&front);
        let bricks = d.bricks.clone();
        let mut tiles = vec![0u64; bricks.brick_count().div_ceil(64)];
        for bi in 0..bricks.brick_count() {
            let b = bricks.brick_coords(bi);
            if sphere(b.map(|x| x * SIDE)) > 0.0 {
                tiles[bi / 64] |= 1 << (bi % 64);
            }
        }
        let phi = (0..bricks.nodes())
            .map(|id| sphere(bricks.coords(id as u32)))
            .collect();
        let mut ls = SparseLevelSet {
            bricks,
            phi,
            tiles,
            gamma,
        };
        assert_eq!(ls.to_dense(), want.phi);
        let before = ls.bricks.slots();
        let params = EvolveParams {
            iterations: 14,
            arrest: 0.0,
            neighbourhood: Neighbourhood::Axes,
            ..EvolveParams::paper(h)
        };
        let want_stats = evolve(&mut want, &dense_d, &params, &NoProgress, &mut |_, _| {});
        let got_stats = sparse_evolve(&mut ls, &mut d, &params, &NoProgress, &mut |_, _| {});
        assert_eq!(got_stats, want_stats);
        assert!(ls.bricks.slots() > before, "the tube added bricks");
        let got = ls.to_dense();
        for (u, (a, b)) in got.iter().zip(&want.phi).enumerate() {
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "node {:?}: {a} vs {b}",
                grid.coords(u)
            );
        }
    }
}
