//! Accumulating an evolution into a height field.
//!
//! Paper: [peridier] §"Cellular Automaton Basics" and Figure 3: "these
//! individual cellular automaton evolution steps are summed, cell by cell, to
//! give the elevations for the surface". `FacetSurfaceGridData` does this with
//! `Nest` and `CellularAutomaton`.
//!
//! z(i, j) = Σ_(t = t₀…T) w_t · v(state_t(i, j)), with t₀ = 0 when step 0 (the
//! initial grid) counts (the default) and 1 otherwise, weights w_t = 1 unless
//! given (e.g. geometric decay w_t = rᵗ), and state values v(s) = s unless given
//! (k-colour rules).
//!
//! # Deviations from the paper
//! None in the result. The fast path (two states, cyclic, any width, unit weights and
//! values) keeps the running sum in bit-sliced counters (one
//! bit plane per binary digit of the count, 64 cells per word), so accumulation
//! costs a few word operations per 64 cells and step instead of 64 additions.
//!
//! [peridier]: https://www.mathematica-journal.com/2011/07/facetsurface-representation/ "Peridier: Rough-Surface Simulation and the Visualization of Nonsmooth Arrays of Data. The Mathematica Journal, 2011"

use asperity_core::{Grid2, HeightField, MemoryBudget, NoProgress, Progress, seeded};
use rand::Rng;
use rayon::prelude::*;

use crate::CaError;
use crate::evolve::{BitGrid, Boundary, step_bytes, step_infinite};
use crate::rule::Rule;

/// Per-step weights of the accumulation.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Weights {
    /// Every step counts 1.
    #[default]
    Uniform,
    /// Step t counts rᵗ.
    Geometric(f64),
    /// Step t counts the t-th value (one per step 0…T).
    Explicit(Vec<f64>),
}

/// Parameters of [`evolve_and_accumulate`].
#[derive(Clone, Debug, PartialEq)]
pub struct CaParams {
    /// The rule.
    pub rule: Rule,
    /// Number of steps T (≥ 1).
    pub steps: usize,
    /// Cyclic grid or infinite background.
    pub boundary: Boundary,
    /// Whether the initial grid (step 0) is part of the sum. Default: true.
    pub include_step0: bool,
    /// Step weights. Default: uniform.
    pub weights: Weights,
    /// Height contributed by each state (k entries). Default: the state itself.
    pub values: Option<Vec<f64>>,
    /// Keep every step (for `--states-out` and step images).
    pub keep_states: bool,
}

impl CaParams {
    /// Defaults for `rule` and `steps`: cyclic, step 0 counted, uniform weights.
    pub fn new(rule: Rule, steps: usize) -> Self {
        Self {
            rule,
            steps,
            boundary: Boundary::Cyclic,
            include_step0: true,
            weights: Weights::Uniform,
            values: None,
            keep_states: false,
        }
    }
}

/// The evolution's result.
#[derive(Clone, Debug, PartialEq)]
pub struct CaOutput {
    /// The accumulated heights (grid row j = array row j).
    pub heights: HeightField,
    /// Every step 0…T on the final region, if kept: `(T+1) × ny × nx` states.
    pub states: Option<Vec<u8>>,
}

/// The initial grid of a run.
#[derive(Clone, Debug, PartialEq)]
pub enum Init {
    /// One cell in state 1: alone on an infinite background, or at the centre
    /// (⌊nx/2⌋, ⌊ny/2⌋) of a sized grid.
    Seed,
    /// Each cell non-zero with probability `density` (state uniform in 1…k−1).
    Random {
        /// Probability of a non-zero cell.
        density: f64,
        /// Random seed.
        seed: u64,
    },
    /// An explicit grid (states), e.g. from an image or a `.npy` file.
    Grid(Grid2<u8>),
}

/// Builds the initial grid: `size` is `[nx, ny]` (needed except for a seed on an
/// infinite background, and a grid that brings its own size).
///
/// # Errors
/// [`CaError::BadInit`] for a missing or zero size, a density outside [0, 1], or
/// states ≥ k.
pub fn initial_grid(
    init: &Init,
    size: Option<[usize; 2]>,
    k: u8,
    budget: &MemoryBudget,
) -> Result<Grid2<u8>, CaError> {
    if let Some(s) = size
        && s.contains(&0)
    {
        return Err(CaError::BadInit(format!(
            "grid size {}×{} has a zero side",
            s[0], s[1]
        )));
    }
    let g = match init {
        Init::Seed => match size {
            None => Grid2::from_vec([1, 1], vec![1])?,
            Some([nx, ny]) => {
                let mut g = Grid2::try_filled([nx, ny], 0u8, budget)?;
                *g.get_mut(nx / 2, ny / 2) = 1;
                g
            }
        },
        Init::Random { density, seed } => {
            if !(0.0..=1.0).contains(density) {
                return Err(CaError::BadInit(format!(
                    "density must be in [0, 1], got {density}"
                )));
            }
            let [nx, ny] = size.ok_or_else(|| {
                CaError::BadInit("a random initial grid needs ⟨size⟩ (WxH)".into())
            })?;
            let mut g = Grid2::try_filled([nx, ny], 0u8, budget)?;
            let mut rng = seeded(*seed);
            for v in g.data_mut() {
                if rng.random::<f64>() < *density {
                    *v = if k == 2 { 1 } else { rng.random_range(1..k) };
                }
            }
            g
        }
        Init::Grid(g) => g.clone(),
    };
    if let Some(bad) = g.data().iter().find(|&&v| v >= k) {
        return Err(CaError::BadInit(format!(
            "initial grid has state {bad}, but the rule has {k} states"
        )));
    }
    Ok(g)
}

