//! Windows for the spectra of non-periodic data, and the test that tells
//! periodic data from non-periodic.
//!
//! The FFT treats a field as one period of an endless tiling. A periodic
//! surface (generated on a torus) tiles seamlessly; a measured or cropped one
//! does not, and the steps at its edges put power ∝ q⁻² (2-D: q⁻³ radially)
//! into every spectrum, which flattens a steep one — the reason an unwindowed
//! PSD of a cropped H = 0.8 surface reports H ≈ 0.5. Jacobs, Junge & Pastewka
//! (Surf. Topogr.: Metrol. Prop. 5, 013001, 2017, §2.3) and SurfaceTopography
//! therefore multiply non-periodic data by a window before the FFT:
//!
//! - 2-D: a rotationally symmetric window w(r) around the centre sample
//!   (nx/2, ny/2), zero beyond r = min(Lx, Ly)/2 (SurfaceTopography's
//!   `get_window_2D`, `direction='radial'`);
//! - profiles: the periodic (DFT-even) window along x (`scipy.signal.get_window`);
//!
//! each scaled so that Σ w² = N, which keeps Parseval's sum ⟨h²⟩ unbiased.
//! Shapes, with t ∈ [0, 1] the distance from the centre over the half-width:
//! Hann ½(1 + cos πt); Blackman–Harris (4-term, Harris 1978) a₀ + a₁ cos πt +
//! a₂ cos 2πt + a₃ cos 3πt; Kaiser I₀(β√(1 − t²)) / I₀(β).
//!
//! [`edge_ratio`] decides periodicity from the data: on a periodic field the
//! jump from the last row to the first is one more neighbour step; on a crop it
//! is a step across the whole field, larger by about (n)^H. The ratio of the
//! rms edge jump to the rms neighbour step is ≈ 1 for periodic data and ≥ 3 for
//! crops of self-affine surfaces of 256² and more (H ≥ 0.2); below 2 counts as
//! periodic.

use asperity_core::HeightField;

/// A window shape for non-periodic data.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Window {
    /// No window (periodic data).
    None,
    /// Hann (raised cosine): the default.
    Hann,
    /// Kaiser with shape parameter β (β ≈ 8.6 is close to Blackman–Harris).
    Kaiser(f64),
    /// 4-term Blackman–Harris (−92 dB side lobes).
    BlackmanHarris,
}

impl Window {
    /// Parses `none`, `hann`, `blackman-harris`, `kaiser` (β = 8.6) or `kaiser:BETA`.
    pub fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "none" => Window::None,
            "hann" => Window::Hann,
            "blackman-harris" | "blackmanharris" => Window::BlackmanHarris,
            "kaiser" => Window::Kaiser(8.6),
            _ => {
                let beta: f64 = s.strip_prefix("kaiser:")?.parse().ok()?;
                if !(beta.is_finite() && beta >= 0.0) {
                    return None;
                }
                Window::Kaiser(beta)
            }
        })
    }

    /// The name, as [`Window::from_name`] reads it.
    pub fn name(self) -> String {
        match self {
            Window::None => "none".into(),
            Window::Hann => "hann".into(),
            Window::BlackmanHarris => "blackman-harris".into(),
            Window::Kaiser(b) => format!("kaiser:{b}"),
        }
    }

    /// w(t) for t = distance from the centre / half-width, in [0, 1]; 0 beyond.
    pub fn shape(self, t: f64) -> f64 {
        use std::f64::consts::PI;
        if t > 1.0 {
            return 0.0;
        }
        match self {
            Window::None => 1.0,
            Window::Hann => 0.5 + 0.5 * (PI * t).cos(),
            Window::BlackmanHarris => {
                const A: [f64; 4] = [0.35875, 0.48829, 0.14128, 0.01168];
                A[0] + A[1] * (PI * t).cos()
                    + A[2] * (2.0 * PI * t).cos()
                    + A[3] * (3.0 * PI * t).cos()
            }
            Window::Kaiser(beta) => {
                bessel_i0(beta * (1.0 - t * t).max(0.0).sqrt()) / bessel_i0(beta)
            }
        }
    }

    /// The 1-D window of `n` samples, DFT-even (sample k at t = |k − n/2| / (n/2),
    /// as `scipy.signal.get_window(..., fftbins=True)`), scaled to Σ w² = n.
    pub fn profile(self, n: usize) -> Vec<f64> {
        let half = n as f64 / 2.0;
        let w: Vec<f64> = (0..n)
            .map(|k| self.shape((k as f64 - (n / 2) as f64).abs() / half))
            .collect();
        normalised(w, n)
    }

    /// The rotationally symmetric 2-D window of an `nx × ny` grid of physical
    /// size `[lx, ly]`, x fastest, scaled to Σ w² = nx·ny.
    pub fn radial(self, [nx, ny]: [usize; 2], [lx, ly]: [f64; 2]) -> Vec<f64> {
        let maxr = lx.min(ly) / 2.0;
        let mut w = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            let y = ly * (j as f64 - (ny / 2) as f64) / ny as f64;
            for i in 0..nx {
                let x = lx * (i as f64 - (nx / 2) as f64) / nx as f64;
                w.push(self.shape((x * x + y * y).sqrt() / maxr));
            }
        }
        normalised(w, nx * ny)
    }
}

