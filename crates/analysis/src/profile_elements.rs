//! Profile elements (ISO 21920-2:2021 §3.3 and 4.2; ISO 4287:1997 §3.2.19,
//! 4.3.1 and 4.4.1): the mean width Rsm and the mean height Rc of the
//! elements of a profile.
//!
//! A *profile element* is a profile peak and the valley that follows it; a
//! peak is the part of the profile above the mean line between two of its
//! crossings, a valley the part below. The crossings are found by linear
//! interpolation between samples. A part counts as a peak (valley) only if
//! its height (depth) reaches the *height discrimination*, 10 % of the
//! profile's Rz (here Rp + Rv over the whole profile), and its width the
//! *width discrimination*, 1 % of the sampling length (ISO 4287 §3.2.19's
//! defaults), the sampling length being a fifth of the evaluation length (ISO
//! 4288's five sampling lengths): a part below either is joined to the part
//! before it, and neighbouring parts of the same sign join into one.
//!
//! Rsm is the mean width of the complete elements: the distance from the first
//! to the last crossing where a valley gives way to a peak, over the number of
//! elements between them (a sinusoid gives its wavelength). Rc is the mean of
//! peak height + valley depth over the same elements. A profile without two
//! such crossings has neither.

/// A part of the profile between two crossings of the mean line.
#[derive(Clone, Copy, Debug)]
struct Part {
    /// Where it starts (the interpolated crossing), in samples.
    start: f64,
    /// +1 above the mean line, −1 below.
    sign: f64,
    /// Its extreme distance from the mean line (≥ 0).
    extreme: f64,
}

