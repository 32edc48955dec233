//! Scale-dependent statistics of a height field, each measured on the data and
//! expressed as a kernel over its FFT modes for the model fits of
//! [`crate::model`]:
//!
//! - [`StructureFunction`]: S(τ) = ⟨(z(x + τ) − z(x))²⟩, along x and along y
//!   (summed), the height–height correlation function (HHCF). For periodic data
//!   the pairs wrap around; otherwise only pairs inside the field count. Its
//!   kernel is 2(1 − cos q_x τ) + 2(1 − cos q_y τ). The scale-dependent rms slope
//!   √(S/2)/τ and curvature of SurfaceTopography (Jacobs, Junge & Pastewka 2017;
//!   Sanner et al., Appl. Surf. Sci. Adv. 7, 100190, 2022) follow from it.
//! - [`BoxVariance`]: the variance of the heights in square boxes of side ℓ,
//!   after removing each box's mean (the partitioning or variance method) or
//!   its least-squares plane (SurfaceTopography's variable bandwidth,
//!   `variable_bandwidth_from_area`), averaged over the boxes that fit. A plane
//!   wave's residual in a box is 1 − |D₀|² (− |D₁|² terms with a plane), with
//!   D₀ and D₁ its projections on the constant and on the centred coordinate.
//! - [`ProfileSpectrum`]: the mean 1-D periodogram of the rows (along x) or the
//!   columns (along y), windowed for non-periodic data. Its kernel at
//!   wavenumber index k is |Ŵ(k − k_x)|², the window's spectrum (a delta
//!   without a window).
//!
//! Kernels are defined up to one constant factor shared by every scale (the
//! model's prefactor C₀ absorbs it).

use rayon::prelude::*;
use std::f64::consts::TAU;
use std::sync::OnceLock;

use asperity_core::HeightField;
use realfft::RealFftPlanner;
use rustfft::{FftPlanner, num_complex::Complex};

use crate::lines::fold_lines;
use crate::model::Kernel;
use crate::window::Window;

/// Lags in samples: about `per_octave` per doubling from `lo` to `hi`, distinct.
pub fn log_scales(lo: usize, hi: usize, per_octave: usize) -> Vec<usize> {
    if hi < lo || lo == 0 {
        return Vec::new();
    }
    let steps = ((hi as f64 / lo as f64).log2() * per_octave as f64).ceil() as usize;
    let mut v: Vec<usize> = (0..=steps)
        .map(|k| {
            (lo as f64 * (hi as f64 / lo as f64).powf(k as f64 / steps.max(1) as f64)).round()
                as usize
        })
        .collect();
    v.dedup();
    v
}

/// Sample counts along y with the same physical length as `along_x` along x,
/// at least `min`.
fn same_length_along_y(h: &HeightField, along_x: &[usize], min: usize) -> Vec<usize> {
    let [dx, dy] = h.spacing();
    along_x
        .iter()
        .map(|&k| ((k as f64 * dx / dy).round() as usize).max(min))
        .collect()
}

/// The structure function at lags τ (in x samples; along y the lag with the
/// same physical length).
#[derive(Clone, Debug)]
pub struct StructureFunction {
    /// Lags along x, in samples.
    pub lags: Vec<usize>,
    lags_y: Vec<usize>,
    n: [usize; 2],
    periodic: bool,
    /// cos(2π k τ / n) per axis: `[scale][k]`.
    cos_x: Vec<Vec<f64>>,
    cos_y: Vec<Vec<f64>>,
}

impl StructureFunction {
    /// The statistic at `lags` on the grid of `h`.
    pub fn new(h: &HeightField, lags: Vec<usize>, periodic: bool) -> Self {
        let [nx, ny] = h.dims();
        let lags_y = same_length_along_y(h, &lags, 1);
        let table = |lags: &[usize], n: usize| -> Vec<Vec<f64>> {
            lags.iter()
                .map(|&t| {
                    (0..n)
                        .map(|k| (TAU * (k * t % n) as f64 / n as f64).cos())
                        .collect()
                })
                .collect()
        };
        Self {
            cos_x: table(&lags, nx),
            cos_y: if ny > 1 {
                table(&lags_y, ny)
            } else {
                Vec::new()
            },
            lags,
            lags_y,
            n: [nx, ny],
            periodic,
        }
    }

