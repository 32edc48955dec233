//! One time step of the dense flow as a fused sweep over the planes: the
//! passes (advance, finish, redistancing, clamp, tube rebuild), their regions
//! of runs, slabs swept in parallel and their seams.

use super::*;

/// The passes of one time step and how far behind the first each must run.
///
/// `depth[i]` is the smallest lag, in planes, at which pass i can follow the
/// passes before it in a single sweep over the planes: pass i at plane p needs
/// the buffer it reads done (by its last writer) up to plane p + reach, and it
/// may overwrite plane p of a buffer only once every earlier reader of that
/// buffer is past p + its reach. So depthᵢ = max(reachᵢ, depth_w + reachᵢ
/// for the writers w of what i reads, depth_r + reach_r for the readers r of
/// what i writes, depth_w′ for the writers w′ of what i writes). The default
/// step (advance, finish, two redistancing iterations, rebuild) gets depths
/// 2, 4, 6, 7, 8.
#[derive(Clone, Debug)]
pub(crate) struct Plan {
    pub(crate) ops: Vec<Op>,
    pub(crate) depth: Vec<usize>,
    /// max(depthᵢ + reachᵢ): the planes a seam's passes touch on each side.
    pub(crate) halo: usize,
}

impl Plan {
    pub(crate) fn new(redistance_iterations: usize) -> Self {
        let ops = step_ops(redistance_iterations);
        let mut depth: Vec<usize> = Vec::with_capacity(ops.len());
        for (i, op) in ops.iter().enumerate() {
            let (src, reach, dst) = op.access();
            let mut d = reach;
            for (j, earlier) in ops[..i].iter().enumerate() {
                let (e_src, e_reach, e_dst) = earlier.access();
                if e_dst == src {
                    d = d.max(depth[j] + reach);
                }
                if e_dst == dst {
                    d = d.max(depth[j]);
                }
                if e_src == dst {
                    d = d.max(depth[j] + e_reach);
                }
            }
            depth.push(d);
        }
        let halo = ops
            .iter()
            .zip(&depth)
            .map(|(op, d)| d + op.access().1)
            .max()
            .unwrap_or(0);
        Self { ops, depth, halo }
    }
}

/// What a region's passes produce.
pub(crate) struct Swept {
    moved: Movement,
    /// The new T's runs of the planes rebuilt here.
    rebuilt: Vec<(usize, Vec<Run>)>,
    /// The largest speed on those planes' new T.
    vmax: f32,
}

/// The planes `first ..` of both buffers.
pub(crate) struct Region<'a> {
    first: usize,
    phi: &'a mut [f32],
    scratch: &'a mut [f32],
}

/// The tubes of a step: T (advanced) and N (redistanced, and the candidates of
/// the next T).
#[derive(Clone, Copy)]
pub(crate) struct Tubes<'a> {
    pub(crate) t: &'a RunTube,
    pub(crate) n: &'a RunTube,
}

/// [`run_region`] as a [`Kernel`].
pub(crate) struct RegionKernel<'a, 'r> {
    c: &'a Step<'a>,
    plan: &'a Plan,
    lags: &'a [usize],
    ranges: &'a [std::ops::Range<usize>],
    tubes: Tubes<'a>,
    region: Region<'r>,
}

impl Kernel for RegionKernel<'_, '_> {
    type Output = Swept;
    #[inline(always)]
    fn run<V: Lanes>(self) -> Swept {
        run_region::<V>(
            self.c,
            self.plan,
            self.lags,
            self.ranges,
            self.tubes,
            self.region,
        )
    }
}

