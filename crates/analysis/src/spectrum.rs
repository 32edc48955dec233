//! The 2-D Fourier transform of a real height field, kept as the half of the
//! spectrum that a real field determines (Hermitian symmetry Z(−q) = Z(q)*):
//! wavenumbers k_x = 0…nx/2 along x, every k_y along y. The PSD
//! ([`crate::psd`]) and the autocorrelation ([`crate::correlation`]) are both
//! read from one [`PowerSpectrum`], so `asperity analyze` of a periodic field
//! transforms it once.
//!
//! Half the modes and no complex copy of the input: a real-to-complex
//! transform of each row (`realfft`, over `rustfft`), then complex transforms
//! of the nx/2 + 1 columns, copied a strip at a time into contiguous lines (no
//! full transpose). Every line is transformed alone, so the result is the
//! same bytes at any thread count.

use std::sync::Arc;

use asperity_core::HeightField;
use rayon::prelude::*;
use realfft::RealFftPlanner;
use rustfft::{Fft, FftPlanner, num_complex::Complex};

/// Columns a task transforms at once (16 columns of 4096 complex values are
/// 1 MiB).
const COLUMNS_PER_TASK: usize = 16;

/// |Z(k)|² on the half grid of a real `nx × ny` field: `(nx/2 + 1) × ny`
/// values, k_x fastest, zero frequency at index 0 (unnormalised: Σ over the
/// full grid of |Z|² is nx·ny·Σz², Parseval).
#[derive(Clone, Debug, PartialEq)]
pub struct PowerSpectrum {
    /// The field's samples per side.
    pub dims: [usize; 2],
    /// The field's sample spacing.
    pub spacing: [f64; 2],
    /// |Z|², `half_width() × ny`, k_x fastest.
    pub power: Vec<f64>,
}

impl PowerSpectrum {
    /// |Z|² of `h` multiplied by `window` (`None`: as it is).
    pub fn of(h: &HeightField, window: Option<&[f64]>) -> Self {
        let [nx, ny] = h.dims();
        let spectrum = forward(h.data(), window, nx, ny);
        Self {
            dims: [nx, ny],
            spacing: h.spacing(),
            power: spectrum.par_iter().map(|c| c.norm_sqr()).collect(),
        }
    }

    /// Stored modes along x: nx/2 + 1.
    pub fn half_width(&self) -> usize {
        self.dims[0] / 2 + 1
    }

    /// How many modes of the full grid stored mode k_x stands for: 1 for
    /// k_x = 0 and (even nx) the Nyquist column, else 2 (k_x and −k_x).
    pub fn multiplicity(&self, kx: usize) -> usize {
        let nx = self.dims[0];
        if kx == 0 || 2 * kx == nx { 1 } else { 2 }
    }
}

/// The half spectrum Z of the real `nx × ny` grid `data` (times `window`).
pub(crate) fn forward(
    data: &[f64],
    window: Option<&[f64]>,
    nx: usize,
    ny: usize,
) -> Vec<Complex<f64>> {
    let half = nx / 2 + 1;
    let rows = RealFftPlanner::<f64>::new().plan_fft_forward(nx);
    let mut out = vec![Complex::new(0.0, 0.0); half * ny];
    out.par_chunks_exact_mut(half).enumerate().for_each_init(
        || (rows.make_input_vec(), rows.make_scratch_vec()),
        |(line, scratch), (j, z)| {
            let row = &data[j * nx..(j + 1) * nx];
            match window {
                Some(w) => {
                    let w = &w[j * nx..(j + 1) * nx];
                    line.iter_mut()
                        .zip(row.iter().zip(w))
                        .for_each(|(l, (v, w))| *l = v * w);
                }
                None => line.copy_from_slice(row),
            }
            rows.process_with_scratch(line, z, scratch)
                .expect("buffers sized by the plan");
        },
    );
    if ny > 1 {
        columns(&mut out, half, ny, &FftPlanner::new().plan_fft_forward(ny));
    }
    out
}

/// The real `nx × ny` grid whose half spectrum is `spectrum` (unnormalised:
/// `inverse(forward(z)) = nx·ny·z`). The imaginary parts that a real field's
/// spectrum cannot have (k_x = 0 and the Nyquist column after the columns'
/// transforms) are dropped.
pub(crate) fn inverse(mut spectrum: Vec<Complex<f64>>, nx: usize, ny: usize) -> Vec<f64> {
    let half = nx / 2 + 1;
    if ny > 1 {
        columns(
            &mut spectrum,
            half,
            ny,
            &FftPlanner::new().plan_fft_inverse(ny),
        );
    }
    let rows = RealFftPlanner::<f64>::new().plan_fft_inverse(nx);
    let mut out = vec![0.0; nx * ny];
    out.par_chunks_exact_mut(nx)
        .zip(spectrum.par_chunks_exact_mut(half))
        .for_each_init(
            || rows.make_scratch_vec(),
            |scratch, (z, line)| {
                line[0].im = 0.0;
                if nx.is_multiple_of(2) {
                    line[half - 1].im = 0.0;
                }
                rows.process_with_scratch(line, z, scratch)
                    .expect("buffers sized by the plan");
            },
        );
    out
}

