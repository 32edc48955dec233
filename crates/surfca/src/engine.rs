//! The general surface-CA engine (gobron-chiba, Appendix 2): a state per cell,
//! a transition rule supplied through [`Rule`], synchronous updates (every cell
//! reads the previous step), both cores used (rayon over cells), and randomness
//! from a counter-based generator keyed by (seed, step, cell) — so the result is
//! the same bytes for any thread count. A run stops after N steps or when no cell
//! changes, and records per step how many cells changed and how many are in each
//! state class (the paper's Figures 16 and 23).

use rayon::prelude::*;

use crate::cells::Cells;

/// A counter-based random stream for one (seed, step, cell): SplitMix64 over a
/// hash of the key. Cheap to create, independent of scheduling.
#[derive(Clone, Debug)]
pub struct CellRng {
    state: u64,
    key: [u64; 3],
    ready: bool,
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl CellRng {
    /// The stream of `cell` at `step` (hashed on first use, so rules that draw
    /// nothing pay nothing).
    pub fn new(seed: u64, step: u64, cell: u64) -> Self {
        Self {
            state: 0,
            key: [seed, step, cell],
            ready: false,
        }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        if !self.ready {
            let [seed, step, cell] = self.key;
            let k = mix(seed ^ 0x9e37_79b9_7f4a_7c15);
            let k = mix(k ^ step.wrapping_mul(0xd1b5_4a32_d192_ed03));
            self.state = mix(k ^ cell.wrapping_mul(0x8cb9_2ba7_2f3d_8dd7));
            self.ready = true;
        }
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        mix(self.state)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform integer in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        ((self.next_u64() as u128 * n as u128) >> 64) as usize
    }
}

/// What a rule sees when it updates one cell.
pub struct View<'a, S> {
    /// The cell structure.
    pub cells: &'a Cells,
    /// Every cell's state at the previous step.
    pub states: &'a [S],
    /// The step being computed (1 for the first update).
    pub step: u64,
}

/// A transition rule.
pub trait Rule: Sync {
    /// The state of one cell.
    type State: Clone + PartialEq + Send + Sync;

    /// The new state of `cell` from the previous step's states.
    fn next(&self, cell: usize, view: &View<'_, Self::State>, rng: &mut CellRng) -> Self::State;

    /// Names of the state classes counted per step (default: none).
    fn classes(&self) -> &[&'static str] {
        &[]
    }

    /// The class of a state, an index into [`Rule::classes`].
    fn class(&self, _state: &Self::State) -> usize {
        0
    }
}

/// How long to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunOptions {
    /// Random seed.
    pub seed: u64,
    /// Step limit.
    pub max_steps: u64,
    /// Stop at the first step that changes no cell.
    pub stop_when_stable: bool,
}

/// Per-step record.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StepStats {
    /// Step number (1-based).
    pub step: u64,
    /// Cells whose state changed.
    pub changed: u64,
    /// Fraction of cells per class (area-weighted), in [`Rule::classes`] order.
    pub class_fraction: Vec<f64>,
}

/// A finished run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RunStats {
    /// Steps performed.
    pub steps: u64,
    /// Whether the run stopped because nothing changed.
    pub stable: bool,
    /// One entry per step.
    pub per_step: Vec<StepStats>,
}

/// Cells per parallel task: fixed, so sums are added in the same order whatever
/// the thread count.
const CHUNK: usize = 4096;

/// One synchronous step: `next` receives the new states (update and change count
/// in one parallel pass over fixed chunks), then the buffers are swapped so
/// `states` holds them.
pub fn step<R: Rule>(
    cells: &Cells,
    rule: &R,
    states: &mut Vec<R::State>,
    next: &mut Vec<R::State>,
    seed: u64,
    step: u64,
) -> StepStats {
    let view = View {
        cells,
        states,
        step,
    };
    let k = rule.classes().len();
    // Per chunk: cells changed and area per class of the new states, added in
    // chunk order afterwards (the same sums at any thread count).
    let parts: Vec<(u64, Vec<f64>)> = next
        .par_chunks_mut(CHUNK)
        .enumerate()
        .map(|(chunk, out)| {
            let base = chunk * CHUNK;
            let mut changed = 0u64;
            let mut area = vec![0.0; k];
            for (i, slot) in out.iter_mut().enumerate() {
                let c = base + i;
                *slot = rule.next(c, &view, &mut CellRng::new(seed, step, c as u64));
                changed += u64::from(*slot != view.states[c]);
                if k > 0 {
                    area[rule.class(slot).min(k - 1)] += cells.area[c];
                }
            }
            (changed, area)
        })
        .collect();
    std::mem::swap(states, next);
    let mut changed = 0;
    let mut area = vec![0.0; k];
    for (c, a) in parts {
        changed += c;
        for (x, y) in area.iter_mut().zip(a) {
            *x += y;
        }
    }
    let total = cells.total_area;
    StepStats {
        step,
        changed,
        class_fraction: area.iter().map(|x| x / total).collect(),
    }
}

/// Runs `rule` on `states` (one per cell) synchronously. `on_step(step, states)`
/// is called after every step (for frames, progress); return `false` to stop.
pub fn run<R: Rule>(
    cells: &Cells,
    rule: &R,
    states: &mut Vec<R::State>,
    opts: &RunOptions,
    mut on_step: impl FnMut(u64, &[R::State]) -> bool,
) -> RunStats {
    assert_eq!(states.len(), cells.len(), "one state per cell");
    let mut per_step = Vec::new();
    let mut stable = false;
    let mut step = 0;
    let mut next = states.clone();
    while step < opts.max_steps {
        step += 1;
        let st = self::step(cells, rule, states, &mut next, opts.seed, step);
        let changed = st.changed;
        per_step.push(st);
        let go_on = on_step(step, states);
        if changed == 0 && opts.stop_when_stable {
            stable = true;
            break;
        }
        if !go_on {
            break;
        }
    }
    RunStats {
        steps: step,
        stable,
        per_step,
    }
}
