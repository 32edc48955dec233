//! Narrow-band level-set evolution by the convection flow (§5.1–5.2, Eqs. 6, 10–12).
//!
//! The level-set function φ (negative inside, Eq. 1's convention) moves by the
//! paper's convection model
//!
//! ```text
//! φ_t = d(x) |∇φ|                                   (Eq. 6)
//! ```
//!
//! i.e. φ_t + F|∇φ| = 0 with normal speed F = −d: the front moves inward, against
//! its outward normal, at the speed of its distance from the data, and stops on the
//! data. Zhao's flow uses v = −∇d instead; the paper replaces it by −d because ∇d
//! is unstable on rough data.
//!
//! One step, as in the paper's outline (after Peng et al.'s fast local level set):
//! 1. **Tubes.** T = {|φ| < γ} (where φ advances) and N = T plus one node along each
//!    axis (where φ is redistanced). Both are node lists, rebuilt after every
//!    step from the previous N (the front moves less than a cell per step, so T′ ⊂ N).
//! 2. **Advance** φ in T by the Godunov upwind Hamiltonian (Osher & Sethian 1988)
//!    with first-order or second-order ENO one-sided differences (Osher & Shu 1991)
//!    and the two-stage TVD Runge–Kutta scheme (Shu & Osher 1988):
//!    φ¹ = φⁿ + Δt L(φⁿ), φⁿ⁺¹ = ½φⁿ + ½(φ¹ + Δt L(φ¹)). The speed is damped by the
//!    cut-off c(φ) of Eq. 10 (1 for |φ| ≤ β, a cubic to 0 at |φ| = γ). The step is
//!    CFL-limited: Δt = cfl · h / max_T c·d.
//! 3. **Redistance** on N by the sign-function Hamilton–Jacobi equation
//!    d_τ + S(d)(|∇d| − 1) = 0, S = d/√(d² + |∇d|²h²) (Eq. 11), first-order Godunov
//!    upwinding (Sussman, Smereka & Osher 1994), pseudo-time step 0.3h, a few
//!    iterations (the paper: "one or two").
//! 4. **Clamp** φ to [−γ, γ] (Eq. 12); nodes outside N keep ±γ.
//!
//! Every pass computes the new values of its nodes from the old ones (Jacobi): φ
//! is held in two buffers during the flow, and each pass reads one and writes the
//! other (or itself, only at the node being updated). Each pass is per node, a
//! maximum or an integer (fixed-point) sum, so the result does not depend on the
//! thread count.
//!
//! **Layout and speed.** The tubes are runs of consecutive nodes along x, listed
//! per plane (module `tube`). A stencil read of eight consecutive nodes along
//! any axis is then eight consecutive floats, so the kernels evaluate eight
//! nodes at once in vector registers (in `f32`; one AVX register where the CPU
//! has AVX, chosen at run time, see module `lanes`), and each plane's runs write
//! only that plane. A step's passes (advance, finish, redistancing, tube rebuild)
//! are fused into one sweep over the planes: pass i runs a fixed number of
//! planes behind the first, just far enough for everything it reads to be done
//! and everything it overwrites to be read, so each plane is fetched from memory
//! once per step rather than once per pass (at 256³ the tubes' cache lines are
//! several times the L3 cache). Slabs of planes are swept in parallel through
//! disjoint `&mut` slices, with no atomics, and the seams between them
//! afterwards; the result equals running the passes one after the other, bit for
//! bit (tested). The runs jump a row apart, which the hardware prefetcher does
//! not follow, so each pass prefetches the rows it meets first a few runs ahead.
//! N is T dilated by merging five sorted run lists per plane.
//!
//! Progress is measured by the front movement: the mean |Δφ| of the flow update
//! (before redistancing) over the nodes within one cell of the front, in cells per
//! step, summed in fixed point (2⁻¹⁶ cells); a tolerance on it ends the evolution
//! early.
//!
//! [`Flow::Regularized`] adds the curvature term of Zhao's weighted minimal surface
//! model, d·λκ|∇φ| with κ = ∇·(∇φ/|∇φ|) (Eq. 2) by central differences, to show the
//! contrast the paper draws in §6: the surface is smoother, and roughness is lost.
//! (Zhao's own flow also has the ∇d·∇φ convection; like the paper, this one keeps
//! the convection by d.)
//!
//! [`Band::Full`] updates every node at every step (same physics, no tubes): the
//! naive scheme the tubes are measured against.
//!
//! # Deviations from the paper
//!
//! **Arrest.** With the unsigned d of Eq. 6 the continuous front approaches the data
//! asymptotically. On the grid, Eq. 6 alone keeps that property (a densely sampled
//! sphere stays within h/2 for 200 steps without redistancing), but the
//! redistancing of Eq. 11 moves the zero level a little wherever the front sits
//! between data samples, and the flow then carries it on: the zero level creeps
//! through S and accelerates inward (d grows again inside). The tests show it on
//! a sphere (`asperity_engine::reconstruct::RECONSTRUCT_PAPER` lists the
//! numbers). Without redistancing, though, φ flattens and a front that must
//! travel far stalls. So nodes closer than an arrest distance δ to a data point
//! have speed 0 (default δ = h/2 for a continuous surface): the front then stops
//! about δ outside the data and stays there (measured on a sphere, at every
//! orientation of its surface). For sampled surfaces the pipeline sets δ from the
//! sample spacing, at least 0.6h ([`crate::ReconstructParams::point_radius`]).
//! δ = 0 gives the paper's model exactly, whose only stop is the iteration count.

