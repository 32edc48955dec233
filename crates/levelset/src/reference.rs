//! A plain dense reference for the sparse reconstruction's distance and flow
//! (issue #36), for tests: feature `reference`, which the crate's own tests
//! turn on.
//!
//! The sparse stages ([`crate::sparse`]) are tested bit for bit against the
//! dense ones, but the two share their kernels — the flow's rate, the
//! redistancing update, the time step, the wavefront's squared distances — so
//! a bug in a kernel cancels out of every sparse-equals-dense test. This module
//! shares none of them. It is written from the paper's equations and the
//! module docs of [`mod@crate::evolve`] and [`crate::distance`], one node at a
//! time, in grid order, every pass over whole grids with boolean masks for the
//! tubes:
//!
//! * [`exact_distance`]: Eq. 7's unsigned distance to the points, exactly, by
//!   brute force over the points of the neighbouring buckets (no wavefront).
//! * [`convection_flow`]: Eq. 6, φ_t = c(φ)·d·|∇φ| (nodes nearer the data than
//!   the arrest distance do not move), with the Godunov Hamiltonian for an
//!   inward-moving front (Osher & Sethian 1988), second-order ENO one-sided
//!   differences (Osher & Shu 1991), the two-stage TVD Runge–Kutta scheme
//!   (Shu & Osher 1988), the cut-off of Eq. 10, redistancing by Eq. 11
//!   (Sussman, Smereka & Osher 1994; Δτ = 0.3h) on the tube N, clamping by
//!   Eq. 12, and the tubes T = {|φ| < γ} (nodes whose ENO stencil fits in the
//!   grid) and N = T grown by one node along each axis or by the 3×3×3 block.
//!
//! The flow works in `f32`, as the kernels do, and evaluates each formula in
//! its textbook order: the level set the pipeline starts from holds many
//! exactly repeated values (distances to the tagged front), so the ENO choice
//! between two second differences of equal magnitude is decided by rounding,
//! and in `f64` such ties break the other way often enough to move nodes by a
//! third of a cell (measured on a DLA deposit). Nothing here is fast: it
//! exists to be obviously right. The optimised stages agree with it to a few
//! units in the last place (the tests bound the difference);
//! `tests/faults.rs` breaks the shared kernels on purpose (feature
//! `fault-injection`) and checks that the comparison with this reference
//! fails while sparse-equals-dense still passes.

use crate::evolve::{Band, EvolveParams, Flow, Neighbourhood, Scheme};
use crate::grid::GridSpec;

/// The exact Euclidean distance from every node of `grid` to the nearest of
/// `points`, for nodes within `cap` of one (`f64::INFINITY` beyond).
///
/// # Panics
/// If `points` is empty.
pub fn exact_distance(points: &[[f64; 3]], grid: &GridSpec, cap: f64) -> Vec<f64> {
    assert!(!points.is_empty(), "no points");
    let h = grid.spacing;
    // Buckets of side `cap` over the grid's box: a node's nearest point
    // within the cap lies in its own bucket or a neighbouring one.
    let side = cap.max(h);
    let extent = |a: usize| (grid.dims[a] - 1) as f64 * h;
    let nb = [0, 1, 2].map(|a| ((extent(a) / side).floor() as usize + 1).max(1));
    let bucket_of = |p: [f64; 3]| -> Option<[usize; 3]> {
        let mut b = [0usize; 3];
        for a in 0..3 {
            let t = ((p[a] - grid.origin[a]) / side).floor();
            // Points up to one bucket outside the box still count.
            if t < -1.0 || t > nb[a] as f64 {
                return None;
            }
            b[a] = (t + 1.0) as usize;
        }
        Some(b)
    };
    let dims_b = nb.map(|n| n + 2);
    let mut buckets: Vec<Vec<usize>> = vec![Vec::new(); dims_b[0] * dims_b[1] * dims_b[2]];
    for (i, &p) in points.iter().enumerate() {
        if let Some(b) = bucket_of(p) {
            buckets[b[0] + dims_b[0] * (b[1] + dims_b[1] * b[2])].push(i);
        }
    }
    let [nx, ny, nz] = grid.dims;
    let mut out = vec![f64::INFINITY; nx * ny * nz];
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let x = grid.position(i, j, k);
                let Some(b) = bucket_of(x) else { continue };
                let mut best = f64::INFINITY;
                for bz in b[2].saturating_sub(1)..=(b[2] + 1).min(dims_b[2] - 1) {
                    for by in b[1].saturating_sub(1)..=(b[1] + 1).min(dims_b[1] - 1) {
                        for bx in b[0].saturating_sub(1)..=(b[0] + 1).min(dims_b[0] - 1) {
                            for &p in &buckets[bx + dims_b[0] * (by + dims_b[1] * bz)] {
                                let q = points[p];
                                let d2 = (x[0] - q[0]).powi(2)
                                    + (x[1] - q[1]).powi(2)
                                    + (x[2] - q[2]).powi(2);
                                best = best.min(d2);
                            }
                        }
                    }
                }
                let d = best.sqrt();
                if d <= cap {
                    out[grid.index(i, j, k)] = d;
                }
            }
        }
    }
    out
}

