//! Procedural detail functions d = F(p, l) (velho-perlin §3–4). So far: **rock**
//! (§4.2), the volumetric–fractal model — "it is only necessary to specify a
//! random value at every control point" of every level, with a 1/f amplitude:
//! the detail of vertex v at level l is A·decayˡ⁻¹·r(seed, l, v) along the local
//! normal, r uniform in [−1, 1] from a counter-based hash of (seed, level,
//! vertex index). Keys use each level's own vertex indices, so adding levels
//! never changes the coarser ones (stable under re-subdivision), and the result
//! is the same at any thread count.

/// Parameters of the rock detail.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rock {
    /// Displacement amplitude at level 1 (mesh units).
    pub amplitude: f64,
    /// Factor per level (½ = 1/f, fractal).
    pub decay: f64,
}

impl Default for Rock {
    fn default() -> Self {
        Self {
            amplitude: 0.08,
            decay: 0.5,
        }
    }
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Uniform in [−1, 1) keyed by (seed, level, vertex).
pub fn random_value(seed: u64, level: usize, vertex: usize) -> f64 {
    let h = mix(mix(seed ^ 0x726f_636b) ^ (level as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15))
        ^ (vertex as u64).wrapping_mul(0xd1b5_4a32_d192_ed03);
    let u = (mix(h) >> 11) as f64 / (1u64 << 53) as f64;
    2.0 * u - 1.0
}

impl Rock {
    /// Details (local frames: along n) for level `level` ≥ 1 with `n` vertices.
    pub fn details(&self, seed: u64, level: usize, n: usize) -> Vec<[f64; 3]> {
        let a = self.amplitude * self.decay.powi(level as i32 - 1);
        (0..n)
            .map(|v| [0.0, 0.0, a * random_value(seed, level, v)])
            .collect()
    }

    /// Checks the parameters.
    ///
    /// # Errors
    /// A message naming the bad parameter.
    pub fn validate(&self) -> Result<(), String> {
        if !self.amplitude.is_finite() {
            return Err(format!("amplitude must be finite, got {}", self.amplitude));
        }
        if !(self.decay.is_finite() && self.decay >= 0.0) {
            return Err(format!("decay must be finite and ≥ 0, got {}", self.decay));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rock_is_fractal_uniform_and_stable() {
        let r = Rock::default();
        let d1 = r.details(3, 1, 10_000);
        let d3 = r.details(3, 3, 10_000);
        let rms =
            |d: &[[f64; 3]]| (d.iter().map(|x| x[2] * x[2]).sum::<f64>() / d.len() as f64).sqrt();
        // Uniform on [−A, A]: rms A/√3; two levels down a quarter of it.
        assert!((rms(&d1) / (0.08 / 3f64.sqrt()) - 1.0).abs() < 0.03);
        assert!((rms(&d3) / rms(&d1) - 0.25).abs() < 0.02);
        assert_eq!(r.details(3, 1, 100), d1[..100].to_vec(), "stable");
        assert_ne!(r.details(4, 1, 100), d1[..100].to_vec(), "seeded");
        assert!(Rock { decay: -1.0, ..r }.validate().is_err());
    }
}