    /// The lags in length units (along x).
    pub fn distances(&self, dx: f64) -> Vec<f64> {
        self.lags.iter().map(|&t| t as f64 * dx).collect()
    }

    /// Measured S(τ): the x part plus, for areas, the y part.
    pub fn measure(&self, h: &HeightField) -> Vec<f64> {
        let [nx, ny] = self.n;
        // Pairs a line at lag t, or None where the lag has none.
        let pairs = |n: usize, t: usize| {
            (t > 0 && (self.periodic || t < n)).then(|| if self.periodic { n } else { n - t })
        };
        let x = lag_sums(h, false, &self.lags, self.periodic);
        let y = (ny > 1).then(|| lag_sums(h, true, &self.lags_y, self.periodic));
        (0..self.lags.len())
            .map(|s| {
                let Some(px) = pairs(nx, self.lags[s]) else {
                    return f64::NAN;
                };
                let sx = x[s] / (px * ny) as f64;
                match &y {
                    None => sx,
                    Some(y) => pairs(ny, self.lags_y[s])
                        .map_or(f64::NAN, |py| sx + y[s] / (py * nx) as f64),
                }
            })
            .collect()
    }
}

/// Σ (z(x + τ) − z(x))² over every line of `h` along x (or, with `along_y`,
/// along y) for each lag τ of `lags`, the pairs wrapping if `periodic` (a lag
/// of 0, or without wrapping one of the line's length or more, sums to 0).
/// Each line is read once for all lags while it sits in cache.
fn lag_sums(h: &HeightField, along_y: bool, lags: &[usize], periodic: bool) -> Vec<f64> {
    let n = if along_y { h.ny() } else { h.nx() };
    let partial = fold_lines(
        h,
        along_y,
        || vec![0.0; lags.len()],
        |sums, z| {
            for (sum, &t) in sums.iter_mut().zip(lags) {
                if t == 0 || (!periodic && t >= n) {
                    continue;
                }
                let t = t % n;
                *sum += squared_differences(&z[..n - t], &z[t..]);
                if periodic {
                    // The wrapped pairs: z[a + t − n] − z[a] for a ≥ n − t.
                    *sum += squared_differences(&z[n - t..], &z[..t]);
                }
            }
        },
    );
    let mut total = vec![0.0; lags.len()];
    for p in partial {
        total.iter_mut().zip(p).for_each(|(t, v)| *t += v);
    }
    total
}

/// Σ (b − a)² over pairs, in eight independent lanes (so the compiler keeps
/// them in vector registers) added in a fixed order.
fn squared_differences(a: &[f64], b: &[f64]) -> f64 {
    const LANES: usize = 8;
    let mut lanes = [0.0f64; LANES];
    let (ca, cb) = (a.chunks_exact(LANES), b.chunks_exact(LANES));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(p, q)| (q - p) * (q - p))
        .sum();
    for (p, q) in ca.zip(cb) {
        for k in 0..LANES {
            let d = q[k] - p[k];
            lanes[k] += d * d;
        }
    }
    lanes.iter().sum::<f64>() + tail
}

impl Kernel for StructureFunction {
    fn scales(&self) -> usize {
        self.lags.len()
    }
    fn mirror_symmetric(&self) -> bool {
        true
    }
    fn eval(&self, kx: usize, ky: usize, out: &mut [f64]) {
        for (s, o) in out.iter_mut().enumerate() {
            let mut k = 2.0 * (1.0 - self.cos_x[s][kx]);
            if self.n[1] > 1 {
                k += 2.0 * (1.0 - self.cos_y[s][ky]);
            }
            *o = k;
        }
    }
}