/// What [`convection_flow`] did.
#[derive(Clone, Debug)]
pub struct ReferenceFlow {
    /// φ at the end, every node.
    pub phi: Vec<f32>,
    /// The time step of each step taken.
    pub dts: Vec<f64>,
    /// The nodes of T at each step.
    pub tube: Vec<usize>,
}

/// The grid's geometry for the stencils.
struct Nodes {
    dims: [usize; 3],
    strides: [usize; 3],
    h: f32,
}

impl Nodes {
    fn coords(&self, u: usize) -> [usize; 3] {
        let [nx, ny, _] = self.dims;
        [u % nx, (u / nx) % ny, u / (nx * ny)]
    }

    /// Whether node `u`'s ENO stencil (two nodes each way) lies in the grid.
    fn fits(&self, u: usize) -> bool {
        let c = self.coords(u);
        (0..3).all(|a| c[a] >= 2 && c[a] + 2 < self.dims[a])
    }

    /// `f` at the node `k` steps along `axis` from `u`.
    fn at(&self, f: &[f32], u: usize, axis: usize, k: isize) -> f32 {
        f[(u as isize + k * self.strides[axis] as isize) as usize]
    }

    /// The backward and forward differences D⁻φ, D⁺φ along `axis` at `u`,
    /// with the second-order ENO corrections when `eno`: D⁻ + m(Δ²ᵢ₋₁, Δ²ᵢ)/2h,
    /// D⁺ − m(Δ²ᵢ, Δ²ᵢ₊₁)/2h for the second differences Δ²ᵢ = φᵢ₊₁ − 2φᵢ + φᵢ₋₁,
    /// m taking the one of smaller magnitude (the first on a tie).
    fn one_sided(&self, f: &[f32], u: usize, axis: usize, eno: bool) -> (f32, f32) {
        let v = |k| self.at(f, u, axis, k);
        let h = self.h;
        let mut backward = (v(0) - v(-1)) / h;
        let mut forward = (v(1) - v(0)) / h;
        if eno {
            let second = |k: isize| v(k + 1) - 2.0 * v(k) + v(k - 1);
            let smaller = |a: f32, b: f32| if a.abs() <= b.abs() { a } else { b };
            backward += smaller(second(-1), second(0)) / (2.0 * h);
            forward -= smaller(second(0), second(1)) / (2.0 * h);
        }
        (backward, forward)
    }
}

/// The cut-off c(φ) of Eq. 10: 1 for |φ| ≤ β, the cubic
/// (|φ| − γ)²(2|φ| + γ − 3β)/(γ − β)³ up to γ, 0 beyond.
fn cutoff(phi: f32, beta: f32, gamma: f32) -> f32 {
    let a = phi.abs();
    if a <= beta {
        1.0
    } else if a <= gamma {
        (a - gamma) * (a - gamma) * (2.0 * a + gamma - 3.0 * beta) / (gamma - beta).powi(3)
    } else {
        0.0
    }
}

/// The settings the reference runs with.
struct Settings {
    beta: f32,
    gamma: f32,
    arrest: f32,
    eno: bool,
}

impl Settings {
    /// The normal speed's magnitude c(φ)·d, 0 nearer the data than the arrest.
    fn speed(&self, phi: f32, d: f32) -> f32 {
        if d < self.arrest {
            0.0
        } else {
            cutoff(phi, self.beta, self.gamma) * d
        }
    }

    /// Eq. 6's rate at `u`: c(φ)·d·|∇φ| with the Godunov |∇φ| of a front
    /// moving inward (F < 0): √Σₐ max(min(D⁻,0)², max(D⁺,0)²).
    fn rate(&self, n: &Nodes, f: &[f32], d: &[f32], u: usize) -> f32 {
        let speed = self.speed(f[u], d[u]);
        if speed == 0.0 {
            return 0.0;
        }
        let grad2: f32 = (0..3)
            .map(|axis| {
                let (backward, forward) = n.one_sided(f, u, axis, self.eno);
                backward.min(0.0).powi(2).max(forward.max(0.0).powi(2))
            })
            .sum();
        speed * grad2.sqrt()
    }
}

