//! Self-affine test surfaces (`generate fbm`): fractional Brownian surfaces by
//! Fourier filtering with random phases, the surfaces of known Hurst exponent
//! that the analysis is checked on (Jacobs, Junge & Pastewka 2017, §2.3; the
//! synthesis of `asperity_analysis::synthesis`).

use asperity_core::fourier_surface::FourierParams;
use asperity_core::{HeightField, MemoryBudget};
use clap::Args;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::params::JobParams;

/// A periodic self-affine (fBm) height field by Fourier synthesis
/// (`generate fbm`): a power-law spectrum C(q) ∝ q^−2(1+H) with random phases.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema, Args)]
#[serde(default)]
pub struct FbmParams {
    /// Samples per side N (an N×N field).
    #[schemars(range(min = 2, max = 1_048_576))]
    #[arg(long, default_value_t = Self::DEFAULT.size)]
    pub size: usize,
    /// Hurst exponent H in (0, 1] (fractal dimension 3 − H).
    #[schemars(extend("exclusiveMinimum" = 0.0), range(max = 1.0))]
    #[arg(long, default_value_t = Self::DEFAULT.hurst)]
    pub hurst: f64,
    /// Root-mean-square height.
    #[schemars(range(min = 0.0, max = 1e12))]
    #[arg(long, default_value_t = Self::DEFAULT.rms)]
    pub rms: f64,
    /// Sample spacing (the field is periodic with period N × spacing).
    #[schemars(range(max = 1e12), extend("exclusiveMinimum" = 0.0))]
    #[arg(long, default_value_t = Self::DEFAULT.spacing)]
    pub spacing: f64,
}

impl FbmParams {
    /// The defaults every front end shows.
    pub const DEFAULT: Self = Self {
        size: 256,
        hurst: 0.8,
        rms: 1.0,
        spacing: 1.0,
    };

    /// The title of the field written (where the format has one).
    pub fn title(&self) -> String {
        format!("fBm H={}", self.hurst)
    }
}

impl Default for FbmParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl JobParams for FbmParams {
    const JOB: &'static str = "generate fbm";
}

/// The field of `p` from `seed` (the FFT synthesis, O(N² log N); the same
/// field as the core's direct sum).
///
/// # Errors
/// The parameters' ([`crate::params::validate`]) and the memory budget.
pub fn fbm(p: &FbmParams, seed: u64, budget: &MemoryBudget) -> Result<HeightField> {
    crate::params::validate(p)?;
    let fourier = FourierParams {
        n: p.size,
        hurst: p.hurst,
        modes: p.size / 2,
        rms: p.rms,
        spacing: p.spacing,
    };
    Ok(asperity_analysis::synthesis::fbm(&fourier, seed, budget)?)
}
