//! Model-based fits of the Hurst exponent: what a statistic of a self-affine
//! surface *should* be on the data's own grid, fitted by generalised least
//! squares.
//!
//! Real-space and profile estimators of H — the structure function, the
//! rms height in boxes, the 1-D PSD of profiles, the triangulated area — are
//! power laws only for an infinite, continuous surface. On a grid of n samples
//! the spectrum ends at the Nyquist wavenumber and starts at 2π/L, and a
//! straight line through log–log points is biased by up to 0.15 in H (too high
//! for small H, too low for large H; measured on SurfaceTopography's
//! `fourier_synthesis` surfaces of 256² to 2048²).
//!
//! Every such statistic is a linear functional of the spectrum: for periodic
//! data, M(s) = Σ_q K_s(q) C(q) over the FFT modes, with a kernel K_s that
//! depends only on the statistic and the scale s (for the structure function at
//! lag τ along x, K = 1 − cos(q_x τ)). The model is the self-affine PSD of
//! Jacobs, Junge & Pastewka (Surf. Topogr.: Metrol. Prop. 5, 013001, 2017,
//! Eq. 4), C(q) = C₀ |q|^−(d+2H) for 2π/L ≤ |q| ≤ π/Δ (d = 2 for areas, 1 for
//! profiles), on the modes of the data's grid. The expectation E_H(s) follows
//! exactly, and so does the covariance of the statistic across scales,
//! Cov(s, s′) = Σ K_s K_s′ C² (the mode powers are independent with variance
//! ∝ C²). H is then the generalised least-squares fit of ln M(s) = ln E_H(s) +
//! c, with the covariance of ln M at the current H as the weight (three
//! rounds) — the log-periodogram regression of Geweke & Porter-Hudak (1983)
//! generalised to any linear statistic. Windowed non-periodic data follow the
//! same model (their kernels include the window).
//!
//! To keep this fast, modes are gathered into thin rings of ln |q| (width
//! 0.002, so C varies by under 0.3 % inside one); the covariance uses rings
//! twenty-five times wider. Sums are made over fixed blocks of rows and added in
//! block order, so the result does not depend on the thread count.

use std::sync::{Arc, Mutex, PoisonError};

use rayon::prelude::*;
use serde::Serialize;

/// Width of a fine ring in ln |q|.
const FINE: f64 = 0.002;
/// Width of a covariance ring in ln |q|.
const COARSE: f64 = 0.05;
/// The variance of a ring's sum counts each mode twice: a real field's modes
/// at q and −q are one random variable.
const PAIRED: f64 = 2.0;
/// Parallel tasks per sum, each over a fixed block of rows of modes (fixed:
/// the sums do not depend on the thread count). Few, because every task
/// holds its own covariance sums (scales² × rings, megabytes).
const TASKS: usize = 8;

/// A statistic at several scales, as a kernel over the FFT modes.
pub trait Kernel: Sync {
    /// Number of scales.
    fn scales(&self) -> usize;
    /// K_s for every scale s at mode (kx, ky), FFT indices in 0..nx, 0..ny.
    fn eval(&self, kx: usize, ky: usize, out: &mut [f64]);
    /// The non-zero K_s at mode (kx, ky) as (s, K_s) in increasing s, pushed
    /// onto `nonzero` (empty on entry), for a kernel that is zero at most
    /// scales of most modes; `false` where the kernel does not list them and
    /// [`Kernel::eval`] is to be used.
    fn eval_sparse(&self, _kx: usize, _ky: usize, _nonzero: &mut Vec<(usize, f64)>) -> bool {
        false
    }
    /// Whether K is the same at (±kx, ±ky): the sums then run over a quarter
    /// of the modes, each counted with its mirror images.
    fn mirror_symmetric(&self) -> bool {
        false
    }
}

/// The grid a model lives on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeGrid {
    /// Samples per axis (`ny` = 1 for a profile).
    pub n: [usize; 2],
    /// Spacing per axis.
    pub spacing: [f64; 2],
}

impl ModeGrid {
    /// The modes of `h`'s grid.
    pub fn of(h: &asperity_core::HeightField) -> Self {
        Self {
            n: h.dims(),
            spacing: h.spacing(),
        }
    }

    /// Spatial dimension d of the spectrum: 1 for a profile, 2 for an area.
    pub fn dim(&self) -> usize {
        if self.n[1] == 1 { 1 } else { 2 }
    }

