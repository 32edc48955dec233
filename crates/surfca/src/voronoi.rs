//! Surface Voronoi diagrams by regular probabilistic growth (gobron-chiba,
//! "3D Surface Voronoi Diagram", Figures 13–17).
//!
//! Every site starts as one labelled cell. An unlabelled cell takes a label when a
//! side neighbour has one (propagation 100 %, ties broken at random), otherwise
//! each labelled corner neighbour passes its label with probability P. The
//! paper's Figure 14 interpolates between the square (P = 1) and the lozenge
//! (P = 0) to get P = √2/2 − ½ ≈ 20.71 % for a circular front; first-passage
//! percolation gives (√2 − 1)² ≈ 17.16 % for exact isotropy at large radii. The
//! default is the paper's value; both are exposed.

use crate::cells::{Cells, is_side};
use crate::engine::{CellRng, Rule, RunOptions, RunStats, View, run};

/// No label yet.
pub const UNLABELLED: u32 = u32::MAX;

/// The paper's diagonal probability √2/2 − ½.
pub const PAPER_P: f64 = std::f64::consts::FRAC_1_SQRT_2 - 0.5;

/// First-passage isotropic value (√2 − 1)².
pub const ISOTROPIC_P: f64 = (std::f64::consts::SQRT_2 - 1.0) * (std::f64::consts::SQRT_2 - 1.0);

/// The growth rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoronoiRule {
    /// Probability that a labelled corner neighbour passes its label.
    pub diagonal_p: f64,
}

impl Rule for VoronoiRule {
    type State = u32;

    fn next(&self, cell: usize, view: &View<'_, u32>, rng: &mut CellRng) -> u32 {
        let own = view.states[cell];
        if own != UNLABELLED {
            return own;
        }
        // A labelled side neighbour at random: count them, draw one, find it
        // (a cell at a vertex where many triangles meet can have many).
        let labelled_sides = || {
            view.cells
                .neighbours(cell)
                .filter(|&(n, k)| is_side(k) && view.states[n] != UNLABELLED)
                .map(|(n, _)| view.states[n])
        };
        let n_sides = labelled_sides().count();
        if n_sides > 0 {
            let pick = rng.below(n_sides);
            return labelled_sides().nth(pick).expect("pick is below the count");
        }
        for (n, _) in view.cells.neighbours(cell) {
            let l = view.states[n];
            if l != UNLABELLED && rng.uniform() < self.diagonal_p {
                return l;
            }
        }
        UNLABELLED
    }

    fn classes(&self) -> &[&'static str] {
        &["unlabelled", "labelled"]
    }

    fn class(&self, s: &u32) -> usize {
        usize::from(*s != UNLABELLED)
    }
}

/// `n` distinct cells drawn with probability proportional to their area.
pub fn random_sites(cells: &Cells, n: usize, seed: u64) -> Vec<usize> {
    let mut cum = Vec::with_capacity(cells.len());
    let mut acc = 0.0;
    for a in &cells.area {
        acc += a;
        cum.push(acc);
    }
    let n = n.min(cells.len());
    let mut out: Vec<usize> = Vec::with_capacity(n);
    let mut rng = CellRng::new(seed, u64::MAX, 0);
    while out.len() < n {
        let x = rng.uniform() * acc;
        let c = cum.partition_point(|&v| v <= x).min(cells.len() - 1);
        if !out.contains(&c) {
            out.push(c);
        }
    }
    out
}

/// The cell nearest to each point (3-D distance to cell centres).
pub fn sites_at(cells: &Cells, points: &[[f64; 3]]) -> Vec<usize> {
    points
        .iter()
        .map(|p| {
            (0..cells.len())
                .min_by(|&a, &b| {
                    let d = |c: usize| {
                        let q = cells.centre[c];
                        (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2)
                    };
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(0)
        })
        .collect()
}

/// Grows labels 0..sites.len() from `sites` until every reachable cell is labelled
/// (or `max_steps`). Returns the labels (UNLABELLED where growth never arrived).
pub fn voronoi(
    cells: &Cells,
    sites: &[usize],
    rule: &VoronoiRule,
    seed: u64,
    max_steps: u64,
    on_step: impl FnMut(u64, &[u32]) -> bool,
) -> (Vec<u32>, RunStats) {
    let mut states = vec![UNLABELLED; cells.len()];
    for (l, &c) in sites.iter().enumerate() {
        states[c] = l as u32;
    }
    let stats = run(
        cells,
        rule,
        &mut states,
        &RunOptions {
            seed,
            max_steps,
            stop_when_stable: true,
        },
        on_step,
    );
    (states, stats)
}

/// Share of the area (of cells on a sphere centred at the origin) whose label is
/// the exact spherical Voronoi region of the sites (largest cosine to the site
/// direction) — the gallery's check against the exact diagram.
pub fn spherical_agreement(cells: &Cells, sites: &[usize], labels: &[u32]) -> f64 {
    let unit = |p: [f64; 3]| {
        let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        [p[0] / n, p[1] / n, p[2] / n]
    };
    let dirs: Vec<[f64; 3]> = sites.iter().map(|&c| unit(cells.centre[c])).collect();
    let (mut agree, mut total) = (0.0, 0.0);
    for ((centre, area), &label) in cells.centre.iter().zip(&cells.area).zip(labels) {
        let p = unit(*centre);
        let cos = |q: [f64; 3]| q[0] * p[0] + q[1] * p[1] + q[2] * p[2];
        let best = (0..dirs.len())
            .max_by(|&a, &b| cos(dirs[a]).total_cmp(&cos(dirs[b])))
            .unwrap_or(0);
        total += area;
        if label as usize == best {
            agree += area;
        }
    }
    if total > 0.0 { agree / total } else { 0.0 }
}