/// Transforms every column of the `width × ny` grid `data` with `fft`, a
/// strip of [`COLUMNS_PER_TASK`] columns copied into contiguous lines at a time.
fn columns(data: &mut [Complex<f64>], width: usize, ny: usize, fft: &Arc<dyn Fft<f64>>) {
    let strips = width.div_ceil(COLUMNS_PER_TASK);
    // Each task reads its strip from the shared grid and returns the
    // transformed strip; the strips are written back afterwards.
    let grid: &[Complex<f64>] = data;
    let done: Vec<Vec<Complex<f64>>> = (0..strips)
        .into_par_iter()
        .map_init(
            || vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()],
            |scratch, s| {
                let first = s * COLUMNS_PER_TASK;
                let count = COLUMNS_PER_TASK.min(width - first);
                let mut strip = vec![Complex::new(0.0, 0.0); count * ny];
                for j in 0..ny {
                    let row = &grid[j * width + first..j * width + first + count];
                    for (c, &v) in row.iter().enumerate() {
                        strip[c * ny + j] = v;
                    }
                }
                fft.process_with_scratch(&mut strip, scratch);
                strip
            },
        )
        .collect();
    data.par_chunks_exact_mut(width)
        .enumerate()
        .for_each(|(j, row)| {
            for (s, strip) in done.iter().enumerate() {
                let first = s * COLUMNS_PER_TASK;
                let count = strip.len() / ny;
                for c in 0..count {
                    row[first + c] = strip[c * ny + j];
                }
            }
        });
}

/// The smallest length ≥ `n` whose only prime factors are 2, 3 and 5: an FFT
/// length that pads no more than needed and stays fast.
pub(crate) fn smooth_len(n: usize) -> usize {
    (n.max(1)..)
        .find(|&m| {
            let mut m = m;
            for p in [2, 3, 5] {
                while m % p == 0 {
                    m /= p;
                }
            }
            m == 1
        })
        .unwrap_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// The full 2-D DFT by its definition, for small grids.
    fn dft(z: &[f64], nx: usize, ny: usize) -> Vec<Complex<f64>> {
        let mut out = Vec::with_capacity(nx * ny);
        for ky in 0..ny {
            for kx in 0..nx {
                let mut s = Complex::new(0.0, 0.0);
                for j in 0..ny {
                    for i in 0..nx {
                        let a = -TAU * ((kx * i) as f64 / nx as f64 + (ky * j) as f64 / ny as f64);
                        s += Complex::new(a.cos(), a.sin()) * z[i + nx * j];
                    }
                }
                out.push(s);
            }
        }
        out
    }

    fn field(nx: usize, ny: usize) -> Vec<f64> {
        (0..nx * ny)
            .map(|k| ((k * 37 + 11) % 101) as f64 / 7.0 - (k % 5) as f64)
            .collect()
    }

    #[test]
    fn half_spectrum_is_the_dft_and_inverts() {
        for (nx, ny) in [(8, 6), (9, 5), (7, 1), (33, 20), (2, 3), (1, 4), (1, 1)] {
            let z = field(nx, ny);
            let full = dft(&z, nx, ny);
            let half = forward(&z, None, nx, ny);
            let hw = nx / 2 + 1;
            for ky in 0..ny {
                for kx in 0..hw {
                    let d = (half[kx + hw * ky] - full[kx + nx * ky]).norm();
                    assert!(d < 1e-9, "{nx}×{ny} mode ({kx}, {ky}): off by {d}");
                }
            }
            let back = inverse(half, nx, ny);
            let n = (nx * ny) as f64;
            for (b, z) in back.iter().zip(&z) {
                assert!(
                    (b / n - z).abs() < 1e-12,
                    "{nx}×{ny}: {} against {z}",
                    b / n
                );
            }
        }
    }

    #[test]
    fn multiplicities_count_the_full_grid() {
        for (nx, ny) in [(8, 6), (9, 5), (7, 1)] {
            let h = HeightField::from_vec([nx, ny], field(nx, ny)).unwrap();
            let p = PowerSpectrum::of(&h, None);
            let modes: usize = (0..p.half_width()).map(|k| p.multiplicity(k) * ny).sum();
            assert_eq!(modes, nx * ny);
            // Parseval over the full grid.
            let total: f64 = (0..p.power.len())
                .map(|k| p.multiplicity(k % p.half_width()) as f64 * p.power[k])
                .sum();
            let squares: f64 = h.data().iter().map(|z| z * z).sum();
            assert!((total / (nx * ny) as f64 - squares).abs() < 1e-9 * squares);
        }
    }
}