    /// |q| of mode (kx, ky), in rad per length unit.
    pub fn q(&self, kx: usize, ky: usize) -> f64 {
        let signed = |k: usize, n: usize| {
            if k <= n / 2 {
                k as f64
            } else {
                k as f64 - n as f64
            }
        };
        let qx =
            std::f64::consts::TAU * signed(kx, self.n[0]) / (self.n[0] as f64 * self.spacing[0]);
        let qy = if self.n[1] == 1 {
            0.0
        } else {
            std::f64::consts::TAU * signed(ky, self.n[1]) / (self.n[1] as f64 * self.spacing[1])
        };
        (qx * qx + qy * qy).sqrt()
    }

    /// The lowest and highest |q| of the model: 2π / the longer side, π / the
    /// coarser spacing (modes beyond, in the corners of a square grid, are
    /// outside the isotropic band and left out).
    pub fn band(&self) -> [f64; 2] {
        let d = self.dim();
        let long = (0..d)
            .map(|a| self.n[a] as f64 * self.spacing[a])
            .fold(0.0, f64::max);
        let coarse = (0..d).map(|a| self.spacing[a]).fold(0.0, f64::max);
        [std::f64::consts::TAU / long, std::f64::consts::PI / coarse]
    }
}

/// ln |q| and the fine and coarse rings of the modes 0 ≤ k_x ≤ nx/2,
/// 0 ≤ k_y ≤ ny/2 of a grid — every other mode is a mirror image with the
/// same |q| — computed once a grid and shared by every kernel summed on it
/// (the logarithm is most of the cost of a sum).
struct ModeTable {
    grid: ModeGrid,
    /// Stored modes per axis: nx/2 + 1, ny/2 + 1.
    half: [usize; 2],
    /// Per stored mode, k_x fastest: ln |q|, and the fine and coarse ring
    /// (`None` outside the model's band).
    modes: Vec<(f64, Option<(u32, u32)>)>,
}

impl ModeTable {
    fn new(grid: &ModeGrid, l: &Layout) -> Self {
        let half = [grid.n[0] / 2 + 1, grid.n[1] / 2 + 1];
        let modes = (0..half[0] * half[1])
            .into_par_iter()
            .map(|k| {
                let q = grid.q(k % half[0], k / half[0]);
                if q <= 0.0 || q > l.q_hi * (1.0 + 1e-12) {
                    return (0.0, None);
                }
                let lq = q.ln();
                let x = (lq - l.ln_q_lo).max(0.0);
                let fine = ((x / FINE) as usize).min(l.fine - 1) as u32;
                let coarse = ((x / COARSE) as usize).min(l.coarse - 1) as u32;
                (lq, Some((fine, coarse)))
            })
            .collect();
        Self {
            grid: *grid,
            half,
            modes,
        }
    }

    /// The table of `grid`: the last one made if it was for this grid (one
    /// table, tens of megabytes for a 4096² grid, stays held between calls).
    fn of(grid: &ModeGrid, l: &Layout) -> Arc<Self> {
        static LAST: Mutex<Option<Arc<ModeTable>>> = Mutex::new(None);
        let mut last = LAST.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(t) = last.as_ref().filter(|t| t.grid == *grid) {
            return Arc::clone(t);
        }
        let t = Arc::new(Self::new(grid, l));
        *last = Some(Arc::clone(&t));
        t
    }

    /// ln |q| and the rings of mode (kx, ky), any FFT indices.
    fn get(&self, kx: usize, ky: usize) -> (f64, Option<(u32, u32)>) {
        let [nx, ny] = self.grid.n;
        let (fx, fy) = (kx.min(nx - kx), ky.min(ny - ky));
        self.modes[fx + self.half[0] * fy]
    }
}

/// A kernel summed over rings of |q| (see the module docs).
#[derive(Clone, Debug)]
pub struct Compressed {
    scales: usize,
    dim: usize,
    /// Mean ln |q| of each fine ring.
    ln_q: Vec<f64>,
    /// Σ K_s over the modes of fine ring r, at `s * rings + r`.
    k: Vec<f64>,
    /// Mean ln |q| of each coarse ring.
    ln_qc: Vec<f64>,
    /// Σ K_s K_t over coarse ring r, at `(s * scales + t) * coarse + r`.
    kk: Vec<f64>,
}

/// Partial sums of one block of rows, ring-major (`k` at `r * scales + s`,
/// `kk` at `(r * scales + s) * scales + t`) so that one mode's products are
/// contiguous; [`Compressed`] stores them scale-major.
struct Partial {
    count: Vec<f64>,
    sum_ln: Vec<f64>,
    k: Vec<f64>,
    count_c: Vec<f64>,
    sum_ln_c: Vec<f64>,
    kk: Vec<f64>,
}