/// What a box's reference is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxReference {
    /// The box's mean (partitioning).
    Mean,
    /// The box's least-squares plane (variable bandwidth).
    Plane,
}

/// Variance of heights in boxes of side ℓ (see the module docs).
#[derive(Clone, Debug)]
pub struct BoxVariance {
    /// Box sides along x, in samples.
    pub sides: Vec<usize>,
    sides_y: Vec<usize>,
    n: [usize; 2],
    reference: BoxReference,
    /// |D₀|² and |D₁|² per axis, `([scale][k] along x, along y)`: made on
    /// the first use of the kernel, which the measurement does not need.
    projections: OnceLock<Projections>,
}

/// |D₀|² and |D₁|² per scale and wavenumber along x, then along y.
type Projections = (Vec<(Vec<f64>, Vec<f64>)>, Vec<(Vec<f64>, Vec<f64>)>);

/// |D₀(k)|² and |D₁(k)|² of a box of `l` samples on an axis of `n`, in closed
/// form: with θ = 2πk/n and c = (l − 1)/2, Σₓ e^{iθ(x − c)} is the Dirichlet
/// kernel D(θ) = sin(lθ/2)/sin(θ/2), so |D₀|² = D²/l², and Σₓ (x − c) e^{iθx}
/// has the modulus |D′(θ)|, so |D₁|² = D′²/(l Σₓ(x − c)²).
fn projections(l: usize, n: usize) -> (Vec<f64>, Vec<f64>) {
    let lf = l as f64;
    // Σ (x − c)² over the box.
    let xx = lf * (lf * lf - 1.0) / 12.0;
    (0..n)
        .map(|k| {
            if k == 0 {
                return (1.0, 0.0);
            }
            let half = TAU * k as f64 / n as f64 / 2.0;
            let (s, c) = half.sin_cos();
            let (sl, cl) = (lf * half).sin_cos();
            let d = sl / s;
            let d_prime = (0.5 * lf * cl * s - 0.5 * sl * c) / (s * s);
            let d1 = if xx > 0.0 {
                d_prime * d_prime / (lf * xx)
            } else {
                0.0
            };
            (d * d / (lf * lf), d1)
        })
        .unzip()
}

impl BoxVariance {
    /// The statistic for boxes of `sides` samples along x (along y, the same
    /// physical length) on the grid of `h`.
    pub fn new(h: &HeightField, sides: Vec<usize>, reference: BoxReference) -> Self {
        let [nx, ny] = h.dims();
        let sides_y = same_length_along_y(h, &sides, 2);
        Self {
            projections: OnceLock::new(),
            sides,
            sides_y,
            n: [nx, ny],
            reference,
        }
    }

    /// Measured mean residual variance per box side.
    pub fn measure(&self, h: &HeightField) -> Vec<f64> {
        let [nx, ny] = self.n;
        // One side per task: each covers about the whole field.
        self.sides
            .par_iter()
            .zip(&self.sides_y)
            .map(|(&lx, &ly)| {
                let ly = if ny == 1 { 1 } else { ly };
                let (bx, by) = (nx / lx, ny / ly);
                if bx == 0 || by == 0 {
                    return f64::NAN;
                }
                let mut total = 0.0;
                for bj in 0..by {
                    for bi in 0..bx {
                        total += box_residual(h, [bi * lx, bj * ly], [lx, ly], self.reference);
                    }
                }
                total / (bx * by) as f64
            })
            .collect()
    }
}