/// One first-order Godunov iteration of Eq. 11 at `u`: φ − Δτ·S(φ)(|∇φ| − 1)
/// with S = φ/√(φ² + |∇φ|²h²) and Δτ = 0.3h; |∇φ| upwinded by the sign of φ
/// (outside: max(D⁻,0)² against min(D⁺,0)²; inside the other way round).
fn redistanced(n: &Nodes, f: &[f32], u: usize) -> f32 {
    let phi = f[u];
    let h = n.h;
    let grad2: f32 = (0..3)
        .map(|axis| {
            let backward = (phi - n.at(f, u, axis, -1)) / h;
            let forward = (n.at(f, u, axis, 1) - phi) / h;
            if phi > 0.0 {
                backward.max(0.0).powi(2).max(forward.min(0.0).powi(2))
            } else {
                backward.min(0.0).powi(2).max(forward.max(0.0).powi(2))
            }
        })
        .sum();
    let sign = phi / (phi * phi + grad2 * h * h).sqrt().max(1e-30);
    phi - 0.3 * h * sign * (grad2.sqrt() - 1.0)
}

/// T grown into N: each node of `t` with its neighbours along the axes, or
/// its 3×3×3 block.
fn grow(n: &Nodes, t: &[bool], how: Neighbourhood) -> Vec<bool> {
    let mut out = t.to_vec();
    let reach: Vec<[isize; 3]> = match how {
        Neighbourhood::Axes => (0..3)
            .flat_map(|a| {
                [-1, 1].map(|s| {
                    let mut o = [0; 3];
                    o[a] = s;
                    o
                })
            })
            .collect(),
        Neighbourhood::Cube => (-1..=1)
            .flat_map(|z| (-1..=1).flat_map(move |y| (-1..=1).map(move |x| [x, y, z])))
            .filter(|o| *o != [0, 0, 0])
            .collect(),
    };
    for u in (0..t.len()).filter(|&u| t[u]) {
        let c = n.coords(u);
        for o in &reach {
            let v: Option<Vec<usize>> = (0..3)
                .map(|a| {
                    let x = c[a] as isize + o[a];
                    (x >= 0 && (x as usize) < n.dims[a]).then_some(x as usize)
                })
                .collect();
            if let Some(v) = v {
                out[v[0] + n.dims[0] * (v[1] + n.dims[1] * v[2])] = true;
            }
        }
    }
    out
}