use asperity_core::Progress;
use rayon::prelude::*;

use crate::distance::DistanceField;
use crate::grid::GridSpec;
use crate::lanes::{Kernel, Lanes, dispatch};
use crate::tagging::Tags;
use crate::tube::{Run, RunTube, push_lanes};
use asperity_core::memory_hints::prefetch;

/// A level-set function on the grid: φ < 0 inside, |φ| ≤ γ.
#[derive(Clone, Debug)]
pub struct LevelSet {
    /// The grid.
    pub grid: GridSpec,
    /// φ at every node, x fastest.
    pub phi: Vec<f32>,
    /// The tube half-width γ (world units): |φ| never exceeds it.
    pub gamma: f32,
}

/// Space discretisation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// First-order upwind (Godunov) differences.
    Upwind,
    /// Second-order ENO differences (the paper's choice).
    Eno2,
}

/// The flow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Flow {
    /// φ_t = d|∇φ| (Eq. 6).
    Convection,
    /// φ_t = d(1 + λκ)|∇φ|: the convection plus a curvature term of weight λ (a length).
    Regularized {
        /// λ in world units.
        weight: f64,
    },
    /// φ_t = ∇d·∇φ: Zhao's convection by the velocity v = −∇d (Eq. 5 with
    /// Zhao's v), the flow the paper replaces by Eq. 6.
    Zhao,
}

/// The neighbourhood that grows T into the redistancing tube N.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Neighbourhood {
    /// One node along each axis (6 neighbours): enough for the first-order
    /// redistancing stencil, and the fastest.
    #[default]
    Axes,
    /// The 3 × 3 × 3 block (26 neighbours), the paper's N =
    /// {min over −1 ≤ ν, µ ≤ 1 of |φ| ≤ γ} (§5.2, step 1) in 3-D.
    Cube,
}

/// Where φ is updated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Band {
    /// The tubes T and N.
    Narrow,
    /// Every node, every step.
    Full,
}

/// Evolution settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvolveParams {
    /// Time steps to take (the paper shows 30, 100 and 200).
    pub iterations: usize,
    /// Space discretisation.
    pub scheme: Scheme,
    /// The flow.
    pub flow: Flow,
    /// CFL number (≤ 0.5 recommended).
    pub cfl: f64,
    /// Full-speed half-width β of Eq. 10 (world units, < γ).
    pub beta: f64,
    /// Redistancing iterations per step (0 turns it off).
    pub redistance_iterations: usize,
    /// Stop once the front moves less than this many cells per step.
    pub tolerance: Option<f64>,
    /// Narrow band or the naive full grid.
    pub band: Band,
    /// Nodes closer than this to the data do not move (world units; 0 is the
    /// paper's model, see the module docs).
    pub arrest: f64,
    /// Call `on_step` with the level set every this many steps (`None`: never).
    pub snapshot_every: Option<usize>,
    /// How T grows into N.
    pub neighbourhood: Neighbourhood,
}

impl EvolveParams {
    /// The paper's settings: 30 steps of ENO2/RK2 convection, β = 2h, two
    /// redistancing iterations per step; CFL 0.9 and arrest h/2 are ours.
    pub fn paper(h: f64) -> Self {
        Self {
            iterations: 30,
            scheme: Scheme::Eno2,
            flow: Flow::Convection,
            cfl: 0.9,
            beta: 2.0 * h,
            redistance_iterations: 2,
            tolerance: None,
            band: Band::Narrow,
            arrest: ARREST_CELLS * h,
            snapshot_every: None,
            neighbourhood: Neighbourhood::Cube,
        }
    }
}

/// The default arrest distance in cells: half a cell.
pub const ARREST_CELLS: f64 = 0.5;

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepStats {
    /// Step number, from 1.
    pub step: usize,
    /// Time step Δt.
    pub dt: f64,
    /// Mean |Δφ| near the front, in cells.
    pub front_movement: f64,
    /// Nodes in T.
    pub tube: usize,
}