/// Σ z, Σ i·z and Σ z² of a row segment (i from 0), in four independent lanes
/// added in a fixed order.
fn row_moments(z: &[f64]) -> [f64; 3] {
    const LANES: usize = 4;
    let (mut s, mut si, mut s2) = ([0.0f64; LANES], [0.0f64; LANES], [0.0f64; LANES]);
    let chunks = z.chunks_exact(LANES);
    let rest = chunks.remainder();
    let mut i = [0.0, 1.0, 2.0, 3.0];
    for c in chunks {
        for k in 0..LANES {
            s[k] += c[k];
            si[k] += i[k] * c[k];
            s2[k] += c[k] * c[k];
            i[k] += LANES as f64;
        }
    }
    let mut out = [s.iter().sum(), si.iter().sum(), s2.iter().sum::<f64>()];
    for (k, &v) in rest.iter().enumerate() {
        out[0] += v;
        out[1] += (z.len() - rest.len() + k) as f64 * v;
        out[2] += v * v;
    }
    out
}

/// Mean square residual of one box after its mean or plane.
fn box_residual(
    h: &HeightField,
    [i0, j0]: [usize; 2],
    [lx, ly]: [usize; 2],
    r: BoxReference,
) -> f64 {
    let (cx, cy) = ((lx - 1) as f64 / 2.0, (ly - 1) as f64 / 2.0);
    let (mut s, mut sx, mut sy, mut s2) = (0.0, 0.0, 0.0, 0.0);
    for j in 0..ly {
        let [sum, first_moment, squares] = row_moments(&h.row(j0 + j)[i0..i0 + lx]);
        s += sum;
        sx += first_moment - cx * sum;
        sy += sum * (j as f64 - cy);
        s2 += squares;
    }
    let n = (lx * ly) as f64;
    let mut res = s2 - s * s / n;
    if r == BoxReference::Plane {
        // Σ (x − cx)² over the box = ly · lx (lx² − 1) / 12.
        let xx = ly as f64 * lx as f64 * ((lx * lx) as f64 - 1.0) / 12.0;
        let yy = lx as f64 * ly as f64 * ((ly * ly) as f64 - 1.0) / 12.0;
        if xx > 0.0 {
            res -= sx * sx / xx;
        }
        if yy > 0.0 {
            res -= sy * sy / yy;
        }
    }
    res.max(0.0) / n
}

impl Kernel for BoxVariance {
    fn scales(&self) -> usize {
        self.sides.len()
    }
    fn mirror_symmetric(&self) -> bool {
        true
    }
    fn eval(&self, kx: usize, ky: usize, out: &mut [f64]) {
        let [nx, ny] = self.n;
        let (d_x, d_y) = self.projections.get_or_init(|| {
            let axis =
                |sides: &[usize], n: usize| sides.iter().map(|&l| projections(l, n)).collect();
            let along_y = if ny > 1 {
                axis(&self.sides_y, ny)
            } else {
                Vec::new()
            };
            (axis(&self.sides, nx), along_y)
        });
        for (s, o) in out.iter_mut().enumerate() {
            let (u, v) = (d_x[s].0[kx], d_x[s].1[kx]);
            let (uy, vy) = if ny > 1 {
                (d_y[s].0[ky], d_y[s].1[ky])
            } else {
                (1.0, 0.0)
            };
            *o = match self.reference {
                BoxReference::Mean => 1.0 - u * uy,
                BoxReference::Plane => 1.0 - u * uy - v * uy - u * vy,
            };
        }
    }
}

/// The mean 1-D periodogram of profiles along one axis.
#[derive(Clone, Debug)]
pub struct ProfileSpectrum {
    /// Wavenumber indices k (q = 2πk / L along the axis).
    pub indices: Vec<usize>,
    along_y: bool,
    n_axis: usize,
    window: Window,
    /// |Ŵ(d)|² for d = 0..n (a delta without a window).
    w2: Vec<f64>,
    /// The non-zero entries of `w2` as (d, value).
    taps: Vec<(usize, f64)>,
    /// The scale measured at each wavenumber index, if any.
    scale_of: Vec<Option<usize>>,
}