/// How the modes are visited: the rings, and whether mirror images are folded.
struct Layout {
    scales: usize,
    fine: usize,
    coarse: usize,
    ln_q_lo: f64,
    q_hi: f64,
    folded: bool,
    /// Rows and columns of modes visited.
    rows: usize,
    cols: usize,
}

impl Layout {
    fn new(kernel: &dyn Kernel, grid: &ModeGrid) -> Self {
        let [q_lo, q_hi] = grid.band();
        let span = (q_hi / q_lo).ln().max(0.0);
        let [nx, ny] = grid.n;
        let folded = kernel.mirror_symmetric();
        // With mirror symmetry only kx, ky ≤ n/2 are visited; a mode stands for
        // its images at −kx and −ky (one image on the axis and at Nyquist).
        let (rows, cols) = if folded {
            (ny / 2 + 1, nx / 2 + 1)
        } else {
            (ny, nx)
        };
        Self {
            scales: kernel.scales(),
            fine: (span / FINE) as usize + 1,
            coarse: (span / COARSE) as usize + 1,
            ln_q_lo: q_lo.ln(),
            q_hi,
            folded,
            rows,
            cols,
        }
    }

    /// How many modes index `k` of an axis of `n` stands for.
    fn images(&self, k: usize, n: usize) -> f64 {
        if !self.folded || n == 1 || k == 0 || 2 * k == n {
            1.0
        } else {
            2.0
        }
    }
}

impl Partial {
    fn zeros(l: &Layout) -> Self {
        let s = l.scales;
        Self {
            count: vec![0.0; l.fine],
            sum_ln: vec![0.0; l.fine],
            k: vec![0.0; s * l.fine],
            count_c: vec![0.0; l.coarse],
            sum_ln_c: vec![0.0; l.coarse],
            kk: vec![0.0; s * s * l.coarse],
        }
    }

    fn add(&mut self, p: &Partial) {
        let add = |a: &mut [f64], b: &[f64]| a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        add(&mut self.count, &p.count);
        add(&mut self.sum_ln, &p.sum_ln);
        add(&mut self.k, &p.k);
        add(&mut self.count_c, &p.count_c);
        add(&mut self.sum_ln_c, &p.sum_ln_c);
        add(&mut self.kk, &p.kk);
    }

    /// The sums over rows `ky_range` of the visited modes.
    fn of_rows(
        kernel: &dyn Kernel,
        table: &ModeTable,
        l: &Layout,
        ky_range: std::ops::Range<usize>,
    ) -> Self {
        let s = l.scales;
        let [nx, ny] = table.grid.n;
        let mut p = Self::zeros(l);
        let mut ks = vec![0.0; s];
        let mut nonzero: Vec<(usize, f64)> = Vec::with_capacity(s);
        for ky in ky_range {
            let wy = l.images(ky, ny);
            for kx in 0..l.cols {
                let (lq, Some((rf, rc))) = table.get(kx, ky) else {
                    continue;
                };
                let (rf, rc) = (rf as usize, rc as usize);
                let w = wy * l.images(kx, nx);
                nonzero.clear();
                let listed = kernel.eval_sparse(kx, ky, &mut nonzero);
                if !listed {
                    kernel.eval(kx, ky, &mut ks);
                    nonzero.extend(ks.iter().copied().enumerate().filter(|(_, k)| *k != 0.0));
                }
                p.count[rf] += w;
                p.sum_ln[rf] += w * lq;
                p.count_c[rc] += w;
                p.sum_ln_c[rc] += w * lq;
                // Sparse kernels (a profile PSD touches a few modes per scale)
                // cost only their non-zero products.
                let (k, kk) = (&mut p.k[rf * s..], &mut p.kk[rc * s * s..]);
                if !listed && nonzero.len() == s {
                    // Dense: contiguous rows the compiler vectorises.
                    for a in 0..s {
                        let wa = w * ks[a];
                        k[a] += wa;
                        let row = &mut kk[a * s..(a + 1) * s];
                        for b in a..s {
                            row[b] += wa * ks[b];
                        }
                    }
                } else {
                    for (i, &(a, ka)) in nonzero.iter().enumerate() {
                        k[a] += w * ka;
                        for &(b, kb) in &nonzero[i..] {
                            kk[a * s + b] += w * ka * kb;
                        }
                    }
                }
            }
        }
        p
    }
}

