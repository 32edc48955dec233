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

#[cfg(feature = "reference")]
use asperity_core::Progress;
#[cfg(feature = "reference")]
use rayon::prelude::*;

#[cfg(feature = "reference")]
use crate::distance::DistanceField;
use crate::grid::GridSpec;
use crate::lanes::Lanes;
#[cfg(feature = "reference")]
use crate::lanes::{Kernel, dispatch};
#[cfg(feature = "reference")]
use crate::tagging::Tags;
#[cfg(feature = "reference")]
use crate::tube::{Run, RunTube, push_lanes};
#[cfg(feature = "reference")]
use asperity_core::memory_hints::prefetch;

mod kernels;
mod plan;
#[cfg(feature = "reference")]
mod sweep;

pub(crate) use kernels::*;
pub(crate) use plan::*;
#[cfg(feature = "reference")]
pub(crate) use sweep::*;

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
            cfl: CFL,
            beta: BETA_CELLS * h,
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

/// The time step's CFL number (ours: the paper states none).
pub const CFL: f64 = 0.9;

/// β, where the cut-off c(φ) starts to fall, in cells (the paper's 2h, §5.2,
/// Eq. 10).
pub const BETA_CELLS: f64 = 2.0;

/// γ, the tube's half-width and the clamp of φ, in cells (3h, §5.2).
pub const TUBE_CELLS: f64 = 3.0;

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

#[cfg(feature = "reference")]
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

#[cfg(feature = "reference")]
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

#[cfg(feature = "reference")]
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

#[cfg(feature = "reference")]
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

#[cfg(feature = "reference")]
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

/// The fewest nodes per axis the flow works on.
pub(crate) const MIN_NODES: usize = 6;

#[cfg(feature = "reference")]
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

#[cfg(feature = "reference")]
/// Slabs per thread in a fused step: a few, so that a thread that finishes
/// early takes over work (this VM's cores run at uneven speeds), and few enough
/// that the seams stay a small part of the planes.
const SLABS_PER_THREAD: usize = 2;

#[cfg(feature = "reference")]
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
        if stopped(params, vmax) || t.is_empty() {
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