impl ProfileSpectrum {
    /// The statistic along x (or y) of `h` at distinct wavenumber indices `indices`,
    /// windowed by `window` (use [`Window::None`] for periodic data).
    pub fn new(h: &HeightField, along_y: bool, indices: Vec<usize>, window: Window) -> Self {
        let n = if along_y { h.ny() } else { h.nx() };
        let w2: Vec<f64> = if window == Window::None {
            (0..n)
                .map(|d| if d == 0 { (n * n) as f64 } else { 0.0 })
                .collect()
        } else {
            let w = window.profile(n);
            let mut c: Vec<Complex<f64>> = w.iter().map(|&v| Complex::new(v, 0.0)).collect();
            FftPlanner::new().plan_fft_forward(n).process(&mut c);
            // Rounding leaves ~1e-30 where a window's spectrum is zero (all
            // but 3 taps of a periodic Hann window): exact zeros keep the
            // model's sums sparse.
            let peak = (n * n) as f64;
            c.iter()
                .map(|v| v.norm_sqr())
                .map(|p| if p < 1e-15 * peak { 0.0 } else { p })
                .collect()
        };
        let taps = w2
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, v)| *v != 0.0)
            .collect();
        let mut scale_of = vec![None; n];
        for (s, &k) in indices.iter().enumerate() {
            scale_of[k % n] = Some(s);
        }
        Self {
            indices,
            along_y,
            n_axis: n,
            window,
            w2,
            taps,
            scale_of,
        }
    }

    /// The wavenumbers in rad per length unit.
    pub fn wavenumbers(&self, spacing: f64) -> Vec<f64> {
        let l = self.n_axis as f64 * spacing;
        self.indices.iter().map(|&k| TAU * k as f64 / l).collect()
    }

    /// Measured mean |FFT(w·z)|² of the profiles at each index, and the same
    /// for every index 0..n/2 (for the report).
    pub fn measure_all(&self, h: &HeightField) -> Vec<f64> {
        let [nx, ny] = h.dims();
        let (n, m) = if self.along_y { (ny, nx) } else { (nx, ny) };
        let w = if self.window == Window::None {
            vec![1.0; n]
        } else {
            self.window.profile(n)
        };
        // Σ |Z(k)|² over the lines, per task of lines, then in order.
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let parts = fold_lines(
            h,
            self.along_y,
            || {
                let (line, spectrum) = (fft.make_input_vec(), fft.make_output_vec());
                (vec![0.0; n / 2 + 1], line, spectrum, fft.make_scratch_vec())
            },
            |(acc, line, spectrum, scratch), z| {
                line.iter_mut()
                    .zip(z.iter().zip(&w))
                    .for_each(|(l, (z, w))| *l = z * w);
                fft.process_with_scratch(line, spectrum, scratch)
                    .expect("buffers sized by the plan");
                acc.iter_mut()
                    .zip(spectrum.iter())
                    .for_each(|(a, c)| *a += c.norm_sqr());
            },
        );
        let mut acc = vec![0.0; n / 2 + 1];
        for (p, ..) in parts {
            acc.iter_mut().zip(p).for_each(|(a, p)| *a += p);
        }
        acc.iter().map(|v| v / m as f64).collect()
    }

    /// Measured values at [`Self::indices`].
    pub fn measure(&self, h: &HeightField) -> Vec<f64> {
        let all = self.measure_all(h);
        self.indices.iter().map(|&k| all[k]).collect()
    }
}