impl Compressed {
    /// Sums `kernel` over the modes of `grid` (see the module docs).
    pub fn new(kernel: &dyn Kernel, grid: &ModeGrid) -> Self {
        let l = Layout::new(kernel, grid);
        let table = ModeTable::of(grid, &l);
        let (s, coarse) = (l.scales, l.coarse);
        let rows_per_task = l.rows.div_ceil(TASKS).max(1);
        let blocks: Vec<usize> = (0..l.rows.div_ceil(rows_per_task)).collect();
        let partials: Vec<Partial> = blocks
            .par_iter()
            .map(|&b| {
                let rows = b * rows_per_task..((b + 1) * rows_per_task).min(l.rows);
                Partial::of_rows(kernel, &table, &l, rows)
            })
            .collect();
        // Added in block order: the same sums at any thread count.
        let mut total = Partial::zeros(&l);
        for p in &partials {
            total.add(p);
        }
        // Scale-major, and the symmetric covariance's lower triangle filled.
        let fine = l.fine;
        let mut k = vec![0.0; s * fine];
        for r in 0..fine {
            for a in 0..s {
                k[a * fine + r] = total.k[r * s + a];
            }
        }
        let mut kk = vec![0.0; s * s * coarse];
        for r in 0..coarse {
            for a in 0..s {
                for b in 0..s {
                    let (lo, hi) = (a.min(b), a.max(b));
                    kk[(a * s + b) * coarse + r] = total.kk[(r * s + lo) * s + hi];
                }
            }
        }
        let mean = |sum: &[f64], count: &[f64]| -> Vec<f64> {
            sum.iter()
                .zip(count)
                .map(|(s, c)| if *c > 0.0 { s / c } else { 0.0 })
                .collect()
        };
        Self {
            scales: s,
            dim: grid.dim(),
            ln_q: mean(&total.sum_ln, &total.count),
            k,
            ln_qc: mean(&total.sum_ln_c, &total.count_c),
            kk,
        }
    }

    /// E_H(s) up to the factor C₀, for every scale.
    pub fn expected(&self, hurst: f64) -> Vec<f64> {
        let a = -(self.dim as f64 + 2.0 * hurst);
        let p: Vec<f64> = self.ln_q.iter().map(|l| (a * l).exp()).collect();
        let r = self.ln_q.len();
        (0..self.scales)
            .map(|s| {
                self.k[s * r..(s + 1) * r]
                    .iter()
                    .zip(&p)
                    .map(|(k, p)| k * p)
                    .sum()
            })
            .collect()
    }

    /// E[ln M(s)] up to ln C₀: ln E_H(s) less half the relative variance of
    /// M(s) (the second-order correction of the logarithm of a random
    /// variable, which matters where a statistic rests on few modes: large
    /// boxes, long lags). A real Gaussian field's modes pair up (ĥ(−q) is the
    /// conjugate of ĥ(q)), so each ring's Σ K² C² counts twice.
    pub fn expected_log(&self, hurst: f64) -> Vec<f64> {
        let e = self.expected(hurst);
        let a = -2.0 * (self.dim as f64 + 2.0 * hurst);
        let rc = self.ln_qc.len();
        let p: Vec<f64> = self.ln_qc.iter().map(|l| (a * l).exp()).collect();
        let s = self.scales;
        (0..s)
            .map(|i| {
                let v: f64 = self.kk[(i * s + i) * rc..(i * s + i + 1) * rc]
                    .iter()
                    .zip(&p)
                    .map(|(k, p)| k * p)
                    .sum();
                if e[i] > 0.0 {
                    e[i].ln() - PAIRED * v / (e[i] * e[i]) / 2.0
                } else {
                    f64::NEG_INFINITY
                }
            })
            .collect()
    }

    /// d ln E_H(s) / dH.
    fn expected_slope(&self, hurst: f64, e: &[f64]) -> Vec<f64> {
        let a = -(self.dim as f64 + 2.0 * hurst);
        let r = self.ln_q.len();
        (0..self.scales)
            .map(|s| {
                let d: f64 = self.k[s * r..(s + 1) * r]
                    .iter()
                    .zip(&self.ln_q)
                    .map(|(k, l)| k * (a * l).exp() * (-2.0 * l))
                    .sum();
                d / e[s]
            })
            .collect()
    }

