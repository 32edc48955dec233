//! Copper corrosion and patina (gobron-chiba, "Corrosion and Patina Generation",
//! Figures 18–23, Appendix I).
//!
//! Each cell is copper metal (weak or *strong*, i.e. resistant), corroded, or
//! non-existent (its metal is gone). Per step (Figure 19):
//! 1. **New seeds**: while fewer than `max_seeds` cells have been seeded, each
//!    existing metal cell starts corroding with probability `seed_rate`.
//! 2. **Attack and defence** (Appendix I, f₁ and f₂, in the synchronous "pull"
//!    form): a corroded cell o attacks n_a = f₁(age) of its n_vc valid (metal)
//!    neighbours, f₁ rising linearly from 1 to `max_attacked` (≤ 7, as the paper
//!    says) over `maturity` steps of age; a metal neighbour i is attacked with
//!    probability n_a/n_vc, weighted by a 3×3 Gaussian of the direction
//!    (sides 1, corners e^(−1/(2σ²)): "pseudo spot regions"), and falls when the
//!    attack, proportional to the attacker's age (`attack`·min(1, age/maturity)),
//!    beats its defence — `defence_strong` or `defence_weak`, raised by
//!    `neighbour_help` times the share of strong cells around it.
//! 3. **Growth of the layers**: a corroded cell loses `k1` of metal and gains `k2`
//!    of oxide, capped at `k3`; when its metal reaches 0 it becomes non-existent.
//!
//! Strong cells are drawn at random (`strong_fraction`) or from a smooth
//! value-noise field over the surface (`strong_noise_scale`).
//!
//! # Deviations from the paper
//!
//! **Oxide grows.** Appendix I writes S_ot(t + Δt) = S_ot(t) − k₂ for the oxide;
//! the text says the patina grows, and the cap k₃ only makes sense for growth, so
//! the oxide gains + k₂ here.

use crate::cells::{Cells, is_side};
use crate::engine::{CellRng, Rule, View};

/// What a cell is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Behaviour {
    /// Copper, not corroded.
    Metal,
    /// Corroding.
    Corroded,
    /// No metal left.
    NonExistent,
}

/// One cell of the corrosion CA (Figure 18).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CorrosionCell {
    /// Behaviour.
    pub behaviour: Behaviour,
    /// Resistant material.
    pub strong: bool,
    /// Metal thickness.
    pub metal: f32,
    /// Oxide (patina) thickness.
    pub oxide: f32,
    /// Steps since corrosion started.
    pub age: u32,
}

/// The constants, with defaults that give the green-patina look.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CorrosionParams {
    /// Initial metal thickness.
    pub metal: f32,
    /// Metal lost per corroded step (k₁).
    pub k1: f32,
    /// Oxide gained per corroded step (k₂).
    pub k2: f32,
    /// Oxide cap (k₃).
    pub k3: f32,
    /// Probability per step that a metal cell becomes a new seed.
    pub seed_rate: f64,
    /// Maximum number of seeds over the run.
    pub max_seeds: usize,
    /// Share of strong cells.
    pub strong_fraction: f64,
    /// If set, strong cells follow a value-noise field of this feature size
    /// (mesh units) instead of being independent.
    pub strong_noise_scale: Option<f64>,
    /// Most cells one corroded cell attacks per step (1–7).
    pub max_attacked: u32,
    /// Age at which an attacker reaches full strength.
    pub maturity: u32,
    /// Attack strength at maturity.
    pub attack: f64,
    /// Defence of a weak cell.
    pub defence_weak: f64,
    /// Defence of a strong cell.
    pub defence_strong: f64,
    /// Extra defence per unit share of strong neighbours.
    pub neighbour_help: f64,
    /// σ of the directional Gaussian (in cells).
    pub sigma: f64,
}

impl Default for CorrosionParams {
    fn default() -> Self {
        Self {
            metal: 1.0,
            k1: 0.0005,
            k2: 0.01,
            k3: 1.0,
            seed_rate: 2e-5,
            max_seeds: 400,
            strong_fraction: 0.35,
            strong_noise_scale: None,
            max_attacked: 4,
            maturity: 40,
            attack: 0.12,
            defence_weak: 0.35,
            defence_strong: 0.8,
            neighbour_help: 0.3,
            sigma: 1.0,
        }
    }
}