impl Kernel for ProfileSpectrum {
    fn scales(&self) -> usize {
        self.indices.len()
    }
    fn eval_sparse(&self, kx: usize, ky: usize, nonzero: &mut Vec<(usize, f64)>) -> bool {
        if self.taps.len() >= self.indices.len() {
            return false;
        }
        // As `eval`'s sparse branch, listing only the scales a tap reaches.
        let k_mode = if self.along_y { ky } else { kx };
        let n = self.n_axis;
        for &(d, v) in &self.taps {
            if let Some(s) = self.scale_of[(k_mode % n + d) % n]
                && v != 0.0
            {
                nonzero.push((s, v));
            }
        }
        nonzero.sort_unstable_by_key(|&(s, _)| s);
        true
    }
    fn eval(&self, kx: usize, ky: usize, out: &mut [f64]) {
        let k_mode = if self.along_y { ky } else { kx };
        let n = self.n_axis;
        if self.taps.len() < out.len() {
            // K_s = w2[(k_s − k) mod n] is non-zero only where k_s = k + d for
            // a tap d: visit the taps, not the scales.
            out.fill(0.0);
            for &(d, v) in &self.taps {
                if let Some(s) = self.scale_of[(k_mode % n + d) % n] {
                    out[s] = v;
                }
            }
        } else {
            for (s, o) in out.iter_mut().enumerate() {
                let d = (self.indices[s] + n - k_mode % n) % n;
                *o = self.w2[d];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Compressed, ModeGrid};

    /// A kernel seen without its symmetry: the model's sums over every mode.
    struct Unfolded<'a>(&'a dyn Kernel);
    impl Kernel for Unfolded<'_> {
        fn scales(&self) -> usize {
            self.0.scales()
        }
        fn eval(&self, kx: usize, ky: usize, out: &mut [f64]) {
            self.0.eval(kx, ky, out);
        }
    }