/// Runs the convection flow of Eq. 6 from `phi` with the speed `d` (both per
/// node, x fastest) on `grid`, tube half-width `gamma`, for
/// `params.iterations` steps or until the speed vanishes on T; see the module
/// docs. Grids with fewer than six nodes along an axis are left as they are.
///
/// # Panics
/// For a flow other than [`Flow::Convection`] or a tolerance (the reference
/// runs the paper's flow for a fixed number of steps).
pub fn convection_flow(
    phi: &[f32],
    d: &[f32],
    grid: &GridSpec,
    gamma: f32,
    params: &EvolveParams,
) -> ReferenceFlow {
    assert_eq!(params.flow, Flow::Convection, "the reference runs Eq. 6");
    assert!(params.tolerance.is_none(), "the reference runs fixed steps");
    let n = Nodes {
        dims: grid.dims,
        strides: grid.strides(),
        h: grid.spacing as f32,
    };
    let s = Settings {
        beta: params.beta.clamp(0.0, 0.999 * f64::from(gamma)) as f32,
        gamma,
        arrest: params.arrest as f32,
        eno: params.scheme == Scheme::Eno2,
    };
    let mut phi = phi.to_vec();
    let mut out = ReferenceFlow {
        phi: Vec::new(),
        dts: Vec::new(),
        tube: Vec::new(),
    };
    if grid.dims.iter().any(|&m| m < 6) {
        out.phi = phi;
        return out;
    }
    let full = params.band == Band::Full;
    let new_tube = |phi: &[f32], candidates: &[bool]| -> (Vec<bool>, f32) {
        let t: Vec<bool> = (0..phi.len())
            .map(|u| candidates[u] && n.fits(u) && (full || phi[u].abs() < gamma))
            .collect();
        let vmax = (0..phi.len())
            .filter(|&u| t[u])
            .map(|u| s.speed(phi[u], d[u]))
            .fold(0.0, f32::max);
        (t, vmax)
    };
    let grow_n = |t: &[bool]| {
        if full {
            t.to_vec()
        } else {
            grow(&n, t, params.neighbourhood)
        }
    };
    let (mut t, mut vmax) = new_tube(&phi, &vec![true; phi.len()]);
    let mut tube_n = grow_n(&t);
    for _ in 0..params.iterations {
        let t_nodes: Vec<usize> = (0..phi.len()).filter(|&u| t[u]).collect();
        if vmax <= 0.0 || t_nodes.is_empty() {
            break;
        }
        let dt64 = params.cfl * grid.spacing / f64::from(vmax);
        out.dts.push(dt64);
        let dt = dt64 as f32;
        out.tube.push(t_nodes.len());
        // RK2 (TVD): φ¹ = φⁿ + Δt L(φⁿ); φⁿ⁺¹ = ½φⁿ + ½(φ¹ + Δt L(φ¹)).
        let mut stage = phi.clone();
        for &u in &t_nodes {
            stage[u] = phi[u] + dt * s.rate(&n, &phi, d, u);
        }
        let mut next = phi.clone();
        for &u in &t_nodes {
            next[u] = 0.5 * (phi[u] + (stage[u] + dt * s.rate(&n, &stage, d, u)));
        }
        phi = next;
        // Redistancing on N (Jacobi), clamped to ±γ by the last iteration.
        let n_nodes: Vec<usize> = (0..phi.len()).filter(|&u| tube_n[u]).collect();
        for pass in 0..params.redistance_iterations {
            let before = phi.clone();
            for &u in &n_nodes {
                phi[u] = redistanced(&n, &before, u);
                if pass + 1 == params.redistance_iterations {
                    phi[u] = phi[u].clamp(-gamma, gamma);
                }
            }
        }
        if params.redistance_iterations == 0 {
            for &u in &n_nodes {
                phi[u] = phi[u].clamp(-gamma, gamma);
            }
        }
        (t, vmax) = new_tube(&phi, &tube_n);
        tube_n = grow_n(&t);
    }
    out.phi = phi;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> GridSpec {
        GridSpec {
            origin: [0.0; 3],
            spacing: 1.0,
            dims: [n; 3],
        }
    }

    fn params() -> EvolveParams {
        EvolveParams {
            iterations: 1,
            redistance_iterations: 0,
            arrest: 0.0,
            beta: 3.9,
            ..EvolveParams::paper(1.0)
        }
    }

    /// A tilted plane's signed distance at constant speed D moves by D·Δt a
    /// step, exactly (RK2 is exact for a linear φ).
    #[test]
    fn a_plane_moves_at_its_speed() {
        let g = grid(16);
        let n = [0.6, 0.48, 0.64];
        let phi: Vec<f32> = (0..g.len())
            .map(|u| {
                let c = g.coords(u);
                let x = g.position(c[0], c[1], c[2]);
                ((x[0] * n[0] + x[1] * n[1] + x[2] * n[2] - 12.0) as f32).clamp(-4.0, 4.0)
            })
            .collect();
        let d = vec![2.0f32; g.len()];
        let r = convection_flow(&phi, &d, &g, 4.0, &params());
        let u = g.index(8, 8, 8);
        assert_eq!(r.dts.len(), 1);
        let want = f64::from(phi[u]) + 2.0 * r.dts[0];
        assert!(
            (f64::from(r.phi[u]) - want).abs() < 1e-5,
            "{} vs {want}",
            r.phi[u]
        );
    }

    /// Redistancing keeps a signed distance that is already one, and arrest
    /// stops the flow.
    #[test]
    fn a_distance_function_is_a_fixed_point_and_arrest_stops() {
        let g = grid(14);
        let phi: Vec<f32> = (0..g.len())
            .map(|u| (g.coords(u)[0] as f32 - 6.5).clamp(-3.0, 3.0))
            .collect();
        let mut p = params();
        p.redistance_iterations = 3;
        p.arrest = 10.0;
        let r = convection_flow(&phi, &vec![2.0; g.len()], &g, 3.0, &p);
        assert!(r.dts.is_empty(), "no speed, no step");
        p.arrest = 0.0;
        let r = convection_flow(&phi, &vec![0.5; g.len()], &g, 3.0, &p);
        let u = g.index(7, 7, 7);
        let want = f64::from(phi[u]) + 0.5 * r.dts[0];
        assert!((f64::from(r.phi[u]) - want).abs() < 1e-5);
    }

    #[test]
    fn exact_distance_is_the_brute_force_minimum() {
        let g = grid(10);
        let pts = [[2.2, 3.1, 4.7], [7.5, 1.0, 2.0], [5.0, 8.9, 8.1]];
        let d = exact_distance(&pts, &g, 3.0);
        for (u, &got) in d.iter().enumerate() {
            let c = g.coords(u);
            let x = g.position(c[0], c[1], c[2]);
            let brute = pts
                .iter()
                .map(|p| {
                    ((x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2) + (x[2] - p[2]).powi(2)).sqrt()
                })
                .fold(f64::INFINITY, f64::min);
            let want = if brute <= 3.0 { brute } else { f64::INFINITY };
            assert_eq!(got, want, "{c:?}");
        }
    }
}
