//! Correlation of a grid's lines with a kernel: `y[i] = Σ_d k[d] · x[i + d]`,
//! the lines either open (samples beyond the ends are absent, read as zero) or
//! wrapped (periodic). Short kernels run directly; long ones through a real FFT
//! of each line (`realfft`), zero-padded so that nothing wraps on open lines.
//! Each line is independent, so the result does not depend on the thread count.

use std::sync::Arc;

use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex;

use crate::spectrum::smooth_len;

/// Kernels at most this long (or lines at most this long) run directly.
const DIRECT_TAPS: usize = 48;

/// A kernel `k[d]` for offsets `d = −half ..= half`.
#[derive(Clone, Debug)]
pub(crate) struct Kernel {
    /// `taps[d + half]`.
    pub taps: Vec<f64>,
    /// The largest offset.
    pub half: usize,
}

impl Kernel {
    /// The kernel `f(d)` for `d = −half ..= half`.
    pub fn from_fn(half: usize, f: impl Fn(isize) -> f64) -> Self {
        let taps = (-(half as isize)..=half as isize).map(f).collect();
        Self { taps, half }
    }

    fn tap(&self, d: isize) -> f64 {
        self.taps[(d + self.half as isize) as usize]
    }
}

/// The correlation of lines of length `n` with one kernel, planned once.
pub(crate) struct LineFilter {
    n: usize,
    wrap: bool,
    kernel: Kernel,
    /// The kernel folded onto the line (wrapped lines shorter than the kernel).
    folded: Option<Vec<f64>>,
    fft: Option<Spectral>,
}

struct Spectral {
    len: usize,
    forward: Arc<dyn RealToComplex<f64>>,
    inverse: Arc<dyn ComplexToReal<f64>>,
    /// The spectrum of the kernel, reversed and laid on the circle, over the length.
    spectrum: Vec<Complex<f64>>,
}

impl Spectral {
    /// The transforms of a line of `n` samples (padded so that an open line
    /// does not wrap) and the kernel's spectrum.
    fn plan(n: usize, kernel: &Kernel, wrap: bool) -> Self {
        let len = if wrap {
            n
        } else {
            smooth_len(n + 2 * kernel.half)
        };
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(len);
        let inverse = planner.plan_fft_inverse(len);
        // correlation as a circular convolution: c[(−d) mod len] = k[d]
        let mut circle = vec![0.0; len];
        for d in -(kernel.half as isize)..=kernel.half as isize {
            circle[(-d).rem_euclid(len as isize) as usize] += kernel.tap(d);
        }
        let mut spectrum = forward.make_output_vec();
        let mut scratch = forward.make_scratch_vec();
        // lengths match the plan's own vectors: this cannot fail
        let _ = forward.process_with_scratch(&mut circle, &mut spectrum, &mut scratch);
        let scale = 1.0 / len as f64;
        spectrum.iter_mut().for_each(|c| *c *= scale);
        Self {
            len,
            forward,
            inverse,
            spectrum,
        }
    }
}

/// Buffers one thread reuses from line to line.
#[derive(Default)]
pub(crate) struct Scratch {
    line: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    work: Vec<Complex<f64>>,
}

impl LineFilter {
    /// Plans the correlation of lines of `n` samples with `kernel`.
    pub fn new(n: usize, kernel: Kernel, wrap: bool) -> Self {
        let folded = (wrap && kernel.taps.len() > n).then(|| {
            let mut f = vec![0.0; n];
            for d in -(kernel.half as isize)..=kernel.half as isize {
                f[d.rem_euclid(n as isize) as usize] += kernel.tap(d);
            }
            f
        });
        let taps = folded.as_ref().map_or(kernel.taps.len(), Vec::len);
        let fft = (taps > DIRECT_TAPS && n > DIRECT_TAPS).then(|| Spectral::plan(n, &kernel, wrap));
        Self {
            n,
            wrap,
            kernel,
            folded,
            fft,
        }
    }

    /// `out[i] = Σ_d k[d] · x[i + d]` over one line.
    pub fn apply(&self, x: &[f64], out: &mut [f64], scratch: &mut Scratch) {
        debug_assert_eq!(x.len(), self.n);
        match &self.fft {
            Some(f) => self.spectral(f, x, out, scratch),
            None => self.direct(x, out),
        }
    }