impl CorrosionParams {
    /// Checks ranges.
    ///
    /// # Errors
    /// A message naming the parameter.
    pub fn validate(&self) -> Result<(), String> {
        let pos = |v: f64, n: &str| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(format!("{n} must be finite and ≥ 0, got {v}"))
            }
        };
        pos(self.metal as f64, "metal")?;
        pos(self.k1 as f64, "k1")?;
        pos(self.k2 as f64, "k2")?;
        pos(self.k3 as f64, "k3")?;
        pos(self.attack, "attack")?;
        pos(self.defence_weak, "defence-weak")?;
        pos(self.defence_strong, "defence-strong")?;
        pos(self.neighbour_help, "neighbour-help")?;
        for (v, n) in [
            (self.seed_rate, "seed-rate"),
            (self.strong_fraction, "strong-fraction"),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(format!("{n} must be in [0, 1], got {v}"));
            }
        }
        if !(1..=7).contains(&self.max_attacked) {
            return Err(format!(
                "max-attacked must be 1..=7 (the paper's range), got {}",
                self.max_attacked
            ));
        }
        if self.maturity == 0 {
            return Err("maturity must be at least 1 step".into());
        }
        if !(self.sigma.is_finite() && self.sigma > 0.0) {
            return Err(format!("sigma must be positive, got {}", self.sigma));
        }
        if let Some(s) = self.strong_noise_scale
            && !(s.is_finite() && s > 0.0)
        {
            return Err(format!("strong-noise-scale must be positive, got {s}"));
        }
        Ok(())
    }
}

fn hash3(seed: u64, x: i64, y: i64, z: i64) -> f64 {
    let mut r = CellRng::new(seed, x as u64 ^ ((y as u64) << 21), z as u64);
    r.uniform()
}

/// Smooth value noise in [0, 1] (trilinear over a hashed lattice of `scale`).
fn value_noise(p: [f64; 3], scale: f64, seed: u64) -> f64 {
    let q = p.map(|x| x / scale);
    let f = q.map(f64::floor);
    let t = [q[0] - f[0], q[1] - f[1], q[2] - f[2]].map(|u| u * u * (3.0 - 2.0 * u));
    let (x, y, z) = (f[0] as i64, f[1] as i64, f[2] as i64);
    let mut v = 0.0;
    for dz in 0..2 {
        for dy in 0..2 {
            for dx in 0..2 {
                let w = (if dx == 1 { t[0] } else { 1.0 - t[0] })
                    * (if dy == 1 { t[1] } else { 1.0 - t[1] })
                    * (if dz == 1 { t[2] } else { 1.0 - t[2] });
                v += w * hash3(seed, x + dx, y + dy, z + dz);
            }
        }
    }
    v
}

/// The initial copper surface with its strong cells.
pub fn initial(cells: &Cells, p: &CorrosionParams, seed: u64) -> Vec<CorrosionCell> {
    (0..cells.len())
        .map(|c| {
            let strong = match p.strong_noise_scale {
                // The noise is ~uniform-ish in [0.2, 0.8]; threshold at the quantile
                // that gives about the requested share.
                Some(s) => value_noise(cells.centre[c], s, seed) < 0.2 + 0.6 * p.strong_fraction,
                None => CellRng::new(seed, u64::MAX - 1, c as u64).uniform() < p.strong_fraction,
            };
            CorrosionCell {
                behaviour: Behaviour::Metal,
                strong,
                metal: p.metal,
                oxide: 0.0,
                age: 0,
            }
        })
        .collect()
}

/// The transition rule (steps 2 and 3 above; seeding is done by [`corrode`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CorrosionRule {
    /// Constants.
    pub params: CorrosionParams,
}

impl CorrosionRule {
    fn strength(&self, age: u32) -> (f64, f64) {
        let p = &self.params;
        let m = (age as f64 / p.maturity as f64).min(1.0);
        let n_a = 1.0 + (p.max_attacked as f64 - 1.0) * m;
        (n_a, p.attack * m.max(1.0 / p.maturity as f64))
    }
}