/// What the evolution did.
#[derive(Clone, Debug, PartialEq)]
pub struct EvolveStats {
    /// Per step.
    pub steps: Vec<StepStats>,
    /// Whether the tolerance stopped it (or the speed vanished).
    pub converged: bool,
}

/// The cut-off c(φ) of Eq. 10.
#[inline]
pub fn cutoff(phi: f64, beta: f64, gamma: f64) -> f64 {
    let a = phi.abs();
    if a <= beta {
        1.0
    } else if a <= gamma {
        (a - gamma).powi(2) * (2.0 * a + gamma - 3.0 * beta) / (gamma - beta).powi(3)
    } else {
        0.0
    }
}

/// The signed distance to the tagged front (the paper: "we recompute the distance
/// function for the tagged boundary … negating the distance function at all
/// interior cells"), clamped to ±γ.
///
/// The front crosses every grid edge from an exterior to an interior node; it is
/// placed where d − ε changes sign along the edge (linear interpolation), or at the
/// edge's midpoint where the paper's rule stopped the front at a larger distance.
/// The distance to these crossing points, by the closest-point method, is |φ|.
pub fn from_tags(
    dist: &DistanceField,
    tags: &Tags,
    eps: f64,
    gamma: f64,
    progress: &dyn Progress,
) -> LevelSet {
    from_tags_reusing(dist, tags, eps, gamma, progress, None)
}

/// Whether row (·, j, k) of the exterior flags can hold a crossing: rows with
/// no exterior node, or exterior along with the rows around them (most of the
/// grid), hold none.
fn row_may_cross(grid: &GridSpec, ext: &[bool], j: usize, k: usize) -> bool {
    let [nx, ny, nz] = grid.dims;
    let row = |j: usize, k: usize| &ext[grid.index(0, j, k)..grid.index(0, j, k) + nx];
    let own = row(j, k);
    let around = [
        (j > 0).then(|| row(j - 1, k)),
        (j + 1 < ny).then(|| row(j + 1, k)),
        (k > 0).then(|| row(j, k - 1)),
        (k + 1 < nz).then(|| row(j, k + 1)),
    ];
    own.contains(&true)
        && (own.contains(&false) || around.iter().flatten().any(|r| r.contains(&false)))
}

/// The points where the tagged offset surface {d = ε} crosses the grid edges
/// from exterior node (i, j, k) to its non-exterior neighbours: d interpolated
/// linearly to ε along the edge (the midpoint where it does not cross ε).
fn node_crossings(
    (grid, d, ext): (&GridSpec, &[f32], &[bool]),
    [i, j, k]: [usize; 3],
    eps: f64,
    out: &mut Vec<[f64; 3]>,
) {
    let strides = grid.strides();
    let u = grid.index(i, j, k);
    let c = [i, j, k];
    for a in 0..3 {
        for side in [false, true] {
            let v = if side {
                if c[a] + 1 >= grid.dims[a] {
                    continue;
                }
                u + strides[a]
            } else {
                if c[a] == 0 {
                    continue;
                }
                u - strides[a]
            };
            if ext[v] {
                continue;
            }
            out.push(crossing_point(
                grid,
                [i, j, k],
                (a, side),
                (d[u], d[v]),
                eps,
            ));
        }
    }
}

/// Where {d = ε} crosses the grid edge from exterior node `c` along `axis`
/// (upward when `up`) to a non-exterior node: d (`du` at `c`, `dv` at the
/// other end) interpolated linearly to ε, or the midpoint where it does not
/// cross ε.
#[inline]
pub(crate) fn crossing_point(
    grid: &GridSpec,
    c: [usize; 3],
    (axis, up): (usize, bool),
    (du, dv): (f32, f32),
    eps: f64,
) -> [f64; 3] {
    let (du, dv) = (f64::from(du), f64::from(dv));
    let theta = if du >= eps && dv < eps {
        (du - eps) / (du - dv)
    } else {
        0.5
    };
    let mut p = grid.position(c[0], c[1], c[2]);
    p[axis] += if up { theta } else { -theta } * grid.spacing;
    p
}

/// Every crossing of the offset surface, plane by plane.
fn crossings(grid: &GridSpec, d: &[f32], ext: &[bool], eps: f64) -> Vec<[f64; 3]> {
    let [nx, ny, nz] = grid.dims;
    (0..nz)
        .into_par_iter()
        .flat_map_iter(|k| {
            let mut out = Vec::new();
            for j in 0..ny {
                if !row_may_cross(grid, ext, j, k) {
                    continue;
                }
                for i in 0..nx {
                    if ext[grid.index(i, j, k)] {
                        node_crossings((grid, d, ext), [i, j, k], eps, &mut out);
                    }
                }
            }
            out
        })
        .collect()
}