    /// The covariance of ln M at `hurst`, restricted to `keep`.
    fn log_covariance(&self, hurst: f64, e: &[f64], keep: &[usize]) -> Vec<f64> {
        let a = -2.0 * (self.dim as f64 + 2.0 * hurst);
        let rc = self.ln_qc.len();
        let p: Vec<f64> = self.ln_qc.iter().map(|l| (a * l).exp()).collect();
        let s = self.scales;
        let m = keep.len();
        let mut cov = vec![0.0; m * m];
        for (i, &si) in keep.iter().enumerate() {
            for (j, &sj) in keep.iter().enumerate() {
                let c: f64 = self.kk[(si * s + sj) * rc..(si * s + sj + 1) * rc]
                    .iter()
                    .zip(&p)
                    .map(|(k, p)| k * p)
                    .sum();
                cov[i * m + j] = c / (e[si] * e[sj]);
            }
        }
        cov
    }
}

/// H from a model fit, with its quality.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ModelFit {
    /// The Hurst exponent.
    pub hurst: f64,
    /// Its standard error: the larger of what the residuals and what the
    /// model's covariance say.
    pub stderr: f64,
    /// Weighted coefficient of determination of ln M against ln E_H.
    pub r2: f64,
    /// Scales used.
    pub points: usize,
    /// ln C₀ (the model's prefactor, in the statistic's units).
    pub ln_prefactor: f64,
    /// Whether H ended on the edge of [0, 1.5] (no self-affine fit).
    pub at_bound: bool,
}

/// The coefficient of determination from residual and total sums of squares.
pub(crate) fn r_squared(ssr: f64, sst: f64) -> f64 {
    if sst > 0.0 {
        (1.0 - ssr / sst).max(0.0)
    } else {
        1.0
    }
}

/// Whether a fitted H sits on the edge of the search range [0, 1.5].
pub(crate) fn at_bound(hurst: f64) -> bool {
    !(1e-3..=1.5 - 1e-3).contains(&hurst)
}

/// Cholesky factor of a symmetric positive definite `m × m` matrix (lower, row
/// major); `None` when it is not positive definite.
fn cholesky(a: &[f64], m: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; m * m];
    for i in 0..m {
        for j in 0..=i {
            let s: f64 = a[i * m + j] - (0..j).map(|k| l[i * m + k] * l[j * m + k]).sum::<f64>();
            if i == j {
                if s <= 0.0 || !s.is_finite() {
                    return None;
                }
                l[i * m + i] = s.sqrt();
            } else {
                l[i * m + j] = s / l[j * m + j];
            }
        }
    }
    Some(l)
}

/// Whitens `v` by the Cholesky factor: solves L y = v.
fn whiten(l: &[f64], m: usize, v: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; m];
    for i in 0..m {
        let s: f64 = v[i] - (0..i).map(|k| l[i * m + k] * y[k]).sum::<f64>();
        y[i] = s / l[i * m + i];
    }
    y
}

/// Weighted least squares of `r` on a constant in whitened coordinates:
/// the residual sum of squares and the fitted constant.
fn profile_intercept(r: &[f64], one: &[f64]) -> (f64, f64) {
    let c =
        r.iter().zip(one).map(|(a, b)| a * b).sum::<f64>() / one.iter().map(|b| b * b).sum::<f64>();
    let ssr = r.iter().zip(one).map(|(a, b)| (a - c * b).powi(2)).sum();
    (ssr, c)
}

/// Minimises `f` on [lo, hi]: a scan of `steps` points, then golden-section
/// search around the best.
pub(crate) fn minimise(f: impl Fn(f64) -> f64, lo: f64, hi: f64, steps: usize) -> f64 {
    let h = (hi - lo) / steps as f64;
    let best = (0..=steps)
        .map(|k| lo + k as f64 * h)
        .map(|x| (x, f(x)))
        .fold(
            (lo, f64::INFINITY),
            |b, (x, v)| if v < b.1 { (x, v) } else { b },
        );
    let (mut a, mut b) = ((best.0 - h).max(lo), (best.0 + h).min(hi));
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    while b - a > 1e-7 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let x = 0.5 * (a + b);
    if f(x) <= best.1 { x } else { best.0 }
}