/// Runs pass i of `plan` on the planes `ranges[i]` of `region`, pass i at plane
/// p in round p + `lags[i]` (passes in order within a round).
#[inline(always)]
pub(crate) fn run_region<V: Lanes>(
    c: &Step,
    plan: &Plan,
    lags: &[usize],
    ranges: &[std::ops::Range<usize>],
    tubes: Tubes,
    region: Region,
) -> Swept {
    let Region {
        first,
        phi,
        scratch,
    } = region;
    let base = first * c.strides[2];
    let mut out = Swept {
        moved: (0, 0),
        rebuilt: Vec::new(),
        vmax: 0.0,
    };
    let mut vmax = V::splat(0.0);
    let live = || ranges.iter().zip(lags).filter(|(r, _)| !r.is_empty());
    let (Some(start), Some(end)) = (
        live().map(|(r, l)| r.start + l).min(),
        live().map(|(r, l)| r.end + l).max(),
    ) else {
        return out;
    };
    for round in start..end {
        for ((&op, range), &lag) in plan.ops.iter().zip(ranges).zip(lags) {
            let Some(p) = round.checked_sub(lag).filter(|p| range.contains(p)) else {
                continue;
            };
            let tube = if matches!(op, Op::Advance | Op::Finish) {
                tubes.t
            } else {
                tubes.n
            };
            let runs = &tube.planes[p][..];
            match op {
                Op::Advance if c.zhao => advance::<V, true>(c, base, phi, scratch, runs),
                Op::Advance => advance::<V, false>(c, base, phi, scratch, runs),
                Op::Finish => {
                    let m = if c.zhao {
                        finish::<V, true>(c, base, scratch, phi, runs)
                    } else {
                        finish::<V, false>(c, base, scratch, phi, runs)
                    };
                    out.moved = (out.moved.0 + m.0, out.moved.1 + m.1);
                }
                Op::Redistance { into, clamp } => match into {
                    Buf::Scratch => redistance::<V>(c, base, phi, scratch, runs, clamp),
                    Buf::Phi => redistance::<V>(c, base, scratch, phi, runs, clamp),
                },
                Op::CopyBack => {
                    for r in runs {
                        let (s, e) = (r.start as usize - base, (r.start + r.len) as usize - base);
                        phi[s..e].copy_from_slice(&scratch[s..e]);
                    }
                }
                Op::Clamp => {
                    for r in runs {
                        let (s, e) = (r.start as usize - base, (r.start + r.len) as usize - base);
                        for x in &mut phi[s..e] {
                            *x = x.clamp(-c.gamma, c.gamma);
                        }
                    }
                }
                Op::Rebuild => {
                    let (t, plane_vmax) =
                        rebuild_plane::<V>(c, p, phi, base, Some(&mut *scratch), runs);
                    vmax = vmax.fast_max(plane_vmax);
                    out.rebuilt.push((p, t));
                }
            }
        }
    }
    out.vmax = vmax.to_array().into_iter().fold(0.0, hi);
    out
}

/// The chunks (first node, length) of up to eight nodes of a plane's runs, with
/// a prefetch of the rows a pass meets first a few runs on: the plane `ahead`
/// nodes on (in `src`, whose node 0 is `base`) and the speed. The runs jump a row
/// apart, which defeats the hardware prefetcher. (An iterator rather than a
/// closure-taking loop, so that the kernels' bodies stay in the function that
/// `dispatch` compiles for AVX.)
pub(crate) struct Chunks<'a> {
    runs: std::iter::Enumerate<std::slice::Iter<'a, Run>>,
    all: &'a [Run],
    src: &'a [f32],
    d: &'a [f32],
    base: usize,
    ahead: usize,
    u: usize,
    end: usize,
}

impl<'a> Chunks<'a> {
    #[inline(always)]
    fn new(c: &Step<'a>, runs: &'a [Run], src: &'a [f32], base: usize, ahead: usize) -> Self {
        Self {
            runs: runs.iter().enumerate(),
            all: runs,
            src,
            d: c.d,
            base,
            ahead,
            u: 0,
            end: 0,
        }
    }
}

impl Iterator for Chunks<'_> {
    type Item = (usize, usize);

    #[inline(always)]
    fn next(&mut self) -> Option<(usize, usize)> {
        if self.u >= self.end {
            let (r, run) = self.runs.next()?;
            if let Some(next) = self.all.get(r + PREFETCH_RUNS) {
                let u = next.start as usize;
                prefetch(self.src, u - self.base + self.ahead);
                prefetch(self.d, u);
            }
            (self.u, self.end) = (run.start as usize, (run.start + run.len) as usize);
        }
        let (u, n) = (self.u, (self.end - self.u).min(LANES));
        self.u += n;
        Some((u, n))
    }
}

