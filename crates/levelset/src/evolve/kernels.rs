//! The flow's kernels, eight nodes at a time (shared with the sparse layout):
//! loads and stores, the step's constants and time step, the stencil reads,
//! the convection rate of Eq. 6 (Godunov upwinding with ENO2 or first-order
//! differences; Zhao's flow; the curvature term) and the redistancing update
//! of Eq. 11.

use super::*;

/// Nodes evaluated together: eight `f32` lanes (`wide`'s portable vectors: one
/// AVX register, or two SSE registers on a baseline build).
pub(crate) const LANES: usize = 8;

#[cfg(feature = "reference")]
/// `s[at .. at + 8]`. In range for every node the flow loads from: a stencil
/// reaches two nodes along one axis, so the eight loaded from the last node of T
/// (two nodes from each face) end well before the grid's last row.
#[inline(always)]
pub(crate) fn load<V: Lanes>(s: &[f32], at: usize) -> V {
    let x: [f32; LANES] = s[at..at + LANES].try_into().expect("eight values");
    V::new(x)
}

#[cfg(feature = "reference")]
/// Writes the first `n` lanes of `v` at `dst[at..]`: one vector store for a
/// full chunk (a slice copy of variable length would call `memmove`).
#[inline(always)]
pub(crate) fn store<V: Lanes>(dst: &mut [f32], at: usize, v: V, n: usize) {
    let v = v.to_array();
    if n == LANES {
        let out: &mut [f32; LANES] = (&mut dst[at..at + LANES]).try_into().expect("eight");
        *out = v;
    } else {
        for (o, x) in dst[at..at + n].iter_mut().zip(v) {
            *o = x;
        }
    }
}

#[cfg(feature = "reference")]
/// The mask of the first `n` lanes.
#[inline(always)]
pub(crate) fn first<V: Lanes>(n: usize) -> V {
    const IOTA: [f32; LANES] = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
    V::new(IOTA).simd_lt(V::splat(n as f32))
}

/// The larger of two values (`a > b ? a : b`, the `maxps` rule).
#[inline(always)]
pub(crate) fn hi(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// The ENO choice: the second difference of smaller magnitude.
#[inline(always)]
pub(crate) fn eno_pick<V: Lanes>(a: V, b: V) -> V {
    a.abs().simd_le(b.abs()).select(a, b)
}

/// Constants of one time step, in the `f32` of the kernels.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Step<'a> {
    /// The speed field d.
    pub(crate) d: &'a [f32],
    /// The dense grid's node counts and strides (the dense sweep's).
    #[cfg(feature = "reference")]
    pub(crate) dims: [usize; 3],
    #[cfg(feature = "reference")]
    pub(crate) strides: [usize; 3],
    pub(crate) h: f32,
    pub(crate) inv_h: f32,
    pub(crate) beta: f32,
    pub(crate) gamma: f32,
    /// 1/(γ − β)³ for the cut-off's cubic.
    pub(crate) inv_cube: f32,
    pub(crate) arrest: f32,
    pub(crate) dt: f32,
    pub(crate) eno: bool,
    /// The full grid: the new T keeps every candidate node.
    pub(crate) keep_all: bool,
    /// The curvature weight λ of the regularised flow (world units, f64 as the
    /// scalar curvature stencil).
    pub(crate) curvature: Option<f64>,
    /// Zhao's flow ∇d·∇φ instead of d|∇φ|.
    pub(crate) zhao: bool,
}

