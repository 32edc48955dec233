//! The flat-substrate driver shared by RD, RDSR and BD: an L (1+1D) or L×L
//! (2+1D) periodic lattice of columns, particles dropped on uniformly random
//! columns, W² tracked incrementally and sampled on a schedule.
//!
//! Heights are `u32` per column (4 bytes per column whatever the thickness); the
//! width sums Σh and Σh² are updated in O(1) per deposition in exact integers, so
//! sampling W(t) costs nothing. Each model is a [`Rule`] (see
//! [`crate::random_deposition`], [`crate::rdsr`], [`crate::ballistic`]); the
//! driver is generic over it so the inner loop is monomorphised.

use asperity_core::{HeightField, MemoryBudget, PointSet, Progress};
use rayon::prelude::*;
use serde::Serialize;

use crate::error::bad;
use crate::interface_width::{WidthSeries, binned_width2, geometric_schedule};
use crate::lattice::{Landing, Lattice, Rule};
use crate::rng::{below, fast_rng};
use crate::{GrowthError, ballistic, random_deposition, rdsr};

/// The deposition models.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "model", rename_all = "lowercase")]
pub enum Model {
    /// Random deposition.
    Rd,
    /// Random deposition with surface relaxation within Manhattan `radius`.
    Rdsr {
        /// Relaxation radius in columns (1 is the Family model).
        radius: u32,
    },
    /// Ballistic deposition with nearest-neighbour sticking.
    Bd,
}

impl Model {
    /// Short name: `rd`, `rdsr`, `bd`.
    pub fn name(&self) -> &'static str {
        match self {
            Model::Rd => "rd",
            Model::Rdsr { .. } => "rdsr",
            Model::Bd => "bd",
        }
    }
}

/// What to simulate.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DepositionParams {
    /// The model.
    pub model: Model,
    /// The substrate.
    pub lattice: Lattice,
    /// Monolayers to deposit (T; depositions = round(T·N)).
    pub layers: f64,
    /// Width samples per decade of time (geometric schedule from t = 1).
    pub samples_per_decade: usize,
    /// Max-height binning side ε for a coarse-grained width (must divide L).
    pub bin: Option<usize>,
    /// Keep every particle's cell (x, y, z) in deposition order.
    pub keep_particles: bool,
}

impl DepositionParams {
    /// Defaults: 10 samples per decade, no binning, particles not kept.
    pub fn new(model: Model, lattice: Lattice, layers: f64) -> Self {
        Self {
            model,
            lattice,
            layers,
            samples_per_decade: 10,
            bin: None,
            keep_particles: false,
        }
    }

    /// Total number of depositions.
    pub fn depositions(&self) -> u64 {
        (self.layers * self.lattice.columns() as f64).round() as u64
    }

    /// Checks the parameters and the memory estimate.
    ///
    /// # Errors
    /// [`GrowthError::BadParameter`] or a memory-limit error.
    pub fn validate(&self, budget: &MemoryBudget) -> Result<(), GrowthError> {
        if !(self.layers.is_finite() && self.layers > 0.0) {
            return Err(bad(format!(
                "layers must be a positive number of monolayers, got {}",
                self.layers
            )));
        }
        if self.layers > 1e9 {
            return Err(bad(format!(
                "{} monolayers would overflow the 32-bit column heights (at most 1e9)",
                self.layers
            )));
        }
        if let Model::Rdsr { radius } = self.model {
            let max = (self.lattice.length / 2).max(1) as u32;
            if radius == 0 || radius > max {
                return Err(bad(format!(
                    "relaxation radius must be in 1..={max} for L = {}, got {radius}",
                    self.lattice.length
                )));
            }
        }
        if let Some(e) = self.bin
            && (e == 0 || !self.lattice.length.is_multiple_of(e))
        {
            return Err(bad(format!(
                "bin size ε = {e} must divide the substrate size L = {}",
                self.lattice.length
            )));
        }
        let mut bytes = self.lattice.columns() as u128 * 4;
        if self.keep_particles {
            bytes += self.depositions() as u128 * 12;
        }
        budget.check_elements(bytes, 1, "growth heights and particle list")?;
        Ok(())
    }
}