fn weight(w: &Weights, t: usize) -> f64 {
    match w {
        Weights::Uniform => 1.0,
        Weights::Geometric(r) => r.powi(t as i32),
        Weights::Explicit(v) => v[t],
    }
}

fn check(p: &CaParams) -> Result<(), CaError> {
    if p.steps == 0 {
        return Err(CaError::BadInit("steps must be at least 1".into()));
    }
    if let Weights::Explicit(v) = &p.weights
        && (v.len() != p.steps + 1 || v.iter().any(|x| !x.is_finite()))
    {
        return Err(CaError::BadInit(format!(
            "need {} finite step weights (steps 0…{}), got {}",
            p.steps + 1,
            p.steps,
            v.len()
        )));
    }
    if let Weights::Geometric(r) = p.weights
        && !r.is_finite()
    {
        return Err(CaError::BadInit(format!("decay ratio {r} is not finite")));
    }
    if let Some(v) = &p.values
        && (v.len() != p.rule.states() as usize || v.iter().any(|x| !x.is_finite()))
    {
        return Err(CaError::BadInit(format!(
            "need {} finite state values, got {}",
            p.rule.states(),
            v.len()
        )));
    }
    Ok(())
}

/// Refuses, with its estimate, a run of `p` from an initial grid of `dims` that
/// the budget cannot hold; returns the evolution's grid size (grown by 2T a side
/// on an infinite background). Callers may check before building the initial
/// grid itself.
///
/// # Errors
/// [`CaError::Core`] with the estimate.
pub fn check_memory(
    dims: [usize; 2],
    p: &CaParams,
    budget: &MemoryBudget,
) -> Result<[usize; 2], CaError> {
    let grow = if p.boundary == Boundary::Infinite {
        p.steps.saturating_mul(2)
    } else {
        0
    };
    let (nx, ny) = (dims[0].saturating_add(grow), dims[1].saturating_add(grow));
    let cells = nx as u128 * ny as u128;
    // Two state buffers + heights (f64), plus every step if kept.
    let kept = if p.keep_states {
        (p.steps as u128 + 1) * cells
    } else {
        0
    };
    budget.check_elements(
        cells * 10 + kept,
        1,
        &format!("a {nx}×{ny} evolution of {} steps", p.steps),
    )?;
    Ok([nx, ny])
}

/// Evolves `init` for `p.steps` steps and accumulates the heights.
///
/// # Errors
/// [`CaError`] for bad parameters; [`CaError::Core`] with the estimate when the
/// grids would exceed `budget`.
pub fn evolve_and_accumulate(
    init: &Grid2<u8>,
    p: &CaParams,
    budget: &MemoryBudget,
    progress: &dyn Progress,
) -> Result<CaOutput, CaError> {
    check(p)?;
    check_memory(init.dims(), p, budget)?;
    progress.start(p.steps as u64, "evolving");
    let fast = p.rule.states() == 2
        && p.boundary == Boundary::Cyclic
        && p.weights == Weights::Uniform
        && p.values.is_none()
        && !p.keep_states;
    let out = if fast {
        accumulate_bits(init, p, progress)
    } else {
        accumulate_bytes(init, p, progress)
    };
    progress.finish();
    Ok(out)
}