impl<'a> Step<'a> {
    /// The constants of `params` on `grid` with tube half-width `gamma` and
    /// speed field `d` (Δt still 0).
    pub(crate) fn new(grid: &GridSpec, gamma: f32, params: &EvolveParams, d: &'a [f32]) -> Self {
        let h = grid.spacing;
        let gamma64 = f64::from(gamma);
        let beta = params.beta.clamp(0.0, gamma64 * 0.999);
        Step {
            d,
            #[cfg(feature = "reference")]
            dims: grid.dims,
            #[cfg(feature = "reference")]
            strides: grid.strides(),
            h: h as f32,
            inv_h: (1.0 / h) as f32,
            beta: beta as f32,
            gamma,
            inv_cube: (1.0 / (gamma64 - beta).powi(3)) as f32,
            arrest: params.arrest as f32,
            dt: 0.0,
            eno: params.scheme == Scheme::Eno2,
            keep_all: params.band == Band::Full,
            curvature: match params.flow {
                Flow::Convection | Flow::Zhao => None,
                Flow::Regularized { weight } => Some(weight),
            },
            zhao: params.flow == Flow::Zhao,
        }
    }
}

/// Whether the largest speed `vmax` of T says the front has stopped: for the
/// flows moving at c·d (arrested), not for Zhao's, whose speed is ∇d·n.
pub(crate) fn stopped(params: &EvolveParams, vmax: f32) -> bool {
    vmax <= 0.0 && params.flow != Flow::Zhao
}

/// The time step for the largest speed `vmax` on a grid of spacing `h`: CFL,
/// and the curvature term's diffusion limit for the regularised flow.
pub(crate) fn time_step(params: &EvolveParams, h: f64, vmax: f32) -> f64 {
    let mut dt = params.cfl * h / f64::from(vmax);
    match params.flow {
        Flow::Regularized { weight } => {
            dt = dt.min(0.9 * h * h / (6.0 * weight.max(1e-300) * f64::from(vmax)));
        }
        // |v|₁ = Σ|∂d| ≤ √3 (each difference of the 1-Lipschitz d is at most 1).
        Flow::Zhao => dt = params.cfl * h / 3f64.sqrt(),
        Flow::Convection => {}
    }
    dt
}

impl Step<'_> {
    /// The cut-off c(φ) of Eq. 10 at eight nodes.
    #[inline(always)]
    pub(crate) fn cutoff<V: Lanes>(&self, phi: V) -> V {
        let splat = V::splat;
        let a = phi.abs();
        let t = a - splat(self.gamma);
        let cubic = t
            * t
            * (splat(2.0) * a + splat(self.gamma) - splat(3.0 * self.beta))
            * splat(self.inv_cube);
        a.simd_le(splat(self.beta)).select(
            splat(1.0),
            a.simd_le(splat(self.gamma)).select(cubic, splat(0.0)),
        )
    }

    /// The cut-off c(φ) of Eq. 10 times d at eight nodes, 0 closer than the
    /// arrest distance (and where d is negative: a held node, see
    /// [`zhao_rate`]).
    #[inline(always)]
    pub(crate) fn speeds<V: Lanes>(&self, phi: V, d: V) -> V {
        let c = self.cutoff(phi);
        d.simd_lt(V::splat(self.arrest))
            .select(V::splat(0.0), c * d)
    }
}

/// Eight nodes' values and their neighbours along the axes. The flow's
/// kernels read φ and d only through this, so that the dense grid's runs and
/// the sparse bricks ([`crate::sparse::flow`]) share them to the bit.
pub(crate) trait Stencil<V: Lanes> {
    /// The eight values.
    fn centre(&self) -> V;
    /// The values `k` nodes on along `axis` (|k| ≤ 2).
    fn along(&self, axis: usize, k: isize) -> V;
    /// κ and |∇φ| at lane `l` by central differences (Eq. 2).
    fn curvature(&self, l: usize, h: f64) -> (f64, f64);
}

#[cfg(feature = "reference")]
/// Eight consecutive nodes from `at` of a dense buffer.
pub(crate) struct Strided<'a> {
    /// The buffer.
    pub src: &'a [f32],
    /// The first node, as an index into `src`.
    pub at: usize,
    /// The grid's strides.
    pub strides: [usize; 3],
}