/// Fits H to `measured` (one value per scale of the kernel behind `model`),
/// using the scales where `use_scale` is true and the value is positive.
/// `None` with fewer than three such scales.
pub fn fit(measured: &[f64], model: &Compressed, use_scale: &[bool]) -> Option<ModelFit> {
    let e0 = model.expected(0.5);
    let keep: Vec<usize> = (0..measured.len())
        .filter(|&s| use_scale[s] && measured[s] > 0.0 && measured[s].is_finite() && e0[s] > 0.0)
        .collect();
    let m = keep.len();
    if m < 3 {
        return None;
    }
    let ln_m: Vec<f64> = keep.iter().map(|&s| measured[s].ln()).collect();
    // Start with ordinary least squares (identity weight), then three rounds of
    // the model covariance at the current H.
    let mut l: Vec<f64> = (0..m * m)
        .map(|k| if k % (m + 1) == 0 { 1.0 } else { 0.0 })
        .collect();
    let mut hurst = 0.5;
    let misfit = |l: &[f64], h: f64| -> (f64, f64) {
        let e = model.expected_log(h);
        let r: Vec<f64> = keep.iter().zip(&ln_m).map(|(&s, lm)| lm - e[s]).collect();
        profile_intercept(&whiten(l, m, &r), &whiten(l, m, &vec![1.0; m]))
    };
    for _round in 0..4 {
        hurst = minimise(|h| misfit(&l, h).0, 0.0, 1.5, 30);
        let e = model.expected(hurst);
        let mut cov = model.log_covariance(hurst, &e, &keep);
        let mean_diag = (0..m).map(|i| cov[i * m + i]).sum::<f64>() / m as f64;
        for i in 0..m {
            cov[i * m + i] += 1e-6 * mean_diag;
        }
        match cholesky(&cov, m) {
            Some(c) => l = c,
            None => break,
        }
    }
    let (ssr, c) = misfit(&l, hurst);
    let e = model.expected(hurst);
    let slope = model.expected_slope(hurst, &e);
    let one = whiten(&l, m, &vec![1.0; m]);
    let j = whiten(&l, m, &keep.iter().map(|&s| slope[s]).collect::<Vec<_>>());
    let (jj, _) = profile_intercept(&j, &one);
    let y = whiten(&l, m, &ln_m);
    let (sst, _) = profile_intercept(&y, &one);
    let sigma2 = if m > 2 { ssr / (m - 2) as f64 } else { ssr };
    // The larger of the error the residuals show and the one the model
    // predicts (its covariance, with the modes paired): with a handful of
    // scales the residuals alone can look deceptively small.
    let stderr = (sigma2.max(PAIRED) / jj.max(1e-300)).sqrt();
    Some(ModelFit {
        hurst,
        stderr,
        r2: r_squared(ssr, sst),
        points: m,
        ln_prefactor: c,
        at_bound: at_bound(hurst),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K = 1 at mode index kx = s + 1 (any ky): the 1-D PSD of periodic profiles.
    struct Rows(usize);
    impl Kernel for Rows {
        fn scales(&self) -> usize {
            self.0
        }
        fn eval(&self, kx: usize, _ky: usize, out: &mut [f64]) {
            out.iter_mut()
                .enumerate()
                .for_each(|(s, o)| *o = f64::from(u8::from(kx == s + 1)));
        }
    }

    #[test]
    fn an_exact_expectation_is_fitted_exactly() {
        let grid = ModeGrid {
            n: [64, 64],
            spacing: [1.0, 1.0],
        };
        let k = Rows(20);
        let c = Compressed::new(&k, &grid);
        for h in [0.2, 0.7, 1.1] {
            // The fit matches ln M to E[ln M] (the Jensen-corrected log mean).
            let m: Vec<f64> = c.expected_log(h).iter().map(|e| 3.5 * e.exp()).collect();
            let f = fit(&m, &c, &[true; 20]).unwrap();
            assert!((f.hurst - h).abs() < 1e-5, "{h}: {f:?}");
            assert!((f.ln_prefactor - 3.5f64.ln()).abs() < 1e-4);
            assert!(f.r2 > 0.999_999);
        }
        assert!(fit(&[1.0; 20], &c, &[false; 20]).is_none());
    }

    #[test]
    fn rings_reproduce_the_direct_sum() {
        let grid = ModeGrid {
            n: [32, 16],
            spacing: [0.5, 1.0],
        };
        let c = Compressed::new(&Rows(5), &grid);
        let [_, q_hi] = grid.band();
        for (s, e) in c.expected(0.8).iter().enumerate() {
            let direct: f64 = (0..16)
                .map(|ky| grid.q(s + 1, ky))
                .filter(|q| *q <= q_hi)
                .map(|q| q.powf(-2.0 - 1.6))
                .sum();
            assert!((e / direct - 1.0).abs() < 4e-3, "{s}: {e} vs {direct}");
        }
    }
}
