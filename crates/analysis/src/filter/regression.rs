//! The Gaussian regression filter: at every point, the polynomial of degree
//! p (0, 1 or 2) in the offsets fitted by least squares with the Gaussian
//! weighting function of ISO 16610-61 (Eq. 1 there), times a per-point weight
//! (0 at a missing point; the robust filter's biweight, ISO 16610-71). The
//! fitted polynomial's value at the point is the mean surface.
//!
//! With the kernel wholly inside the data and unit weights, the odd moments of
//! the symmetric kernel vanish and degrees 0 and 1 give exactly the convolution
//! of ISO 16610-61 (and its profile form, ISO 16610-21); near the border they
//! differ: degree 0 is the kernel renormalised to the points it covers, and
//! degree 1 also reproduces any plane there (the end-effect correction of
//! ISO 16610-28 by regression; Brinkmann, Bodschwinna & Lemke 2001). Degree 2
//! is the second-order regression filter (ISO 16610-31 for profiles), which
//! reproduces quadratic forms everywhere and is a different filter inside too.
//!
//! The weighted moments `M_ab = Σ w · g · u^a · v^b` and right-hand sides
//! `R_ab = Σ w · z · g · u^a · v^b` (u, v the offsets in units of λc) are
//! separable correlations along x then y (by FFT for long kernels); with unit
//! weights the moments are products of one-dimensional sums.

use rayon::prelude::*;

use super::convolve::{Kernel, LineFilter, Scratch, transpose};

/// ISO 16610-61's α = √(ln 2 / π): the Gaussian weighting function
/// `s(x) = 1/(α λc) · exp(−π (x / (α λc))²)` transmits 50 % of a sinusoid of
/// wavelength λc.
pub const ALPHA: f64 = 0.469_718_639_349_825_9;

/// Where the weighting function is cut, in cut-offs (see [`half_width`]).
const TRUNCATION: f64 = 1.0;

/// The kernel's half width in samples: the weighting function truncated at
/// ±λc, where it has fallen to exp(−π / α²) = 6.5·10⁻⁷ of its peak.
pub(crate) fn half_width(cutoff: f64, spacing: f64) -> usize {
    (TRUNCATION * cutoff / spacing).floor().min(1e7) as usize
}

/// One grid's regression set-up.
pub(crate) struct Regression {
    pub dims: [usize; 2],
    pub spacing: [f64; 2],
    pub cutoff: f64,
    pub order: usize,
    pub wrap: bool,
}

/// The monomials u^a v^b of the fit: degree ≤ p, none along an axis one sample long.
fn monomials(order: usize, [nx, ny]: [usize; 2]) -> Vec<(usize, usize)> {
    let mut m = Vec::new();
    for total in 0..=order {
        for b in 0..=total {
            let a = total - b;
            if (a == 0 || nx > 1) && (b == 0 || ny > 1) {
                m.push((a, b));
            }
        }
    }
    m
}

/// The kernels g(d)·u^a for a = 0..=max along one axis.
fn axis_filters(n: usize, spacing: f64, cutoff: f64, max: usize, wrap: bool) -> Vec<LineFilter> {
    let half = half_width(cutoff, spacing);
    (0..=max)
        .map(|a| {
            let k = Kernel::from_fn(half, |d| {
                let u = d as f64 * spacing / cutoff;
                (-std::f64::consts::PI * (u / ALPHA).powi(2)).exp() * u.powi(a as i32)
            });
            LineFilter::new(n, k, wrap)
        })
        .collect()
}

/// What every line of one filter shares: the fit's monomials, the kernels
/// along each axis, the moment pairs the normal matrix reads, and the sums of
/// the kernels over each line (the moments of unit weights).
struct Plan {
    mono: Vec<(usize, usize)>,
    /// The highest power of u among the monomials.
    ax: usize,
    fx: Vec<LineFilter>,
    fy: Vec<LineFilter>,
    /// The moment pairs (a, b) (sums of two monomials' exponents) …
    pairs: Vec<(usize, usize)>,
    /// … and where pair (a, b) sits: `slot[a * nb + b]`.
    slot: Vec<usize>,
    nb: usize,
    /// Σ_d g(d) u^a over each point of a line along x, and along y.
    mx: Vec<Vec<f64>>,
    my: Vec<Vec<f64>>,
    /// The weight of a point whose kernel sees every sample with weight 1.
    full: f64,
}

impl Regression {
    fn plan(&self) -> Plan {
        let [nx, ny] = self.dims;
        let mono = monomials(self.order, self.dims);
        let ax = mono.iter().map(|m| m.0).max().unwrap_or(0);
        let ay = mono.iter().map(|m| m.1).max().unwrap_or(0);
        let fx = axis_filters(nx, self.spacing[0], self.cutoff, 2 * ax, self.wrap);
        let fy = axis_filters(ny, self.spacing[1], self.cutoff, 2 * ay, self.wrap);
        let nb = 2 * ay + 1;
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        let mut slot = vec![usize::MAX; (2 * ax + 1) * nb];
        for p in &mono {
            for q in &mono {
                let (a, b) = (p.0 + q.0, p.1 + q.1);
                if slot[a * nb + b] == usize::MAX {
                    slot[a * nb + b] = pairs.len();
                    pairs.push((a, b));
                }
            }
        }
        let (mx, my) = (line_sums(&fx, nx), line_sums(&fy, ny));
        let peak = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let full = peak(&mx[0]) * peak(&my[0]);
        Plan {
            mono,
            ax,
            fx,
            fy,
            pairs,
            slot,
            nb,
            mx,
            my,
            full,
        }
    }