#[cfg(feature = "reference")]
impl<V: Lanes> Stencil<V> for Strided<'_> {
    #[inline(always)]
    fn centre(&self) -> V {
        load(self.src, self.at)
    }

    #[inline(always)]
    fn along(&self, axis: usize, k: isize) -> V {
        load(
            self.src,
            self.at.wrapping_add_signed(k * self.strides[axis] as isize),
        )
    }

    #[inline(always)]
    fn curvature(&self, l: usize, h: f64) -> (f64, f64) {
        crate::curvature::curvature_and_gradient(self.src, self.at + l, self.strides, h)
    }
}

#[cfg(feature = "reference")]
/// The bits of the first `n` lanes.
#[inline(always)]
pub(crate) fn lane_bits(n: usize) -> u32 {
    (1 << n) - 1
}

/// Zhao's rate c(φ) ∇d·∇φ at eight nodes: ∇d by central differences of the
/// distance (1-Lipschitz, so each component is at most 1), ∇φ upwinded for
/// the velocity v = −∇d: D⁻ where v points along +x, D⁺ where it points back.
///
/// The sampled-surface model marks nodes by a negative d (the distance is
/// |d|; `crate::sparse::voids::freeze`): a marked node beyond δ + 2h from the
/// samples (δ the arrest distance) lies deep in a void and is held (rate 0);
/// one nearer lies on a thin part, where φ may rise only to the obstacle
/// ψ = |d| − δ (the rate is capped at (ψ − φ)/Δt), so the fronts closing on
/// a thin sheet from both sides stop on the smooth level set {d = δ} and the
/// sheet keeps an inside.
#[inline(always)]
pub(crate) fn zhao_rate<V: Lanes>(
    c: &Step,
    phi: &impl Stencil<V>,
    d: &impl Stencil<V>,
    p0: V,
) -> V {
    let zero = V::splat(0.0);
    let half_inv_h = V::splat(0.5 * c.inv_h);
    let mut sum = zero;
    for axis in 0..3 {
        let (dm, dp) = one_sided(c, phi, axis, p0);
        let g = (d.along(axis, 1).abs() - d.along(axis, -1).abs()) * half_inv_h;
        sum += g * g.simd_lt(zero).select(dm, dp);
    }
    let rate = c.cutoff(p0) * sum;
    let dc = d.centre();
    let marked = dc.simd_lt(zero);
    if marked.to_bitmask() == 0 {
        return rate;
    }
    let near = dc.abs();
    let arrest = V::splat(c.arrest);
    // `crate::sparse::voids::obstacle_reach`.
    let thin = near.simd_lt(V::splat(c.arrest + 2.0 * c.h));
    let obstacle = if c.dt > 0.0 {
        rate.fast_min((near - arrest - p0) * V::splat(1.0 / c.dt))
    } else {
        rate
    };
    marked.select(thin.select(obstacle, zero), rate)
}

/// One-sided differences (D⁻, D⁺) along `axis` for eight nodes: first order,
/// or second-order ENO (Osher & Shu).
#[inline(always)]
pub(crate) fn one_sided<V: Lanes>(c: &Step, st: &impl Stencil<V>, axis: usize, p0: V) -> (V, V) {
    let (pm, pp) = (st.along(axis, -1), st.along(axis, 1));
    let inv_h = V::splat(c.inv_h);
    let mut dm = (p0 - pm) * inv_h;
    let mut dp = (pp - p0) * inv_h;
    if c.eno {
        let (pmm, ppp) = (st.along(axis, -2), st.along(axis, 2));
        let (two, half) = (V::splat(2.0), V::splat(0.5 * c.inv_h));
        let c0 = pp - two * p0 + pm;
        let cm = p0 - two * pm + pmm;
        let cp = ppp - two * pp + p0;
        #[cfg(feature = "fault-injection")]
        if crate::faults::on(crate::faults::Fault::EnoSign) {
            dm -= V::splat(2.0) * half * eno_pick(cm, c0);
        }
        dm += half * eno_pick(cm, c0);
        dp -= half * eno_pick(c0, cp);
    }
    (dm, dp)
}

