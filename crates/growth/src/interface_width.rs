//! Interface width W(L, t) and its sampling schedule (kim-machiraju-thompson §4.1:
//! "the interface width … is defined by the root mean square fluctuation in the
//! surface height").
//!
//! Conventions (Barabási & Stanley, *Fractal Concepts in Surface Growth*, ch. 2):
//! - time t is in **monolayers**: depositions / number of columns;
//! - W²(t) = (1/N) Σ_i (h_i − h̄)² over the N = L^d columns, with h_i the number of
//!   the top-most occupied cell plus one (the column height for RD and RDSR, the
//!   top of a porous column for BD);
//! - over independent runs, **W² is averaged**, then the root taken.
//!
//! Max-height binning (Alves, Oliveira & Ferreira 2014) coarse-grains the surface
//! before the width is taken: the substrate is cut into ε (1+1D) or ε×ε (2+1D)
//! bins and each bin keeps its highest column. It removes the intrinsic width that
//! hides ballistic deposition's exponent at accessible times.

use serde::Serialize;

use crate::lattice::Lattice;

/// W²(t) sampled during one run, or averaged over several.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct WidthSeries {
    /// Times in monolayers.
    pub t: Vec<f64>,
    /// Squared interface width at each time (run average).
    pub w2: Vec<f64>,
    /// Standard error of `w2` over runs (0 for a single run).
    pub w2_stderr: Vec<f64>,
    /// Squared width after max-height binning (empty when binning is off).
    pub w2_binned: Vec<f64>,
    /// Mean height h̄ at each time.
    pub mean_height: Vec<f64>,
    /// Number of runs averaged.
    pub runs: usize,
}

impl WidthSeries {
    /// W(t) = √W²(t).
    pub fn width(&self) -> Vec<f64> {
        self.w2.iter().map(|v| v.sqrt()).collect()
    }

    /// The binned width √W²_binned(t) (empty when binning is off).
    pub fn width_binned(&self) -> Vec<f64> {
        self.w2_binned.iter().map(|v| v.sqrt()).collect()
    }

    /// Averages runs sampled at the same times (W² averaged, as the module docs say).
    ///
    /// # Panics
    /// If `runs` is empty or the runs were sampled at different times.
    pub fn average(runs: &[WidthSeries]) -> WidthSeries {
        let first = &runs[0];
        assert!(
            runs.iter().all(|r| r.t == first.t),
            "runs sampled at different times"
        );
        let n = runs.len() as f64;
        let mean = |f: &dyn Fn(&WidthSeries) -> &Vec<f64>| -> Vec<f64> {
            (0..f(first).len())
                .map(|k| runs.iter().map(|r| f(r)[k]).sum::<f64>() / n)
                .collect()
        };
        let w2 = mean(&|r| &r.w2);
        let w2_stderr = if runs.len() > 1 {
            (0..w2.len())
                .map(|k| {
                    let var =
                        runs.iter().map(|r| (r.w2[k] - w2[k]).powi(2)).sum::<f64>() / (n - 1.0);
                    (var / n).sqrt()
                })
                .collect()
        } else {
            vec![0.0; w2.len()]
        };
        WidthSeries {
            t: first.t.clone(),
            w2,
            w2_stderr,
            w2_binned: mean(&|r| &r.w2_binned),
            mean_height: mean(&|r| &r.mean_height),
            runs: runs.iter().map(|r| r.runs).sum(),
        }
    }
}

/// Deposition counts at which to sample: `per_decade` geometric steps from one
/// monolayer (N depositions) to `total`, plus `total` itself; duplicates removed.
pub fn geometric_schedule(columns: u64, total: u64, per_decade: usize) -> Vec<u64> {
    let mut out = Vec::new();
    let per_decade = per_decade.max(1) as f64;
    for k in 0.. {
        let t = 10f64.powf(k as f64 / per_decade);
        let count = (t * columns as f64).round() as u64;
        if count >= total {
            break;
        }
        if out.last() != Some(&count) {
            out.push(count);
        }
    }
    if total > 0 {
        out.push(total);
    }
    out
}

/// Deposition counts `samples` evenly spaced from `from` to `total` (both included).
pub fn uniform_schedule(from: u64, total: u64, samples: usize) -> Vec<u64> {
    let samples = samples.max(2) as u64;
    let mut out: Vec<u64> = (0..samples)
        .map(|k| from + (total - from.min(total)) * k / (samples - 1))
        .collect();
    out.dedup();
    out
}

/// W² of `heights` (N columns).
pub fn width2(heights: &[u32]) -> f64 {
    let n = heights.len() as f64;
    let (s, s2) = heights.iter().fold((0u128, 0u128), |(s, s2), &h| {
        (s + h as u128, s2 + (h as u128) * (h as u128))
    });
    let n_int = heights.len() as u128;
    // N·Σh² − (Σh)² is exact in integers; one division at the end.
    (n_int * s2 - s * s) as f64 / (n * n)
}

/// W² after max-height binning with bins of side `eps` (`eps` must divide L).
pub fn binned_width2(lattice: &Lattice, heights: &[u32], eps: usize) -> f64 {
    let l = lattice.length;
    let nb = l / eps;
    let bins: Vec<u32> = if lattice.dim == 1 {
        heights
            .chunks(eps)
            .map(|c| *c.iter().max().expect("eps ≥ 1"))
            .collect()
    } else {
        let mut b = vec![0u32; nb * nb];
        for y in 0..l {
            for x in 0..l {
                let k = x / eps + nb * (y / eps);
                b[k] = b[k].max(heights[x + l * y]);
            }
        }
        b
    };
    width2(&bins)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn width_of_known_heights() {
        // Heights 0, 2: mean 1, W² = 1.
        assert_eq!(width2(&[0, 2]), 1.0);
        assert_eq!(width2(&[5, 5, 5]), 0.0);
        // 0..4: variance of a discrete uniform = (n² − 1)/12 = 1.25.
        assert!((width2(&[0, 1, 2, 3]) - 1.25).abs() < 1e-15);
        let lat = Lattice::new(4, 1).unwrap();
        assert_eq!(binned_width2(&lat, &[0, 3, 1, 1], 2), 1.0);
        let lat = Lattice::new(2, 2).unwrap();
        assert_eq!(binned_width2(&lat, &[0, 3, 1, 1], 1), width2(&[0, 3, 1, 1]));
        assert_eq!(binned_width2(&lat, &[0, 3, 1, 1], 2), 0.0);
    }

    #[test]
    fn schedules() {
        let s = geometric_schedule(100, 100_000, 2);
        assert_eq!(s, vec![100, 316, 1000, 3162, 10000, 31623, 100_000]);
        assert_eq!(uniform_schedule(10, 20, 3), vec![10, 15, 20]);
        let w = WidthSeries::average(&[
            WidthSeries {
                t: vec![1.0],
                w2: vec![1.0],
                w2_stderr: vec![0.0],
                w2_binned: vec![],
                mean_height: vec![2.0],
                runs: 1,
            },
            WidthSeries {
                t: vec![1.0],
                w2: vec![3.0],
                w2_stderr: vec![0.0],
                w2_binned: vec![],
                mean_height: vec![4.0],
                runs: 1,
            },
        ]);
        assert_eq!(w.w2, vec![2.0]);
        assert_eq!(w.mean_height, vec![3.0]);
        assert!((w.w2_stderr[0] - 1.0).abs() < 1e-15);
        assert_eq!(w.runs, 2);
    }
}