/// [`from_tags`], with the closest-point cells of an earlier wavefront on this
/// grid to refill rather than a fresh buffer.
pub(crate) fn from_tags_reusing(
    dist: &DistanceField,
    tags: &Tags,
    eps: f64,
    gamma: f64,
    progress: &dyn Progress,
    cells: Option<Vec<std::sync::atomic::AtomicU64>>,
) -> LevelSet {
    let grid = dist.grid;
    let ext = &tags.exterior;
    let crossings = crossings(&grid, &dist.values, ext, eps);
    let gamma32 = gamma as f32;
    if crossings.is_empty() {
        // Nothing was tagged (or everything was): φ is ±γ everywhere.
        let phi = ext
            .par_iter()
            .map(|&e| if e { gamma32 } else { -gamma32 })
            .collect();
        return LevelSet {
            grid,
            phi,
            gamma: gamma32,
        };
    }
    // Straight from the packed closest points to φ: no distance field, no
    // nearest-point array. |φ| is clamped at γ, so the wavefront stops half a
    // cell beyond it.
    let cap = gamma + 0.5 * grid.spacing;
    let (cells, _) = crate::distance::closest_points(&crossings, &grid, cap, progress, cells);
    let phi = cells
        .into_par_iter()
        .zip(ext.par_iter())
        .map(|(c, &e)| {
            let c = c.into_inner();
            let r = if c == crate::distance::EMPTY {
                gamma32
            } else {
                crate::distance::unpack_d2(c).sqrt().min(gamma32)
            };
            if e { r } else { -r }
        })
        .collect();
    LevelSet {
        grid,
        phi,
        gamma: gamma32,
    }
}

/// Nodes evaluated together: eight `f32` lanes (`wide`'s portable vectors: one
/// AVX register, or two SSE registers on a baseline build).
pub(crate) const LANES: usize = 8;

/// `s[at .. at + 8]`. In range for every node the flow loads from: a stencil
/// reaches two nodes along one axis, so the eight loaded from the last node of T
/// (two nodes from each face) end well before the grid's last row.
#[inline(always)]
pub(crate) fn load<V: Lanes>(s: &[f32], at: usize) -> V {
    let x: [f32; LANES] = s[at..at + LANES].try_into().expect("eight values");
    V::new(x)
}

/// Writes the first `n` lanes of `v` at `dst[at..]`: one vector store for a
/// full chunk (a slice copy of variable length would call `memmove`).
#[inline(always)]
fn store<V: Lanes>(dst: &mut [f32], at: usize, v: V, n: usize) {
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

/// The mask of the first `n` lanes.
#[inline(always)]
fn first<V: Lanes>(n: usize) -> V {
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
fn eno_pick<V: Lanes>(a: V, b: V) -> V {
    a.abs().simd_le(b.abs()).select(a, b)
}

/// Constants of one time step, in the `f32` of the kernels.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Step<'a> {
    /// The speed field d.
    pub(crate) d: &'a [f32],
    pub(crate) dims: [usize; 3],
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
            dims: grid.dims,
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
    /// arrest distance.
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

/// Eight consecutive nodes from `at` of a dense buffer.
pub(crate) struct Strided<'a> {
    /// The buffer.
    pub src: &'a [f32],
    /// The first node, as an index into `src`.
    pub at: usize,
    /// The grid's strides.
    pub strides: [usize; 3],
}

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

/// The bits of the first `n` lanes.
#[inline(always)]
pub(crate) fn lane_bits(n: usize) -> u32 {
    (1 << n) - 1
}

/// Zhao's rate c(φ) ∇d·∇φ at eight nodes: ∇d by central differences of the
/// distance (1-Lipschitz, so each component is at most 1), ∇φ upwinded for
/// the velocity v = −∇d: D⁻ where v points along +x, D⁺ where it points back.
#[inline(always)]
fn zhao_rate<V: Lanes>(c: &Step, phi: &impl Stencil<V>, d: &impl Stencil<V>, p0: V) -> V {
    let zero = V::splat(0.0);
    let half_inv_h = V::splat(0.5 * c.inv_h);
    let mut sum = zero;
    for axis in 0..3 {
        let (dm, dp) = one_sided(c, phi, axis, p0);
        let g = (d.along(axis, 1) - d.along(axis, -1)) * half_inv_h;
        sum += g * g.simd_lt(zero).select(dm, dp);
    }
    c.cutoff(p0) * sum
}

/// One-sided differences (D⁻, D⁺) along `axis` for eight nodes: first order,
/// or second-order ENO (Osher & Shu).
#[inline(always)]
fn one_sided<V: Lanes>(c: &Step, st: &impl Stencil<V>, axis: usize, p0: V) -> (V, V) {
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
    p0 - V::splat(0.3 * c.h) * (p0 / norm) * (g2.sqrt() - V::splat(1.0))
}

/// One of the two buffers φ lives in during a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Buf {
    /// `LevelSet::phi`: φⁿ at the start of a step, φⁿ⁺¹ at its end.
    Phi,
    /// The scratch buffer.
    Scratch,
}