/// The mean width and the mean height of the profile elements of `z`
/// (samples `step` apart, about its own mean): (Rsm, Rc), or `None` with
/// fewer than one complete element.
pub fn mean_width_and_height(z: &[f64], step: f64) -> Option<(f64, f64)> {
    if z.len() < 3 {
        return None;
    }
    let mean = z.iter().sum::<f64>() / z.len() as f64;
    let z: Vec<f64> = z.iter().map(|v| v - mean).collect();
    let (lo, hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let height_min = 0.1 * (hi - lo);
    let width_min = 0.01 * (z.len() - 1) as f64 / 5.0;
    let parts = significant(parts(&z), z.len() - 1, height_min, width_min);
    // elements: from one valley-to-peak crossing to the next
    let rises: Vec<usize> = (1..parts.len())
        .filter(|&k| parts[k].sign > 0.0 && parts[k - 1].sign < 0.0)
        .collect();
    let (first, last) = (*rises.first()?, *rises.last()?);
    if first == last {
        return None;
    }
    let elements = rises.len() - 1;
    let width = (parts[last].start - parts[first].start) * step / elements as f64;
    let heights: f64 = parts[first..last].iter().map(|p| p.extreme).sum();
    Some((width, heights / elements as f64))
}

/// The parts of `z` between its crossings of 0 (a sample at exactly 0 counts
/// as below the mean line).
fn parts(z: &[f64]) -> Vec<Part> {
    let sign = |v: f64| if v > 0.0 { 1.0 } else { -1.0 };
    let mut out = vec![Part {
        start: 0.0,
        sign: sign(z[0]),
        extreme: z[0].abs(),
    }];
    for i in 1..z.len() {
        let s = sign(z[i]);
        let current = out.last_mut().expect("a part");
        if s == current.sign {
            current.extreme = current.extreme.max(z[i].abs());
        } else {
            // the crossing between samples i − 1 and i
            let at = (i - 1) as f64 + z[i - 1] / (z[i - 1] - z[i]);
            out.push(Part {
                start: at,
                sign: s,
                extreme: z[i].abs(),
            });
        }
    }
    out
}

/// The parts that pass the height and width discrimination, each with the
/// parts after it that do not joined to it; parts of the same sign joined.
fn significant(parts: Vec<Part>, end: usize, height_min: f64, width_min: f64) -> Vec<Part> {
    let mut out: Vec<Part> = Vec::with_capacity(parts.len());
    for (k, p) in parts.iter().enumerate() {
        let next = parts.get(k + 1).map_or(end as f64, |n| n.start);
        let passes = p.extreme >= height_min && next - p.start >= width_min;
        match out.last_mut() {
            // the same sign: one part
            Some(last) if last.sign == p.sign => last.extreme = last.extreme.max(p.extreme),
            // too small: joined to the part before it
            Some(_) if !passes => {}
            _ if passes => out.push(*p),
            _ => {}
        }
    }
    out
}

/// Rmr(c) in %: the length of the piecewise-linear profile `z` above height
/// `c` over its length (with `periodic`, the step from the last sample back
/// to the first counts too).
pub fn material_length_ratio(z: &[f64], c: f64, periodic: bool) -> f64 {
    let above = |a: f64, b: f64| -> f64 {
        let (lo, hi) = (a.min(b), a.max(b));
        if lo >= c {
            1.0
        } else if hi <= c {
            0.0
        } else {
            (hi - c) / (hi - lo)
        }
    };
    let mut length: f64 = z.windows(2).map(|w| above(w[0], w[1])).sum();
    let mut steps = z.len().saturating_sub(1);
    if periodic && z.len() > 1 {
        length += above(z[z.len() - 1], z[0]);
        steps += 1;
    }
    if steps == 0 {
        return if z.first().is_some_and(|&v| v >= c) {
            100.0
        } else {
            0.0
        };
    }
    100.0 * length / steps as f64
}

/// Rmc(mr): the height at which [`material_length_ratio`] is `mr` % (the
/// highest such height), by bisection to the heights' rounding.
pub fn height_at_length_ratio(z: &[f64], mr: f64, periodic: bool) -> f64 {
    let (mut lo, mut hi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if material_length_ratio(z, mid, periodic) >= mr {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// A sinusoid's elements are its periods: Rsm = λ, Rc = 2A, for a
    /// wavelength that is no whole number of samples.
    #[test]
    fn a_sinusoid_gives_its_wavelength_and_twice_its_amplitude() {
        let (lambda, a, step) = (37.3, 1.7, 0.25);
        let z: Vec<f64> = (0..4000)
            .map(|i| a * (TAU * i as f64 * step / lambda + 0.3).sin())
            .collect();
        let (rsm, rc) = mean_width_and_height(&z, step).unwrap();
        assert!((rsm - lambda).abs() < 1e-6 * lambda, "Rsm {rsm}");
        // the samples' extremes fall within (π step/λ)² A/2 of the peaks
        assert!((rc - 2.0 * a).abs() < 2e-4 * a, "Rc {rc}");
    }

    /// Ripples below the height discrimination do not make elements, nor do
    /// crossings narrower than the width discrimination.
    #[test]
    fn small_ripples_are_discriminated() {
        let (lambda, step) = (100.0, 1.0);
        let z: Vec<f64> = (0..2001)
            .map(|i| {
                let x = i as f64 * step;
                (TAU * x / lambda).sin() + 0.05 * (TAU * x / 7.0).sin()
            })
            .collect();
        let (rsm, _) = mean_width_and_height(&z, step).unwrap();
        assert!((rsm - lambda).abs() < 0.02 * lambda, "Rsm {rsm}");
        let noisy: Vec<f64> = z
            .iter()
            .enumerate()
            .map(|(i, v)| v + if i % 2 == 0 { 1e-3 } else { -1e-3 })
            .collect();
        let (rsm, _) = mean_width_and_height(&noisy, step).unwrap();
        assert!(
            (rsm - lambda).abs() < 0.02 * lambda,
            "Rsm {rsm} with sample noise"
        );
        assert!(mean_width_and_height(&[0.0, 1.0, 0.0, -1.0], 1.0).is_none());
    }

    /// A triangle wave is its own linear interpolation: Rmr(c) is exact, and
    /// on a sinusoid it is within the interpolation's O(step²).
    #[test]
    fn the_material_length_ratio_is_the_length_above_c() {
        let tri: Vec<f64> = (0..=400)
            .map(|i| 1.0 - ((i % 100) as f64 - 50.0).abs() / 25.0)
            .collect();
        for c in [-0.5, 0.0, 0.25, 0.99] {
            let want = 100.0 * (1.0 - c) / 2.0;
            assert!(
                (material_length_ratio(&tri, c, false) - want).abs() < 1e-12,
                "c {c}"
            );
            let back = height_at_length_ratio(&tri, want, false);
            assert!((back - c).abs() < 1e-12, "Rmc({want}) = {back}, not {c}");
        }
        let sine: Vec<f64> = (0..10_000)
            .map(|i| (TAU * i as f64 / 1000.0).sin())
            .collect();
        let want = 50.0 - 100.0 * 0.5f64.asin() / std::f64::consts::PI;
        // the chords cross c = 0.5 within k·tan(π/6)/8 ≈ 4.5e-4 steps of the sine
        let got = material_length_ratio(&sine, 0.5, true);
        assert!(
            (got - want).abs() < 1.2e-4 && (got - want).abs() > 1e-6,
            "{got} vs {want}"
        );
        assert_eq!(material_length_ratio(&sine, 2.0, true), 0.0);
        assert_eq!(material_length_ratio(&sine, -2.0, true), 100.0);
    }
}