impl Rule for CorrosionRule {
    type State = CorrosionCell;

    fn next(
        &self,
        cell: usize,
        view: &View<'_, CorrosionCell>,
        rng: &mut CellRng,
    ) -> CorrosionCell {
        let p = &self.params;
        let mut s = view.states[cell];
        match s.behaviour {
            Behaviour::NonExistent => s,
            Behaviour::Corroded => {
                s.metal -= p.k1;
                s.oxide = (s.oxide + p.k2).min(p.k3);
                s.age += 1;
                // (f32 steps of k₁ leave rounding crumbs: below 1e-6 is none.)
                if s.metal <= 1e-6 {
                    s.metal = 0.0;
                    s.behaviour = Behaviour::NonExistent;
                }
                s
            }
            Behaviour::Metal => {
                if !view
                    .cells
                    .neighbours(cell)
                    .any(|(n, _)| view.states[n].behaviour == Behaviour::Corroded)
                {
                    return s;
                }
                // Defence from the cell and its neighbourhood.
                let (mut strong, mut count) = (0usize, 0usize);
                for (n, _) in view.cells.neighbours(cell) {
                    count += 1;
                    strong += usize::from(view.states[n].strong);
                }
                let share = if count > 0 {
                    strong as f64 / count as f64
                } else {
                    0.0
                };
                let defence = if s.strong {
                    p.defence_strong
                } else {
                    p.defence_weak
                } + p.neighbour_help * share;
                let corner = (-1.0 / (2.0 * p.sigma * p.sigma)).exp();
                for (o, k) in view.cells.neighbours(cell) {
                    let a = view.states[o];
                    if a.behaviour != Behaviour::Corroded {
                        continue;
                    }
                    // The attacker's valid (metal) neighbours.
                    let n_vc = view
                        .cells
                        .neighbours(o)
                        .filter(|&(m, _)| view.states[m].behaviour == Behaviour::Metal)
                        .count()
                        .max(1);
                    let (n_a, attack) = self.strength(a.age);
                    let aim = (n_a / n_vc as f64).min(1.0) * if is_side(k) { 1.0 } else { corner };
                    if rng.uniform() < aim && attack * rng.uniform() > defence * rng.uniform() {
                        s.behaviour = Behaviour::Corroded;
                        return s;
                    }
                }
                s
            }
        }
    }

    fn classes(&self) -> &[&'static str] {
        &["metal", "corroded", "non-existent"]
    }

    fn class(&self, s: &CorrosionCell) -> usize {
        match s.behaviour {
            Behaviour::Metal => 0,
            Behaviour::Corroded => 1,
            Behaviour::NonExistent => 2,
        }
    }
}

/// Runs `steps` corrosion steps from `states` (from [`initial`]): new seeds, then
/// one synchronous CA step. Returns the per-step statistics.
pub fn corrode(
    cells: &Cells,
    params: &CorrosionParams,
    states: &mut Vec<CorrosionCell>,
    seed: u64,
    steps: u64,
    mut on_step: impl FnMut(u64, &[CorrosionCell]) -> bool,
) -> crate::engine::RunStats {
    let rule = CorrosionRule { params: *params };
    let mut seeded = states
        .iter()
        .filter(|s| s.behaviour != Behaviour::Metal)
        .count();
    let mut stats = crate::engine::RunStats {
        steps: 0,
        stable: false,
        per_step: Vec::new(),
    };
    let mut next = states.clone();
    for step in 1..=steps {
        // 1. New seeds (sequential, in cell order: deterministic).
        if seeded < params.max_seeds && params.seed_rate > 0.0 {
            for (c, s) in states.iter_mut().enumerate() {
                if seeded >= params.max_seeds {
                    break;
                }
                if s.behaviour == Behaviour::Metal
                    && CellRng::new(seed ^ 0x5eed, step, c as u64).uniform() < params.seed_rate
                {
                    s.behaviour = Behaviour::Corroded;
                    seeded += 1;
                }
            }
        }
        // 2–3. One CA step.
        let st = crate::engine::step(cells, &rule, states, &mut next, seed, step);
        stats.steps = step;
        stats.per_step.push(st);
        if !on_step(step, states) {
            break;
        }
    }
    stats
}