    /// The kernels that claim mirror symmetry have it, and the model summed
    /// over a quarter of the modes equals the full sum.
    #[test]
    fn mirror_symmetric_kernels_fold_exactly() {
        let (nx, ny) = (24, 18);
        let h = HeightField::from_vec([nx, ny], vec![0.0; nx * ny]).unwrap();
        let grid = ModeGrid {
            n: [nx, ny],
            spacing: [1.0, 1.0],
        };
        let sf = StructureFunction::new(&h, vec![1, 2, 5], false);
        let mean = BoxVariance::new(&h, vec![2, 3, 6], BoxReference::Mean);
        let plane = BoxVariance::new(&h, vec![3, 4, 6], BoxReference::Plane);
        for k in [&sf as &dyn Kernel, &mean, &plane] {
            assert!(k.mirror_symmetric());
            let (mut a, mut b, mut c) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]);
            for ky in 0..ny {
                for kx in 0..nx {
                    k.eval(kx, ky, &mut a);
                    k.eval((nx - kx) % nx, ky, &mut b);
                    k.eval(kx, (ny - ky) % ny, &mut c);
                    for s in 0..3 {
                        assert!((a[s] - b[s]).abs() < 1e-12 && (a[s] - c[s]).abs() < 1e-12);
                    }
                }
            }
            let folded = Compressed::new(k, &grid);
            let full = Compressed::new(&Unfolded(k), &grid);
            for hu in [0.3, 0.9] {
                for (x, y) in folded.expected(hu).iter().zip(full.expected(hu)) {
                    assert!((x / y - 1.0).abs() < 1e-12, "{x} vs {y}");
                }
                for (x, y) in folded.expected_log(hu).iter().zip(full.expected_log(hu)) {
                    assert!((x - y).abs() < 1e-12, "{x} vs {y}");
                }
            }
        }
    }

    fn wave(n: usize, kx: usize, ky: usize, phase: f64) -> HeightField {
        HeightField::from_vec(
            [n, n],
            (0..n * n)
                .map(|p| (TAU * ((kx * (p % n) + ky * (p / n)) as f64) / n as f64 + phase).cos())
                .collect(),
        )
        .unwrap()
    }

    /// For a single plane wave of random phase the expected statistic is the
    /// kernel at its mode (times the wave's power), scale by scale — the
    /// identity the model rests on. The structure function has no phase
    /// dependence; the boxes are averaged over eight phases, which cancels the
    /// ±k cross terms exactly.
    #[test]
    fn measurements_match_their_kernels_on_plane_waves() {
        let n = 32;
        for (kx, ky) in [(3, 0), (2, 5), (7, 7)] {
            let mean_over_phases = |f: &dyn Fn(&HeightField) -> Vec<f64>| -> Vec<f64> {
                let mut acc = vec![0.0; 3];
                for j in 0..8 {
                    let m = f(&wave(n, kx, ky, j as f64 * TAU / 8.0));
                    acc.iter_mut().zip(&m).for_each(|(a, v)| *a += v / 8.0);
                }
                acc
            };
            let h = wave(n, kx, ky, 0.3);
            let sf = StructureFunction::new(&h, vec![1, 5, 8], true);
            let bv = BoxVariance::new(&h, vec![4, 8, 16], BoxReference::Plane);
            let bm = BoxVariance::new(&h, vec![4, 8, 16], BoxReference::Mean);
            for (m, k) in [
                (sf.measure(&h), eval_all(&sf, kx, ky)),
                (mean_over_phases(&|h| bv.measure(h)), eval_all(&bv, kx, ky)),
                (mean_over_phases(&|h| bm.measure(h)), eval_all(&bm, kx, ky)),
            ] {
                let ratio: Vec<f64> = m.iter().zip(&k).map(|(a, b)| a / b).collect();
                for r in &ratio {
                    assert!((r - ratio[0]).abs() < 1e-9, "({kx}, {ky}): {ratio:?}");
                }
            }
        }
    }

    fn eval_all(k: &dyn Kernel, kx: usize, ky: usize) -> Vec<f64> {
        let mut out = vec![0.0; k.scales()];
        k.eval(kx, ky, &mut out);
        out
    }

    #[test]
    fn profile_spectrum_of_a_row_wave() {
        let n = 64;
        let h = wave(n, 5, 0, 0.0);
        let p = ProfileSpectrum::new(&h, false, vec![4, 5, 6], Window::None);
        let m = p.measure(&h);
        assert!(m[0] < 1e-18 && m[2] < 1e-18);
        assert!((m[1] - (n * n) as f64 / 4.0).abs() < 1e-6);
        let c = Compressed::new(
            &p,
            &ModeGrid {
                n: [n, n],
                spacing: [1.0, 1.0],
            },
        );
        assert!(c.expected(0.5).iter().all(|e| *e > 0.0));
    }

    #[test]
    fn box_projections_in_closed_form_are_the_sums() {
        for (l, n) in [(1, 8), (2, 8), (4, 64), (7, 50), (64, 256), (300, 1024)] {
            let (d0, d1) = projections(l, n);
            let c = (l - 1) as f64 / 2.0;
            let xx: f64 = (0..l).map(|x| (x as f64 - c).powi(2)).sum();
            for k in 0..n {
                let th = TAU * k as f64 / n as f64;
                let (mut s0, mut s1) = (Complex::new(0.0, 0.0), Complex::new(0.0, 0.0));
                for x in 0..l {
                    let e = Complex::from_polar(1.0, th * x as f64);
                    s0 += e;
                    s1 += e * (x as f64 - c);
                }
                let e0 = s0.norm_sqr() / (l * l) as f64;
                let e1 = if xx > 0.0 {
                    s1.norm_sqr() / (l as f64 * xx)
                } else {
                    0.0
                };
                assert!(
                    (d0[k] - e0).abs() < 1e-9,
                    "l {l} n {n} k {k}: D0 {} vs {e0}",
                    d0[k]
                );
                assert!(
                    (d1[k] - e1).abs() < 1e-9,
                    "l {l} n {n} k {k}: D1 {} vs {e1}",
                    d1[k]
                );
            }
        }
    }

    #[test]
    fn log_scales_are_distinct_and_bounded() {
        let s = log_scales(1, 64, 3);
        assert_eq!(s.first(), Some(&1));
        assert_eq!(s.last(), Some(&64));
        assert!(s.windows(2).all(|w| w[1] > w[0]));
        assert!(log_scales(5, 2, 3).is_empty());
    }
}