/// Stage 1 of RK2 on one plane's runs: `stage` = φ + Δt L(φ).
#[inline(always)]
pub(crate) fn advance<V: Lanes, const ZHAO: bool>(
    c: &Step,
    base: usize,
    phi: &[f32],
    stage: &mut [f32],
    runs: &[Run],
) {
    let dt = V::splat(c.dt);
    for (u, n) in Chunks::new(c, runs, phi, base, 2 * c.strides[2]) {
        let st = Strided {
            src: phi,
            at: u - base,
            strides: c.strides,
        };
        let speed = Strided {
            src: c.d,
            at: u,
            strides: c.strides,
        };
        let v = load::<V>(phi, u - base) + dt * rate::<V, ZHAO>(c, &st, &speed, lane_bits(n));
        store(stage, u - base, v, n);
    }
}

/// Stage 2 of RK2 on one plane's runs, in place in `phi`; the front movement.
#[inline(always)]
pub(crate) fn finish<V: Lanes, const ZHAO: bool>(
    c: &Step,
    base: usize,
    stage: &[f32],
    phi: &mut [f32],
    runs: &[Run],
) -> Movement {
    let dt = V::splat(c.dt);
    let mut moved = (0u64, 0u64);
    for (u, n) in Chunks::new(c, runs, stage, base, 2 * c.strides[2]) {
        let at = u - base;
        let st = Strided {
            src: stage,
            at,
            strides: c.strides,
        };
        let speed = Strided {
            src: c.d,
            at: u,
            strides: c.strides,
        };
        let v = load::<V>(stage, at) + dt * rate::<V, ZHAO>(c, &st, &speed, lane_bits(n));
        let old = load::<V>(phi, at);
        let new = V::splat(0.5) * (old + v);
        // Movement within a cell of the front, in fixed point (2⁻¹⁶ cells) so
        // that the sum's order does not matter.
        let near = old.abs().simd_lt(V::splat(c.h)) & first::<V>(n);
        let m = ((new - old).abs() * V::splat(c.inv_h)).fast_min(V::splat(1e3));
        let fixed = near.select(m * V::splat(65536.0), V::splat(0.0));
        moved.0 += fixed.trunc_sum();
        moved.1 += u64::from(near.to_bitmask().count_ones());
        store(phi, at, new, n);
    }
    moved
}

/// One redistancing iteration of `src` into `dst` on one plane's runs.
#[inline(always)]
pub(crate) fn redistance<V: Lanes>(
    c: &Step,
    base: usize,
    src: &[f32],
    dst: &mut [f32],
    runs: &[Run],
    clamp: bool,
) {
    for (u, n) in Chunks::new(c, runs, src, base, c.strides[2]) {
        let st = Strided {
            src,
            at: u - base,
            strides: c.strides,
        };
        let mut v = redistanced::<V>(c, &st);
        if clamp {
            v = v.fast_max(V::splat(-c.gamma)).fast_min(V::splat(c.gamma));
        }
        store(dst, u - base, v, n);
    }
}

/// How many runs ahead the passes prefetch.
pub(crate) const PREFETCH_RUNS: usize = 4;

/// How a step's passes are ordered (tests compare the orders).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Order {
    /// Pipelined over slabs of planes, about this many slabs per thread.
    Fused { slabs_per_thread: usize },
    /// Each pass over the whole grid before the next, in one region.
    #[cfg(test)]
    PassByPass,
}

/// The slab boundaries: cut planes at least `gap` apart and from the grid's
/// ends, splitting the planes' work (`n`'s nodes plus a fixed cost per plane)
/// into about `slabs` equal parts.
pub(crate) fn slab_cuts(n: &RunTube, slabs: usize, gap: usize) -> Vec<usize> {
    let nz = n.planes.len();
    let weight = |k: usize| n.planes[k].iter().map(|r| r.len as usize).sum::<usize>() + 64;
    let total: usize = (0..nz).map(weight).sum();
    let mut cuts: Vec<usize> = Vec::new();
    let mut acc = 0;
    let mut part = 1;
    for k in 0..nz {
        if part >= slabs || k + gap > nz {
            break;
        }
        if acc >= total * part / slabs && k >= cuts.last().map_or(0, |&c| c) + gap {
            cuts.push(k);
            part += 1;
        }
        acc += weight(k);
    }
    cuts
}