    /// The mean surface of the row-major heights `z` with per-point weights
    /// `w` (`None`: every point weighs 1). Points with weight 0 may hold
    /// anything finite. A point with no weight within reach comes out NaN.
    pub fn mean_surface(&self, z: &[f64], w: Option<&[f64]>) -> Vec<f64> {
        let [nx, ny] = self.dims;
        let plan = self.plan();
        let along_x = |data: &[f64], max: usize| -> Vec<Vec<f64>> {
            (0..=max)
                .map(|a| transpose(&plan.fx[a].rows(data), nx, ny))
                .collect()
        };
        let zw: Vec<f64> = match w {
            Some(w) => z.par_iter().zip(w).map(|(z, w)| z * w).collect(),
            None => z.to_vec(),
        };
        let rhs_t = along_x(&zw, plan.ax);
        drop(zw);
        let weights_t = w.map(|w| along_x(w, 2 * plan.ax));
        let out_t = plan.along_y(&rhs_t, weights_t.as_deref(), ny);
        transpose(&out_t, ny, nx)
    }
}

/// Σ_d k(d) over each point of a line (the correlation of ones).
fn line_sums(f: &[LineFilter], n: usize) -> Vec<Vec<f64>> {
    let ones = vec![1.0; n];
    f.iter()
        .map(|f| {
            let mut out = vec![0.0; n];
            f.apply(&ones, &mut out, &mut Scratch::default());
            out
        })
        .collect()
}

impl Plan {
    /// The y pass and the fits: for each column of the grid (a row of the
    /// transposed `rhs_t`, `weights_t`), the right-hand sides R_ab and, with
    /// weights, the moments M_ab along it, then each point's β₀.
    fn along_y(&self, rhs_t: &[Vec<f64>], weights_t: Option<&[Vec<f64>]>, ny: usize) -> Vec<f64> {
        let columns = rhs_t[0].len() / ny;
        let mut out_t = vec![0.0; columns * ny];
        out_t.par_chunks_mut(ny).enumerate().for_each_init(
            || (Scratch::default(), Vec::new(), Vec::new()),
            |(s, r, m), (i, out)| {
                let row = i * ny..(i + 1) * ny;
                r.resize(self.mono.len() * ny, 0.0);
                for (p, &(a, b)) in self.mono.iter().enumerate() {
                    self.fy[b].apply(&rhs_t[a][row.clone()], &mut r[p * ny..(p + 1) * ny], s);
                }
                if let Some(wt) = weights_t {
                    m.resize(self.pairs.len() * ny, 0.0);
                    for (k, &(a, b)) in self.pairs.iter().enumerate() {
                        self.fy[b].apply(&wt[a][row.clone()], &mut m[k * ny..(k + 1) * ny], s);
                    }
                }
                for (j, o) in out.iter_mut().enumerate() {
                    let moment = |a: usize, b: usize| match weights_t {
                        Some(_) => m[self.slot[a * self.nb + b] * ny + j],
                        None => self.mx[a][i] * self.my[b][j],
                    };
                    *o = solve_point(&self.mono, &moment, |p| r[p * ny + j], self.full);
                }
            },
        );
        out_t
    }
}

/// β₀ of the weighted least-squares fit at one point; a fit that the data
/// around the point cannot determine falls back to degree 0, and a point
/// with no weight within reach gives NaN.
fn solve_point(
    mono: &[(usize, usize)],
    moment: &dyn Fn(usize, usize) -> f64,
    rhs: impl Fn(usize) -> f64,
    full: f64,
) -> f64 {
    let m00 = moment(0, 0);
    // NaN moments (no weight) fail the test too
    if m00.is_nan() || m00 <= 1e-9 * full {
        return f64::NAN;
    }
    let n = mono.len();
    if n > 1 {
        let mut a = [[0.0; 6]; 6];
        let mut b = [0.0; 6];
        for p in 0..n {
            for q in 0..n {
                a[p][q] = moment(mono[p].0 + mono[q].0, mono[p].1 + mono[q].1);
            }
            b[p] = rhs(p);
        }
        if let Some(beta0) = eliminate(&mut a, &mut b, n) {
            return beta0;
        }
    }
    rhs(0) / m00
}

/// Gaussian elimination with partial pivoting on the leading n × n block
/// (n ≤ 6: a fixed-size stack solve, no allocation per point); the first
/// unknown, or `None` when a pivot is negligible (an ill-posed local fit).
fn eliminate(a: &mut [[f64; 6]; 6], b: &mut [f64; 6], n: usize) -> Option<f64> {
    let scale = (0..n).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        let pivot = a[p][c].abs();
        if pivot.is_nan() || pivot <= 1e-12 * scale {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot_row = a[c];
        for r in c + 1..n {
            let f = a[r][c] / pivot_row[c];
            for (x, p) in a[r][c..n].iter_mut().zip(&pivot_row[c..n]) {
                *x -= f * p;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 6];
    for c in (0..n).rev() {
        let s: f64 = (c + 1..n).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    Some(x[0])
}