/// The flow's rate d·c(φ)|∇φ| (plus the curvature term) at eight nodes; |∇φ|
/// upwinded for the inward-moving front (F < 0): √Σ max(min(D⁻,0)²,
/// max(D⁺,0)²). The curvature term is evaluated on the lanes of `valid`;
/// the other lanes may come out as anything (their nodes are not stored).
#[inline(always)]
pub(crate) fn rate<V: Lanes, const ZHAO: bool>(
    c: &Step,
    phi: &impl Stencil<V>,
    d: &impl Stencil<V>,
    valid: u32,
) -> V {
    let p0 = phi.centre();
    if ZHAO {
        return zhao_rate(c, phi, d, p0);
    }
    let zero = V::splat(0.0);
    let speed = c.speeds(p0, d.centre());
    // Arrested or cut off on every node that counts: the rate is +0 there
    // (0 · |∇φ| with |∇φ| finite), without the differences.
    if speed.simd_gt(zero).to_bitmask() & valid == 0 {
        return zero;
    }
    let mut g2 = zero;
    for axis in 0..3 {
        let (dm, dp) = one_sided(c, phi, axis, p0);
        let (a, b) = (dm.fast_min(zero), dp.fast_max(zero));
        #[cfg(feature = "fault-injection")]
        let (a, b) = if crate::faults::on(crate::faults::Fault::UpwindSide) {
            (dm.fast_max(zero), dp.fast_min(zero))
        } else {
            (a, b)
        };
        g2 += (a * a).fast_max(b * b);
    }
    let out = speed * g2.sqrt();
    let Some(weight) = c.curvature else {
        return out;
    };
    let (speed, mut out) = (speed.to_array(), out.to_array());
    let h = f64::from(c.h);
    for (l, o) in out.iter_mut().enumerate() {
        if valid >> l & 1 == 1 && speed[l] != 0.0 {
            let (kappa, grad) = phi.curvature(l, h);
            *o += (f64::from(speed[l]) * weight * kappa * grad) as f32;
        }
    }
    V::new(out)
}

/// One first-order Godunov iteration of Eq. 11 at eight nodes: φ − Δτ
/// S(φ)(|∇φ| − 1), S = φ/√(φ² + |∇φ|²h²), Δτ = 0.3h.
#[inline(always)]
pub(crate) fn redistanced<V: Lanes>(c: &Step, st: &impl Stencil<V>) -> V {
    let p0 = st.centre();
    let (zero, inv_h) = (V::splat(0.0), V::splat(c.inv_h));
    let outside = p0.simd_gt(zero);
    let mut g2 = zero;
    for axis in 0..3 {
        let (pm, pp) = (st.along(axis, -1), st.along(axis, 1));
        let a = (p0 - pm) * inv_h;
        let b = (pp - p0) * inv_h;
        let (a_out, b_out) = (a.fast_max(zero), b.fast_min(zero));
        let (a_in, b_in) = (a.fast_min(zero), b.fast_max(zero));
        g2 += outside.select(
            (a_out * a_out).fast_max(b_out * b_out),
            (a_in * a_in).fast_max(b_in * b_in),
        );
    }
    let h = V::splat(c.h);
    let norm = (p0 * p0 + g2 * h * h).sqrt().fast_max(V::splat(1e-30));
    #[cfg(feature = "fault-injection")]
    if crate::faults::on(crate::faults::Fault::RedistanceStep) {
        return p0 - V::splat(0.6 * c.h) * (p0 / norm) * (g2.sqrt() - V::splat(1.0));
    }
    p0 - V::splat(0.3 * c.h) * (p0 / norm) * (g2.sqrt() - V::splat(1.0))
}
