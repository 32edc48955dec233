//! The texture direction Std (ISO 25178-2 §4.3.4): the angle at which the
//! angular amplitude spectrum f_AAD(θ) — the amplitude |Z(q)| of the height
//! field's Fourier transform summed over the wave vectors q of direction θ —
//! is largest. θ is the wave vector's angle, counter-clockwise from +x with y
//! along the field's rows (row index increasing), folded into [0°, 180°):
//! a lay of ridges running along y has Std = 0°.
//!
//! The spectrum is [`PowerSpectrum`]'s half grid (each stored mode k_x > 0
//! stands for itself and its mirror −q, which has the same direction), in
//! bins of [`STEP_DEG`] (surfalize's default). Angles use physical
//! frequencies, so unequal spacings give the true direction. The spectrum
//! `analyze` reads is windowed for non-periodic data, which keeps the edges'
//! leakage (a cross along the axes) from pulling Std to 0° or 90°. Std means
//! something only for a surface with a lay (Str well below 1).

use serde::Serialize;

use crate::spectrum::PowerSpectrum;

/// The width of an angular bin, in degrees.
pub const STEP_DEG: f64 = 0.5;

/// Std and the angular amplitude spectrum it is read from.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[allow(non_snake_case)]
pub struct TextureDirection {
    /// The texture direction, degrees in [0, 180): the lower edge of the largest bin.
    pub Std: f64,
    /// f_AAD in each bin (bin k covers [k, k + 1) · [`STEP_DEG`]).
    pub amplitude: Vec<f64>,
}

/// Std of the field whose spectrum is `s`; `None` for a constant field.
pub fn texture_direction(s: &PowerSpectrum) -> Option<TextureDirection> {
    let [nx, ny] = s.dims;
    let [dx, dy] = s.spacing;
    let half = s.half_width();
    let bins = (180.0 / STEP_DEG).round() as usize;
    let mut amplitude = vec![0.0; bins];
    for j in 0..ny {
        // the signed wavenumber of row j (FFT order)
        let ky = if 2 * j < ny {
            j as f64
        } else {
            j as f64 - ny as f64
        };
        let fy = ky / (ny as f64 * dy);
        for kx in 0..half {
            if kx == 0 && j == 0 {
                continue;
            }
            let fx = kx as f64 / (nx as f64 * dx);
            let theta = fy.atan2(fx).to_degrees().rem_euclid(180.0);
            let bin = ((theta / STEP_DEG) as usize).min(bins - 1);
            amplitude[bin] += s.multiplicity(kx) as f64 * s.power[j * half + kx].sqrt();
        }
    }
    let (best, peak) = amplitude
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (k, a)| if *a > b.1 { (k, *a) } else { b });
    (peak > 0.0).then_some(TextureDirection {
        Std: best as f64 * STEP_DEG,
        amplitude,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use asperity_core::HeightField;
    use rand::{Rng, SeedableRng, rngs::StdRng};

    /// Ridges whose wave vector points at a drawn angle, on a periodic grid
    /// (whole periods) with noise: Std is that angle, to a bin.
    #[test]
    fn the_direction_of_a_lay_is_its_wave_vectors() {
        let mut rng = StdRng::seed_from_u64(rand::random());
        let n = 256;
        for (px, py) in [(8i32, 0i32), (0, 8), (7, 4), (3, 9), (-5, 6), (12, -2)] {
            let data = (0..n * n)
                .map(|k| {
                    let (x, y) = ((k % n) as f64, (k / n) as f64);
                    let phase =
                        2.0 * std::f64::consts::PI * (px as f64 * x + py as f64 * y) / n as f64;
                    phase.cos() + 0.3 * rng.random_range(-1.0..1.0)
                })
                .collect();
            let h = HeightField::from_vec([n, n], data).unwrap();
            let d = texture_direction(&PowerSpectrum::of(&h, None)).unwrap();
            let want = (py as f64).atan2(px as f64).to_degrees().rem_euclid(180.0);
            let off = (d.Std - want)
                .rem_euclid(180.0)
                .min((want - d.Std).rem_euclid(180.0));
            assert!(off <= STEP_DEG, "({px}, {py}): Std {} vs {want}", d.Std);
        }
    }

    /// Unequal spacings: the direction is the physical one.
    #[test]
    fn unequal_spacings_give_the_physical_direction() {
        let (nx, ny, dx, dy) = (200, 100, 0.5, 1.0);
        // one period over each side: a wave vector (1/100, 1/100) per unit length, 45°
        let data = (0..nx * ny)
            .map(|k| {
                let (x, y) = ((k % nx) as f64 * dx, (k / nx) as f64 * dy);
                (2.0 * std::f64::consts::PI * (x + y) / 100.0).cos()
            })
            .collect();
        let h = HeightField::from_vec([nx, ny], data)
            .unwrap()
            .with_spacing([dx, dy])
            .unwrap();
        let d = texture_direction(&PowerSpectrum::of(&h, None)).unwrap();
        assert!((d.Std - 45.0).abs() <= STEP_DEG, "{}", d.Std);
    }
}