fn accumulate_bytes(init: &Grid2<u8>, p: &CaParams, progress: &dyn Progress) -> CaOutput {
    let [mut cx, mut cy] = init.dims();
    let grow = if p.boundary == Boundary::Infinite {
        2 * p.steps
    } else {
        0
    };
    let (nx, ny) = (cx + grow, cy + grow);
    let values: Vec<f64> = p
        .values
        .clone()
        .unwrap_or_else(|| (0..p.rule.states()).map(f64::from).collect());
    let mut heights = vec![0.0f64; nx * ny];
    let mut states = p
        .keep_states
        .then(|| Vec::with_capacity((p.steps + 1) * nx * ny));
    let mut cur = init.data().to_vec();
    let mut next = vec![0u8; cur.len()];
    let mut background = 0u8;
    for t in 0..=p.steps {
        // Embed the current region (cx × cy) centred in the final frame.
        let off = (grow - (cx - init.nx())) / 2;
        let w = weight(&p.weights, t);
        let counts = t > 0 || p.include_step0;
        if counts || states.is_some() {
            let mut frame_row = vec![background; nx];
            for j in 0..ny {
                let inside = j >= off && j < off + cy;
                frame_row.fill(background);
                if inside {
                    frame_row[off..off + cx].copy_from_slice(&cur[(j - off) * cx..][..cx]);
                }
                if counts {
                    for (h, &s) in heights[j * nx..][..nx].iter_mut().zip(&frame_row) {
                        *h += w * values[s as usize];
                    }
                }
                if let Some(st) = states.as_mut() {
                    st.extend_from_slice(&frame_row);
                }
            }
        }
        if t == p.steps {
            break;
        }
        match p.boundary {
            Boundary::Cyclic => {
                step_bytes(&p.rule, &cur, &mut next, cx, cy);
                std::mem::swap(&mut cur, &mut next);
            }
            Boundary::Infinite => {
                let (grown, gx, gy, b) = step_infinite(&p.rule, &cur, cx, cy, background);
                (cur, cx, cy, background) = (grown, gx, gy, b);
            }
        }
        progress.advance(1);
    }
    CaOutput {
        heights: HeightField::from_vec([nx, ny], heights).expect("sizes agree"),
        states,
    }
}

fn accumulate_bits(init: &Grid2<u8>, p: &CaParams, progress: &dyn Progress) -> CaOutput {
    let [nx, ny] = init.dims();
    let mut cur = BitGrid::from_bytes(init.data(), nx, ny);
    let mut next = cur.clone();
    // Bit-sliced counters: planes[word * P + b] holds bit b of 64 cells' counts.
    let planes = (usize::BITS - (p.steps + 1).leading_zeros()) as usize;
    let mut counters = vec![0u64; cur.bits.len() * planes];
    let add_words = |c: &mut [u64], words: &[u64]| {
        for (k, &w) in words.iter().enumerate() {
            let mut carry = w;
            for plane in &mut c[k * planes..(k + 1) * planes] {
                if carry == 0 {
                    break;
                }
                let t = *plane & carry;
                *plane ^= carry;
                carry = t;
            }
        }
    };
    let add = |counters: &mut [u64], grid: &BitGrid| {
        if grid.bits.len() < crate::evolve::SEQUENTIAL_WORDS {
            add_words(counters, &grid.bits);
            return;
        }
        counters
            .par_chunks_mut(planes * 4096)
            .zip(grid.bits.par_chunks(4096))
            .for_each(|(c, words)| add_words(c, words));
    };
    if p.include_step0 {
        add(&mut counters, &cur);
    }
    for _ in 0..p.steps {
        cur.step_into(&p.rule, &mut next);
        std::mem::swap(&mut cur, &mut next);
        add(&mut counters, &cur);
        progress.advance(1);
    }
    let words = cur.words;
    let heights: Vec<f64> = counters
        .par_chunks(planes * words)
        .flat_map_iter(|row| {
            (0..nx).map(move |i| {
                let c = &row[(i / 64) * planes..][..planes];
                c.iter()
                    .enumerate()
                    .map(|(pl, &w)| ((w >> (i % 64) & 1) << pl) as f64)
                    .sum::<f64>()
            })
        })
        .collect();
    CaOutput {
        heights: HeightField::from_vec([nx, ny], heights).expect("sizes agree"),
        states: None,
    }
}

/// [`evolve_and_accumulate`] without progress reporting.
///
/// # Errors
/// As [`evolve_and_accumulate`].
pub fn accumulate(
    init: &Grid2<u8>,
    p: &CaParams,
    budget: &MemoryBudget,
) -> Result<CaOutput, CaError> {
    evolve_and_accumulate(init, p, budget, &NoProgress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rule::Family;
    use rand::Rng;

    #[test]
    fn bit_counters_equal_the_byte_path_on_any_width() {
        // Giving the state values explicitly (the same 0 and 1) forces the byte
        // path; the heights must agree exactly, spare bits of the last word
        // counting nothing.
        let mut rng = asperity_core::seeded(4);
        for (nx, ny) in [(100, 37), (64, 9), (3, 70)] {
            let cells: Vec<u8> = (0..nx * ny).map(|_| rng.random_range(0..2)).collect();
            let init = Grid2::from_vec([nx, ny], cells).unwrap();
            let rule = Rule::new(Family::Totalistic9, 2, 450).unwrap();
            let fast = CaParams::new(rule.clone(), 12);
            let mut slow = fast.clone();
            slow.values = Some(vec![0.0, 1.0]);
            let budget = MemoryBudget::unlimited();
            let a = accumulate(&init, &fast, &budget).unwrap();
            let b = accumulate(&init, &slow, &budget).unwrap();
            assert_eq!(a.heights.data(), b.heights.data(), "{nx}x{ny}");
            assert!(a.heights.data().iter().any(|&h| h > 0.0));
        }
    }
}