/// Splits `buf` (planes of `plane_len` nodes) into the disjoint, sorted plane
/// spans `spans`.
pub(crate) fn carve<'a>(
    mut buf: &'a mut [f32],
    plane_len: usize,
    spans: &[std::ops::Range<usize>],
) -> Vec<&'a mut [f32]> {
    let mut out = Vec::with_capacity(spans.len());
    let mut at = 0;
    for s in spans {
        let rest = std::mem::take(&mut buf);
        let (_, tail) = rest.split_at_mut((s.start - at) * plane_len);
        let (piece, tail) = tail.split_at_mut((s.end - s.start) * plane_len);
        out.push(piece);
        buf = tail;
        at = s.end;
    }
    out
}

/// One time step's passes over the whole grid: returns the front movement, the
/// new T and its largest speed.
///
/// Run pass by pass, every pass streams the tubes through memory (at 256³ the
/// buffers' tube lines are several times the L3 cache). Fused, one sweep over
/// each slab of planes runs pass i at plane p − depthᵢ (see [`Plan`]), so each
/// plane is fetched once per step and finished while a dozen planes stay in
/// cache. The slabs run in parallel, each on its own planes only: pass i covers
/// [k₀ + depthᵢ, k₁ − depthᵢ) of slab [k₀, k₁) (the whole extent at the
/// grid's ends). The planes left, [k − depthᵢ, k + depthᵢ) around each cut k,
/// are swept afterwards, again in parallel (the cuts are 2·halo apart, so these
/// seams are disjoint). Every (pass, plane) runs once and after everything it
/// depends on, so the result is the same as pass by pass, bit for bit, for any
/// slab count.
pub(crate) fn step_sweep(
    c: &Step,
    plan: &Plan,
    tubes: Tubes,
    phi: &mut [f32],
    scratch: &mut [f32],
    order: Order,
) -> (Movement, RunTube, f32) {
    let nz = c.dims[2];
    let plane_len = c.strides[2];
    let mut parts: Vec<Swept> = Vec::new();
    match order {
        Order::Fused { slabs_per_thread } => {
            let sweep = |phi: &mut [f32], scratch: &mut [f32], first, ranges: Vec<_>| {
                let region = Region {
                    first,
                    phi,
                    scratch,
                };
                dispatch(RegionKernel {
                    c,
                    plan,
                    lags: &plan.depth,
                    ranges: &ranges,
                    tubes,
                    region,
                })
            };
            let slabs = slabs_per_thread * rayon::current_num_threads();
            let cuts = slab_cuts(tubes.n, slabs, 2 * plan.halo);
            let mut bounds = vec![0];
            bounds.extend(&cuts);
            bounds.push(nz);
            let spans: Vec<_> = bounds.windows(2).map(|w| w[0]..w[1]).collect();
            // Pass i covers [k₀ + depthᵢ, k₁ − depthᵢ) of slab [k₀, k₁), up to
            // the grid's ends.
            let from = |k: usize, depth: usize| if k == 0 { 0 } else { k + depth };
            let to = |k: usize, depth: usize| if k == nz { nz } else { k - depth };
            let slabs: Vec<_> = carve(phi, plane_len, &spans)
                .into_iter()
                .zip(carve(scratch, plane_len, &spans))
                .zip(&spans)
                .collect();
            parts.par_extend(slabs.into_par_iter().map(|((phi, scratch), span)| {
                let ranges = (plan.depth.iter())
                    .map(|&d| from(span.start, d)..to(span.end, d))
                    .collect();
                sweep(phi, scratch, span.start, ranges)
            }));
            // The seams: pass i on [k − depthᵢ, k + depthᵢ) around each cut k,
            // reading at most `halo` planes either side (the cuts are at least
            // 2·halo apart and from the ends).
            let seams: Vec<_> = cuts.iter().map(|&k| k - plan.halo..k + plan.halo).collect();
            let regions: Vec<_> = carve(phi, plane_len, &seams)
                .into_iter()
                .zip(carve(scratch, plane_len, &seams))
                .zip(cuts.iter().zip(&seams))
                .collect();
            parts.par_extend(regions.into_par_iter().map(|((phi, scratch), (&k, span))| {
                let ranges = plan.depth.iter().map(|&d| k - d..k + d).collect();
                sweep(phi, scratch, span.start, ranges)
            }));
        }
        #[cfg(test)]
        Order::PassByPass => {
            let lags: Vec<usize> = (0..plan.ops.len()).map(|i| i * nz).collect();
            let ranges = vec![0..nz; plan.ops.len()];
            let region = Region {
                first: 0,
                phi,
                scratch,
            };
            // With the portable lanes: the test comparing the orders also
            // compares the instruction sets.
            parts.push(crate::lanes::portable(RegionKernel {
                c,
                plan,
                lags: &lags,
                ranges: &ranges,
                tubes,
                region,
            }));
        }
    }
    let mut moved = (0, 0);
    let mut vmax = 0.0;
    let mut planes = vec![Vec::new(); nz];
    for part in parts {
        moved = (moved.0 + part.moved.0, moved.1 + part.moved.1);
        vmax = hi(vmax, part.vmax);
        for (k, runs) in part.rebuilt {
            planes[k] = runs;
        }
    }
    (moved, RunTube { planes }, vmax)
}