    fn direct(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n as isize;
        if let Some(f) = &self.folded {
            for (i, o) in out.iter_mut().enumerate() {
                *o = f
                    .iter()
                    .enumerate()
                    .map(|(e, k)| k * x[(i + e) % self.n])
                    .sum();
            }
            return;
        }
        let half = self.kernel.half;
        let taps = &self.kernel.taps;
        // Where the whole kernel lies on the line, tap by tap over every
        // point (the compiler vectorises across points; each point still sums
        // its taps in order, as below). Elsewhere each tap is wrapped or left out.
        let inner = match self.n >= 2 * half {
            true => half..self.n - half,
            false => 0..0,
        };
        if !inner.is_empty() {
            let body = &mut out[inner.clone()];
            body.fill(0.0);
            for (e, k) in taps.iter().enumerate() {
                // inner.start = half, so the points' first sample is x[e]
                for (o, v) in body.iter_mut().zip(&x[e..]) {
                    *o += k * v;
                }
            }
        }
        let half = half as isize;
        for i in (0..inner.start).chain(inner.end..self.n) {
            let i_ = i as isize;
            let mut s = 0.0;
            for d in -half..=half {
                let j = i_ + d;
                let j = if self.wrap {
                    j.rem_euclid(n)
                } else if (0..n).contains(&j) {
                    j
                } else {
                    continue;
                };
                s += self.kernel.tap(d) * x[j as usize];
            }
            out[i] = s;
        }
    }

    fn spectral(&self, f: &Spectral, x: &[f64], out: &mut [f64], s: &mut Scratch) {
        s.line.clear();
        s.line.extend_from_slice(x);
        s.line.resize(f.len, 0.0);
        s.spectrum.resize(f.len / 2 + 1, Complex::default());
        let need = f.forward.get_scratch_len().max(f.inverse.get_scratch_len());
        s.work.resize(need, Complex::default());
        // buffer lengths are the plan's: these cannot fail
        let _ = f
            .forward
            .process_with_scratch(&mut s.line, &mut s.spectrum, &mut s.work);
        s.spectrum
            .iter_mut()
            .zip(&f.spectrum)
            .for_each(|(a, b)| *a *= b);
        // a real signal's transform has real end bins; keep them exactly so
        s.spectrum[0].im = 0.0;
        if f.len.is_multiple_of(2) {
            s.spectrum[f.len / 2].im = 0.0;
        }
        let _ = f
            .inverse
            .process_with_scratch(&mut s.spectrum, &mut s.line, &mut s.work);
        out.copy_from_slice(&s.line[..self.n]);
    }

    /// Every row of the row-major `data` (rows of `n` samples), on every core.
    pub fn rows(&self, data: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; data.len()];
        out.par_chunks_mut(self.n)
            .zip(data.par_chunks(self.n))
            .for_each_init(Scratch::default, |s, (o, x)| self.apply(x, o, s));
        out
    }
}

/// The transpose of the row-major `data` with rows of `nx` samples (rows of
/// `ny` samples come out), in cache-sized blocks.
pub(crate) fn transpose(data: &[f64], nx: usize, ny: usize) -> Vec<f64> {
    const BLOCK: usize = 32;
    let mut out = vec![0.0; data.len()];
    out.par_chunks_mut(ny * BLOCK.min(nx).max(1))
        .enumerate()
        .for_each(|(b, strip)| {
            let i0 = b * BLOCK.min(nx).max(1);
            let rows = strip.len() / ny.max(1);
            for j in 0..ny {
                let src = &data[j * nx + i0..j * nx + i0 + rows];
                for (r, &v) in src.iter().enumerate() {
                    strip[r * ny + j] = v;
                }
            }
        });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    fn reference(x: &[f64], k: &Kernel, wrap: bool) -> Vec<f64> {
        let n = x.len() as isize;
        (0..n)
            .map(|i| {
                (-(k.half as isize)..=k.half as isize)
                    .filter_map(|d| {
                        let j = i + d;
                        let j = if wrap {
                            j.rem_euclid(n)
                        } else if (0..n).contains(&j) {
                            j
                        } else {
                            return None;
                        };
                        Some(k.tap(d) * x[j as usize])
                    })
                    .sum()
            })
            .collect()
    }

    #[test]
    fn direct_and_spectral_paths_equal_the_definition() {
        let mut rng = StdRng::seed_from_u64(rand::random());
        for (n, half) in [
            (5, 2),
            (7, 9),
            (100, 3),
            (100, 70),
            (257, 400),
            (300, 30),
            (64, 64),
        ] {
            let x: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let k = Kernel::from_fn(half, |d| (d as f64 * 0.37).sin() + 0.5);
            for wrap in [false, true] {
                let f = LineFilter::new(n, k.clone(), wrap);
                let mut out = vec![0.0; n];
                f.apply(&x, &mut out, &mut Scratch::default());
                let want = reference(&x, &k, wrap);
                let scale: f64 = k.taps.iter().map(|t| t.abs()).sum();
                for (a, b) in out.iter().zip(&want) {
                    assert!(
                        (a - b).abs() <= 1e-12 * scale,
                        "n {n} half {half} wrap {wrap}: {a} vs {b}"
                    );
                }
            }
        }
    }

    #[test]
    fn transpose_swaps_the_axes() {
        let (nx, ny) = (70, 45);
        let data: Vec<f64> = (0..nx * ny).map(|k| k as f64).collect();
        let t = transpose(&data, nx, ny);
        for j in 0..ny {
            for i in 0..nx {
                assert_eq!(t[i * ny + j], data[j * nx + i]);
            }
        }
        assert_eq!(transpose(&t, ny, nx), data);
    }
}