/// One pass of a time step. Each reads one buffer with a stencil and writes a
/// buffer on its own nodes, plane by plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    /// Stage 1 of RK2 on T: scratch = φ¹ = φⁿ + Δt L(φⁿ).
    Advance,
    /// Stage 2 on T, in place: φⁿ⁺¹ = ½φⁿ + ½(φ¹ + Δt L(φ¹)); measures the
    /// front movement.
    Finish,
    /// One redistancing iteration on N from the other buffer into `into`,
    /// clamped to ±γ when `clamp` (Eq. 12).
    Redistance { into: Buf, clamp: bool },
    /// φ = scratch on N (after an odd number of redistancing iterations).
    CopyBack,
    /// φ clamped to ±γ on N (no redistancing).
    Clamp,
    /// The new T from φ on the old N with its largest speed; scratch = φ there.
    Rebuild,
}

impl Op {
    /// The buffer read with a stencil, the stencil's reach in planes, and the
    /// buffer written.
    pub(crate) fn access(self) -> (Buf, usize, Buf) {
        match self {
            Op::Advance => (Buf::Phi, 2, Buf::Scratch),
            Op::Finish => (Buf::Scratch, 2, Buf::Phi),
            Op::Redistance {
                into: Buf::Scratch, ..
            } => (Buf::Phi, 1, Buf::Scratch),
            Op::Redistance { into: Buf::Phi, .. } => (Buf::Scratch, 1, Buf::Phi),
            Op::CopyBack => (Buf::Scratch, 0, Buf::Phi),
            Op::Clamp => (Buf::Phi, 0, Buf::Phi),
            Op::Rebuild => (Buf::Phi, 0, Buf::Scratch),
        }
    }
}

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
        let mut ops = vec![Op::Advance, Op::Finish];
        for pass in 0..redistance_iterations {
            ops.push(Op::Redistance {
                into: if pass % 2 == 0 {
                    Buf::Scratch
                } else {
                    Buf::Phi
                },
                clamp: pass + 1 == redistance_iterations,
            });
        }
        if redistance_iterations % 2 == 1 {
            ops.push(Op::CopyBack);
        } else if redistance_iterations == 0 {
            ops.push(Op::Clamp);
        }
        ops.push(Op::Rebuild);
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
struct Swept {
    moved: Movement,
    /// The new T's runs of the planes rebuilt here.
    rebuilt: Vec<(usize, Vec<Run>)>,
    /// The largest speed on those planes' new T.
    vmax: f32,
}

/// Fixed-point front movement: (Σ|Δφ|/h · 2¹⁶, node count).
pub(crate) type Movement = (u64, u64);

/// The planes `first ..` of both buffers.
struct Region<'a> {
    first: usize,
    phi: &'a mut [f32],
    scratch: &'a mut [f32],
}

/// The tubes of a step: T (advanced) and N (redistanced, and the candidates of
/// the next T).
#[derive(Clone, Copy)]
struct Tubes<'a> {
    t: &'a RunTube,
    n: &'a RunTube,
}