fn normalised(mut w: Vec<f64>, n: usize) -> Vec<f64> {
    let s2: f64 = w.iter().map(|v| v * v).sum();
    if s2 > 0.0 {
        let k = (n as f64 / s2).sqrt();
        w.iter_mut().for_each(|v| *v *= k);
    }
    w
}

/// The modified Bessel function I₀ by its power series (converges for every
/// x; 60 terms reach double precision for the β ≤ 50 a window uses).
fn bessel_i0(x: f64) -> f64 {
    let q = x * x / 4.0;
    let (mut term, mut sum) = (1.0, 1.0);
    for k in 1..200 {
        term *= q / (k * k) as f64;
        sum += term;
        if term < sum * 1e-17 {
            break;
        }
    }
    sum
}

/// `h` multiplied by `w` (same layout).
pub fn apply(h: &HeightField, w: &[f64]) -> HeightField {
    let mut out = h.clone();
    out.data_mut().iter_mut().zip(w).for_each(|(z, w)| *z *= w);
    out
}

/// The rms jump across the field's edges (last row to first, last column to
/// first) over the rms step between neighbours, the larger of the x and y
/// ratios (see the module docs). `None` for fields under 4 samples a side or
/// without any step.
pub fn edge_ratio(h: &HeightField) -> Option<f64> {
    let [nx, ny] = h.dims();
    let ratio = |jump2: f64, n_jump: usize, step2: f64, n_step: usize| {
        (step2 > 0.0).then(|| ((jump2 / n_jump as f64) / (step2 / n_step as f64)).sqrt())
    };
    if nx < 4 {
        return None;
    }
    let (mut jx, mut sx) = (0.0, 0.0);
    for j in 0..ny {
        let r = h.row(j);
        jx += (r[0] - r[nx - 1]).powi(2);
        sx += r.windows(2).map(|w| (w[1] - w[0]).powi(2)).sum::<f64>();
    }
    let rx = ratio(jx, ny, sx, ny * (nx - 1))?;
    if ny == 1 {
        return Some(rx);
    }
    if ny < 4 {
        return None;
    }
    let (mut jy, mut sy) = (0.0, 0.0);
    for i in 0..nx {
        jy += (h.row(0)[i] - h.row(ny - 1)[i]).powi(2);
    }
    for j in 0..ny - 1 {
        sy += h
            .row(j)
            .iter()
            .zip(h.row(j + 1))
            .map(|(a, b)| (b - a).powi(2))
            .sum::<f64>();
    }
    let ry = ratio(jy, nx, sy, nx * (ny - 1)).unwrap_or(rx);
    Some(rx.max(ry))
}

/// Edge ratios below this count as periodic (see the module docs).
pub const PERIODIC_BELOW: f64 = 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_are_normalised_and_shaped() {
        for w in [Window::Hann, Window::BlackmanHarris, Window::Kaiser(8.6)] {
            let p = w.profile(64);
            let s2: f64 = p.iter().map(|v| v * v).sum();
            assert!((s2 - 64.0).abs() < 1e-9, "{w:?}");
            assert!(p[0].abs() < 0.05 * p[32], "{w:?} vanishes at the edge");
            let r = w.radial([32, 16], [2.0, 1.0]);
            assert!((r.iter().map(|v| v * v).sum::<f64>() - 512.0).abs() < 1e-9);
        }
        // scipy.signal.get_window('hann', 8) = 0.5 − 0.5 cos(2πk/8), before scaling.
        let h = Window::Hann.profile(8);
        let raw: Vec<f64> = (0..8)
            .map(|k| 0.5 - 0.5 * (std::f64::consts::TAU * k as f64 / 8.0).cos())
            .collect();
        let k = (8.0 / raw.iter().map(|v| v * v).sum::<f64>()).sqrt();
        for (a, b) in h.iter().zip(&raw) {
            assert!((a - b * k).abs() < 1e-12);
        }
        // I₀(1) = 1.2660658777520082 (Abramowitz & Stegun 9.8).
        assert!((bessel_i0(1.0) - 1.266_065_877_752_008_2).abs() < 1e-15);
        assert_eq!(Window::from_name("kaiser:5"), Some(Window::Kaiser(5.0)));
        assert_eq!(Window::from_name("kaiser:-1"), None);
        assert_eq!(Window::from_name("hamming"), None);
    }

    #[test]
    fn edge_ratio_tells_a_torus_from_a_crop() {
        use asperity_core::fourier_surface::FourierParams;
        for hurst in [0.2, 0.8] {
            let p = FourierParams {
                n: 256,
                hurst,
                modes: 128,
                rms: 1.0,
                spacing: 1.0,
            };
            let torus =
                crate::synthesis::fbm(&p, 3, &asperity_core::MemoryBudget::unlimited()).unwrap();
            let ratio = edge_ratio(&torus).unwrap();
            assert!(ratio < 1.3, "H = {hurst}: {ratio}");
            let crop = HeightField::from_vec(
                [128, 128],
                (0..128 * 128)
                    .map(|k| *torus.get(k % 128 + 40, k / 128 + 70))
                    .collect(),
            )
            .unwrap();
            let ratio = edge_ratio(&crop).unwrap();
            assert!(ratio > 1.5 * PERIODIC_BELOW, "H = {hurst}: {ratio}");
        }
    }
}