/// The result of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct Deposit {
    /// The substrate.
    pub lattice: Lattice,
    /// Final column heights (number of the top-most occupied cell plus one),
    /// x fastest.
    pub heights: Vec<u32>,
    /// W²(t) of this run.
    pub series: WidthSeries,
    /// Every particle's cell (x, y, z) in deposition order, when kept.
    pub particles: Option<Vec<[u32; 3]>>,
    /// Depositions made.
    pub depositions: u64,
}

impl Deposit {
    /// The heights as a height field (spacing 1; a 1+1D run is one row).
    pub fn height_field(&self) -> HeightField {
        let l = self.lattice.length;
        let ny = if self.lattice.dim == 1 { 1 } else { l };
        HeightField::from_vec([l, ny], self.heights.iter().map(|&h| h as f64).collect())
            .expect("dims match")
    }

    /// The occupied cells as points at their centres' integer coordinates
    /// (x, y, z): the kept particles in deposition order, or, for the compact
    /// RD/RDSR deposits, every cell below each column's height, column by column.
    pub fn point_set(&self) -> PointSet {
        let pts: Vec<[f64; 3]> = match &self.particles {
            Some(p) => p.iter().map(|c| c.map(|v| v as f64)).collect(),
            None => {
                let l = self.lattice.length;
                let mut out = Vec::with_capacity(self.heights.iter().map(|&h| h as usize).sum());
                for (i, &h) in self.heights.iter().enumerate() {
                    for z in 0..h {
                        out.push([(i % l) as f64, (i / l) as f64, z as f64]);
                    }
                }
                out
            }
        };
        PointSet::new(pts)
    }
}

/// Runs one simulation with the generator of run `run` under `seed`.
///
/// # Errors
/// Invalid parameters or the memory budget.
pub fn deposit(
    params: &DepositionParams,
    seed: u64,
    run: u64,
    budget: &MemoryBudget,
    progress: &dyn Progress,
) -> Result<Deposit, GrowthError> {
    params.validate(budget)?;
    let total = params.depositions();
    let schedule = geometric_schedule(
        params.lattice.columns() as u64,
        total,
        params.samples_per_decade,
    );
    Ok(deposit_on_schedule(params, seed, run, &schedule, progress))
}

/// Runs one simulation and samples W² after each deposition count in `schedule`
/// (increasing; the last entry is the run length). Parameters must be valid.
pub fn deposit_on_schedule(
    params: &DepositionParams,
    seed: u64,
    run: u64,
    schedule: &[u64],
    progress: &dyn Progress,
) -> Deposit {
    match params.model {
        Model::Rd => simulate(
            params,
            &random_deposition::Rd,
            seed,
            run,
            schedule,
            progress,
        ),
        Model::Rdsr { radius } => simulate(
            params,
            &rdsr::Rdsr::new(radius, params.lattice.dim),
            seed,
            run,
            schedule,
            progress,
        ),
        Model::Bd => simulate(params, &ballistic::Bd, seed, run, schedule, progress),
    }
}