/// [`run_region`] as a [`Kernel`].
struct RegionKernel<'a, 'r> {
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
fn run_region<V: Lanes>(
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
struct Chunks<'a> {
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
fn advance<V: Lanes, const ZHAO: bool>(
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
fn finish<V: Lanes, const ZHAO: bool>(
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
fn redistance<V: Lanes>(
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
const PREFETCH_RUNS: usize = 4;

/// How a step's passes are ordered (tests compare the orders).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Order {
    /// Pipelined over slabs of planes, about this many slabs per thread.
    Fused { slabs_per_thread: usize },
    /// Each pass over the whole grid before the next, in one region.
    #[cfg(test)]
    PassByPass,
}

/// The slab boundaries: cut planes at least `gap` apart and from the grid's
/// ends, splitting the planes' work (`n`'s nodes plus a fixed cost per plane)
/// into about `slabs` equal parts.
fn slab_cuts(n: &RunTube, slabs: usize, gap: usize) -> Vec<usize> {
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
fn carve<'a>(
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
fn step_sweep(
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
fn rebuild_plane<V: Lanes>(
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
fn first_tube(c: &Step, phi: &[f32]) -> (RunTube, f32) {
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

/// The fewest nodes per axis the flow works on.
pub(crate) const MIN_NODES: usize = 6;

/// Evolves `ls` by the flow for `params.iterations` steps with the speed `dist`;
/// `on_step` sees the level set every `params.snapshot_every` steps. Grids with
/// fewer than six nodes along an axis are left as they are.
pub fn evolve(
    ls: &mut LevelSet,
    dist: &DistanceField,
    params: &EvolveParams,
    progress: &dyn Progress,
    on_step: &mut dyn FnMut(&StepStats, &LevelSet),
) -> EvolveStats {
    let order = Order::Fused {
        slabs_per_thread: SLABS_PER_THREAD,
    };
    evolve_in_order(ls, dist, params, progress, on_step, order)
}

/// Slabs per thread in a fused step: a few, so that a thread that finishes
/// early takes over work (this VM's cores run at uneven speeds), and few enough
/// that the seams stay a small part of the planes.
const SLABS_PER_THREAD: usize = 2;

/// [`evolve`] with the passes of each step in `order`.
fn evolve_in_order(
    ls: &mut LevelSet,
    dist: &DistanceField,
    params: &EvolveParams,
    progress: &dyn Progress,
    on_step: &mut dyn FnMut(&StepStats, &LevelSet),
    order: Order,
) -> EvolveStats {
    let grid = ls.grid;
    if grid.dims.iter().any(|&n| n < MIN_NODES) {
        // At most one node per row fits the ENO stencil: nothing to evolve (and
        // the eight-node loads would reach past the grid).
        return EvolveStats {
            steps: Vec::new(),
            converged: true,
        };
    }
    let h = grid.spacing;
    let full = params.band == Band::Full;
    let mut c = Step::new(&grid, ls.gamma, params, &dist.values);
    let plan = Plan::new(params.redistance_iterations);
    // φ lives in two buffers during the flow, `ls.phi` (current) and `scratch`,
    // equal outside the tube N between steps. Every pass reads one buffer and
    // writes the other on its own nodes (Jacobi): stage 1 reads φ and writes the
    // scratch on T; stage 2 reads the scratch's stencils and φ at the node itself,
    // and writes φ in place; redistancing alternates φ → scratch → φ on N; the
    // tube rebuild copies φ back into the scratch on N.
    let mut scratch = ls.phi.clone();
    let (mut t, mut vmax) = first_tube(&c, &ls.phi);
    let grow = |t: &RunTube| match (full, params.neighbourhood) {
        (true, _) => t.clone(),
        (false, Neighbourhood::Axes) => t.dilate(&grid),
        (false, Neighbourhood::Cube) => t.dilate_cube(&grid),
    };
    let mut n = grow(&t);
    progress.start(params.iterations as u64, "convection flow");
    let mut stats = EvolveStats {
        steps: Vec::new(),
        converged: false,
    };
    for step in 1..=params.iterations {
        if vmax <= 0.0 || t.is_empty() {
            stats.converged = true;
            break;
        }
        let dt = time_step(params, h, vmax);
        c.dt = dt as f32;
        let tubes = Tubes { t: &t, n: &n };
        let ((moved, count), new_t, new_vmax) =
            step_sweep(&c, &plan, tubes, &mut ls.phi, &mut scratch, order);
        let front_movement = if count > 0 {
            moved as f64 / 65536.0 / count as f64
        } else {
            0.0
        };
        let s = StepStats {
            step,
            dt,
            front_movement,
            tube: t.nodes(),
        };
        stats.steps.push(s);
        (t, vmax) = (new_t, new_vmax);
        n = grow(&t);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{GridSpec, Sizing};
    use asperity_core::MemoryBudget;

    fn sphere_grid(n: usize) -> GridSpec {
        let pts = [[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]];
        GridSpec::around(
            &pts,
            Sizing::Resolution(n),
            |_| 6,
            &MemoryBudget::unlimited(),
        )
        .unwrap()
    }

    fn norm(p: [f64; 3]) -> f64 {
        (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
    }

    fn signed_sphere(grid: &GridSpec, r: f64, gamma: f64) -> LevelSet {
        let phi = grid.sample(|p| (norm(p) - r).clamp(-gamma, gamma));
        LevelSet {
            grid: *grid,
            phi,
            gamma: gamma as f32,
        }
    }

    /// A speed field d with the given values.
    fn speed_field(grid: GridSpec, values: Vec<f32>) -> DistanceField {
        DistanceField {
            grid,
            values,
            cap: f32::INFINITY,
            nearest: None,
            sweeps: 0,
            last_change: 0.0,
        }
    }

    /// The radius of the ball with the volume of the inside nodes.
    fn volume_radius(ls: &LevelSet) -> f64 {
        let inside = ls.phi.iter().filter(|&&p| p < 0.0).count() as f64 * ls.grid.spacing.powi(3);
        (inside * 3.0 / (4.0 * std::f64::consts::PI)).cbrt()
    }

    #[test]
    fn cutoff_is_smooth_and_bounded() {
        let (b, g) = (2.0, 3.0);
        assert_eq!(cutoff(1.0, b, g), 1.0);
        assert!((cutoff(2.0, b, g) - 1.0).abs() < 1e-12);
        assert!(cutoff(3.0, b, g).abs() < 1e-12);
        assert_eq!(cutoff(-3.5, b, g), 0.0);
        let mid = cutoff(2.5, b, g);
        assert!(mid > 0.0 && mid < 1.0 && (mid - 0.5).abs() < 1e-12);
    }

    #[test]
    fn eno2_differences_are_exact_on_a_quadratic() {
        let phi: Vec<f32> = (0..24).map(|i| (i as f32 * 0.5).powi(2)).collect();
        let zeros = vec![0.0; 24];
        let mut c = Step {
            d: &zeros,
            dims: [24, 1, 1],
            strides: [1, 24, 24],
            h: 0.5,
            inv_h: 2.0,
            beta: 1.0,
            gamma: 2.0,
            inv_cube: 1.0,
            arrest: 0.0,
            dt: 0.0,
            eno: true,
            keep_all: false,
            curvature: None,
            zhao: false,
        };
        let p0 = load::<wide::f32x8>(&phi, 5);
        let st = Strided {
            src: &phi,
            at: 5,
            strides: c.strides,
        };
        let (dm, dp) = one_sided(&c, &st, 0, p0);
        let (dm, dp) = (dm.to_array(), dp.to_array());
        // d/dx x² at x = (5 + l)/2 is 5 + l, in every lane.
        for l in 0..LANES {
            let exact = 5.0 + l as f32;
            assert!(
                (dm[l] - exact).abs() < 1e-5 && (dp[l] - exact).abs() < 1e-5,
                "{l}: {} {}",
                dm[l],
                dp[l]
            );
        }
        c.eno = false;
        let st = Strided {
            src: &phi,
            at: 5,
            strides: c.strides,
        };
        let (dm, dp) = one_sided(&c, &st, 0, p0);
        let (dm, dp) = (dm.to_array(), dp.to_array());
        assert!((dm[0] - 4.5).abs() < 1e-5 && (dp[0] - 5.5).abs() < 1e-5);
    }

    /// Tiny grids, down to one node per axis, neither panic nor change; from six
    /// nodes on the flow runs.
    #[test]
    fn tiny_grids_are_safe() {
        for n in 1..=9 {
            let grid = GridSpec {
                origin: [0.0; 3],
                spacing: 1.0,
                dims: [n, n + 1, n],
            };
            let gamma = 3.0;
            let c = (n as f64 - 1.0) / 2.0;
            let phi: Vec<f32> = (0..grid.len())
                .map(|u| {
                    let q = grid.coords(u);
                    let r = ((q[0] as f64 - c).powi(2)
                        + (q[1] as f64 - c).powi(2)
                        + (q[2] as f64 - c).powi(2))
                    .sqrt();
                    (r - 0.4 * n as f64).clamp(-gamma, gamma) as f32
                })
                .collect();
            let mut ls = LevelSet {
                grid,
                phi: phi.clone(),
                gamma: gamma as f32,
            };
            let dist = speed_field(grid, vec![1.0; grid.len()]);
            for band in [Band::Narrow, Band::Full] {
                let mut params = EvolveParams::paper(1.0);
                params.band = band;
                params.iterations = 3;
                let stats = evolve(
                    &mut ls,
                    &dist,
                    &params,
                    &asperity_core::NoProgress,
                    &mut |_, _| {},
                );
                assert_eq!(ls.phi.len(), grid.len());
                if n < MIN_NODES {
                    assert!(stats.steps.is_empty() && ls.phi == phi, "n {n}");
                } else {
                    assert!(!stats.steps.is_empty(), "n {n}");
                }
            }
        }
    }

    /// With constant speed d ≡ v a sphere's radius shrinks by v·t exactly
    /// (φ_t = v|∇φ| moves the front inward at speed v).
    #[test]
    fn constant_speed_shrinks_a_sphere_at_that_speed() {
        let grid = sphere_grid(48);
        let h = grid.spacing;
        let gamma = 4.0 * h;
        for scheme in [Scheme::Upwind, Scheme::Eno2] {
            let mut ls = signed_sphere(&grid, 0.8, gamma);
            let dist = speed_field(grid, vec![1.0; grid.len()]);
            let mut params = EvolveParams::paper(h);
            params.scheme = scheme;
            params.iterations = 20;
            params.cfl = 0.5;
            params.snapshot_every = Some(1);
            let mut time = 0.0;
            let stats = evolve(
                &mut ls,
                &dist,
                &params,
                &asperity_core::NoProgress,
                &mut |s, _| time += s.dt,
            );
            assert_eq!(stats.steps.len(), 20);
            // Radius from the enclosed volume (count of negative nodes).
            let r = volume_radius(&ls);
            let expected = 0.8 - time;
            assert!(
                (r - expected).abs() < 0.5 * h,
                "{scheme:?}: r {r} vs {expected} (h {h})"
            );
        }
    }

    /// The fused sweep (slabs, seams, passes pipelined over the planes) gives
    /// the result of running each pass over the whole grid before the next, bit
    /// for bit: ENO and upwind, convection and the regularised flow, zero to
    /// three redistancing iterations, narrow band and full grid, one to five
    /// slabs per thread.
    #[test]
    fn fused_steps_equal_pass_by_pass() {
        let grid = sphere_grid(56);
        let h = grid.spacing;
        let gamma = 3.0 * h;
        // A rough speed field: the distance to a bumpy sphere.
        let d = grid.sample(|p| {
            let bump = 0.04 * (9.0 * p[0]).sin() * (7.0 * p[1]).cos() * (5.0 * p[2]).sin();
            (norm(p) - 0.5 - bump).abs()
        });
        let dist = speed_field(grid, d);
        let run = |params: &EvolveParams, order: Order| {
            let mut ls = signed_sphere(&grid, 0.85, gamma);
            let stats = evolve_in_order(
                &mut ls,
                &dist,
                params,
                &asperity_core::NoProgress,
                &mut |_, _| {},
                order,
            );
            let moved: Vec<u64> = stats
                .steps
                .iter()
                .map(|s| s.front_movement.to_bits())
                .collect();
            (
                ls.phi.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                moved,
            )
        };
        let mut cases = Vec::new();
        for redistance in 0..=3 {
            let mut p = EvolveParams::paper(h);
            p.iterations = 6;
            p.redistance_iterations = redistance;
            cases.push(p);
        }
        let mut upwind = EvolveParams::paper(h);
        upwind.scheme = Scheme::Upwind;
        upwind.iterations = 6;
        let mut curved = upwind;
        curved.scheme = Scheme::Eno2;
        curved.flow = Flow::Regularized { weight: h };
        let mut full = upwind;
        full.band = Band::Full;
        let mut zhao = upwind;
        zhao.flow = Flow::Zhao;
        let mut axes = upwind;
        axes.neighbourhood = Neighbourhood::Axes;
        cases.extend([upwind, curved, full, zhao, axes]);
        for params in &cases {
            let reference = run(params, Order::PassByPass);
            assert!(reference.1.iter().any(|&m| f64::from_bits(m) > 0.01));
            for slabs_per_thread in 1..=5 {
                let fused = run(params, Order::Fused { slabs_per_thread });
                assert!(
                    fused == reference,
                    "{slabs_per_thread} slabs per thread differ for {params:?}"
                );
            }
        }
        // The grid has room for several slabs even with the widest seams.
        let all = RunTube::interior_of(grid.dims, 2);
        assert!(slab_cuts(&all, 10, 2 * Plan::new(3).halo).len() >= 2);
        // The default step's depths, as documented on `Plan`.
        assert_eq!(Plan::new(2).depth, [2, 4, 6, 7, 8]);
        assert_eq!(Plan::new(2).halo, 8);
    }

    /// The tube rebuild leaves the same result as updating every node.
    #[test]
    fn narrow_band_agrees_with_the_full_grid() {
        let grid = sphere_grid(40);
        let h = grid.spacing;
        let gamma = 3.0 * h;
        let dist = speed_field(grid, grid.sample(|p| (norm(p) - 0.5).abs()));
        let mut results = Vec::new();
        for band in [Band::Narrow, Band::Full] {
            let mut ls = signed_sphere(&grid, 0.9, gamma);
            let mut params = EvolveParams::paper(h);
            params.band = band;
            params.iterations = 40;
            evolve(
                &mut ls,
                &dist,
                &params,
                &asperity_core::NoProgress,
                &mut |_, _| {},
            );
            results.push(volume_radius(&ls));
        }
        // Both converge onto the data sphere r = 0.5, stopping about δ = h/2 outside
        // it, and agree.
        for r in &results {
            assert!(*r > 0.5 && r - 0.5 < h, "{results:?} (h {h})");
        }
        assert!((results[0] - results[1]).abs() < 0.25 * h, "{results:?}");
        // The paper's model (δ = 0) has no grid-level steady state: the front
        // passes the data and moves on inward.
        let mut ls = signed_sphere(&grid, 0.9, gamma);
        let mut params = EvolveParams::paper(h);
        params.arrest = 0.0;
        params.iterations = 40;
        evolve(
            &mut ls,
            &dist,
            &params,
            &asperity_core::NoProgress,
            &mut |_, _| {},
        );
        let r = volume_radius(&ls);
        assert!(r < 0.5 - 0.5 * h, "pure convection stopped at {r}");
    }
}