/// The new T on plane `k`: the nodes of `runs` with |φ| < γ (all of them when
/// `c.keep_all`) whose ENO stencil fits in the grid, and the largest speed there,
/// eight nodes at a time; `phi` and `scratch` start at node `base`, and
/// `scratch` = φ on `runs` on the way when given.
#[inline(always)]
pub(crate) fn rebuild_plane<V: Lanes>(
    c: &Step,
    k: usize,
    phi: &[f32],
    base: usize,
    mut scratch: Option<&mut [f32]>,
    runs: &[Run],
) -> (Vec<Run>, V) {
    let [nx, ny, nz] = c.dims;
    let plane = k * nx * ny;
    let mut t = Vec::new();
    let mut vmax = V::splat(0.0);
    let fits_plane = k >= 2 && k + 2 < nz;
    for r in runs {
        let (s, e) = (r.start as usize, (r.start + r.len) as usize);
        if let Some(dst) = scratch.as_deref_mut() {
            dst[s - base..e - base].copy_from_slice(&phi[s - base..e - base]);
        }
        let j = (s - plane) / nx;
        if !fits_plane || j < 2 || j + 2 >= ny {
            continue;
        }
        let row = plane + j * nx;
        let (mut u, end) = (s.max(row + 2), e.min(row + nx - 2));
        while u < end {
            let n = (end - u).min(LANES);
            let p = load::<V>(phi, u - base);
            let keep = if c.keep_all {
                first::<V>(n)
            } else {
                p.abs().simd_lt(V::splat(c.gamma)) & first::<V>(n)
            };
            let bits = keep.to_bitmask();
            if bits != 0 {
                let speed = keep.select(c.speeds(p, load::<V>(c.d, u)), V::splat(0.0));
                vmax = vmax.fast_max(speed);
                push_lanes(&mut t, u, bits, n);
            }
            u += n;
        }
    }
    (t, vmax)
}

/// The first tube T from every node that fits the ENO stencil, and its
/// largest speed.
pub(crate) fn first_tube(c: &Step, phi: &[f32]) -> (RunTube, f32) {
    /// One plane of it as a [`Kernel`].
    struct Plane<'a> {
        c: &'a Step<'a>,
        k: usize,
        phi: &'a [f32],
        runs: &'a [Run],
    }
    impl Kernel for Plane<'_> {
        type Output = (Vec<Run>, f32);
        #[inline(always)]
        fn run<V: Lanes>(self) -> (Vec<Run>, f32) {
            let (t, vmax) = rebuild_plane::<V>(self.c, self.k, self.phi, 0, None, self.runs);
            (t, vmax.to_array().into_iter().fold(0.0, hi))
        }
    }
    let everything = RunTube::interior_of(c.dims, 2);
    let (planes, vmax): (Vec<Vec<Run>>, Vec<f32>) = everything
        .planes
        .par_iter()
        .enumerate()
        .map(|(k, runs)| dispatch(Plane { c, k, phi, runs }))
        .unzip();
    (RunTube { planes }, vmax.into_iter().fold(0.0, hi))
}