fn simulate<R: Rule>(
    params: &DepositionParams,
    rule: &R,
    seed: u64,
    run: u64,
    schedule: &[u64],
    progress: &dyn Progress,
) -> Deposit {
    let lat = params.lattice;
    let n = lat.columns();
    let l = lat.length as u64;
    let total = schedule.last().copied().unwrap_or(0);
    let mut rng = fast_rng(seed, run);
    let mut heights = vec![0u32; n];
    let mut particles = params
        .keep_particles
        .then(|| Vec::with_capacity(total as usize));
    // Σh and Σh² in exact integers.
    let (mut s, mut s2) = (0u128, 0u128);
    let mut series = WidthSeries {
        runs: 1,
        ..WidthSeries::default()
    };
    progress.start(total, &format!("{} deposition", params.model.name()));
    let mut done = 0u64;
    for &target in schedule {
        while done < target {
            // Chunks of at most 2²⁰ depositions between progress reports.
            let stop = target.min(done + (1 << 20));
            for _ in done..stop {
                let x = below(&mut rng, l) as usize;
                let y = if lat.dim == 2 {
                    below(&mut rng, l) as usize
                } else {
                    0
                };
                let Landing {
                    column: col,
                    old,
                    z,
                } = rule.deposit(&lat, &mut heights, x, y, &mut rng);
                // The column went from `old` to z + 1 (old = z for RD/RDSR).
                let new = z as u128 + 1;
                let old = old as u128;
                s += new - old;
                s2 += new * new - old * old;
                if let Some(p) = particles.as_mut() {
                    p.push([(col % lat.length) as u32, (col / lat.length) as u32, z]);
                }
            }
            progress.advance(stop - done);
            done = stop;
        }
        let nn = n as u128;
        let w2 = (nn * s2 - s * s) as f64 / (n as f64 * n as f64);
        series.t.push(done as f64 / n as f64);
        series.w2.push(w2);
        series.w2_stderr.push(0.0);
        series.mean_height.push(s as f64 / n as f64);
        if let Some(e) = params.bin {
            series.w2_binned.push(binned_width2(&lat, &heights, e));
        }
    }
    progress.finish();
    Deposit {
        lattice: lat,
        heights,
        series,
        particles,
        depositions: done,
    }
}

/// The average of `runs` independent runs (run r uses generator r under `seed`),
/// computed in parallel; returns the first run's deposit and the averaged series.
///
/// # Errors
/// As [`deposit`], and `runs` = 0.
pub fn deposit_ensemble(
    params: &DepositionParams,
    seed: u64,
    runs: usize,
    budget: &MemoryBudget,
    progress: &dyn Progress,
) -> Result<(Deposit, WidthSeries), GrowthError> {
    if runs == 0 {
        return Err(bad("the number of runs must be at least 1"));
    }
    params.validate(budget)?;
    let total = params.depositions();
    let schedule = geometric_schedule(
        params.lattice.columns() as u64,
        total,
        params.samples_per_decade,
    );
    // Each thread's run holds its own heights, and every run's series is kept
    // for the average and its standard error: both estimated before any run.
    let lattices =
        (params.lattice.columns() as u128) * 4 * rayon::current_num_threads().min(runs) as u128;
    let series = runs as u128 * (schedule.len() as u128 * 4 * 8 + 128);
    budget.check_elements(
        lattices + series,
        1,
        &format!("the heights of the parallel runs and the width series of {runs} runs"),
    )?;
    progress.start(
        total * runs as u64,
        &format!("{} × {runs} runs", params.model.name()),
    );
    // Only the first run's deposit is kept; the others give their series and
    // drop their heights as they finish, so memory is the runs' series plus
    // one lattice per thread, not one lattice per run.
    let mut results: Vec<(Option<Deposit>, WidthSeries)> = (0..runs as u64)
        .into_par_iter()
        .map(|r| {
            let mut p = params.clone();
            p.keep_particles = params.keep_particles && r == 0;
            let mut d = deposit_on_schedule(&p, seed, r, &schedule, &asperity_core::NoProgress);
            progress.advance(total);
            let series = std::mem::take(&mut d.series);
            (if r == 0 { Some(d) } else { None }, series)
        })
        .collect();
    progress.finish();
    let mut first = results[0].0.take().expect("run 0 keeps its deposit");
    let series: Vec<WidthSeries> = results.into_iter().map(|(_, s)| s).collect();
    first.series = series[0].clone();
    let avg = WidthSeries::average(&series);
    Ok((first, avg))
}
