//! A third application, to show the engine is general: Gray–Scott
//! reaction–diffusion on the cell structure (Pearson 1993; the surface-CA form of
//! Turk's and Witkin & Kass's texture-on-surface reaction–diffusion).
//!
//! u_t = D_u ∇²u − uv² + F(1 − u),  v_t = D_v ∇²v + uv² − (F + k)v,
//!
//! stepped explicitly with Δt = 1 on the cell graph: the Laplacian of a cell is
//! Σ_n w_n (x_n − x) / Σ_n w_n with side neighbours weighted 1 and corner
//! neighbours ¼ (Karl Sims' normalised 9-point kernel 0.2/0.05/−1), so D = 1
//! is the largest stable diffusion; it works unchanged across edges and
//! vertices because the links are symmetric. Seeds are patches where v = ½,
//! u = ½; spots, stripes or labyrinths grow from them depending on (F, k).

use crate::cells::{Cells, is_side};
use crate::engine::{CellRng, Rule, View};

/// Concentrations of one cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chemicals {
    /// Substrate u.
    pub u: f32,
    /// Activator v.
    pub v: f32,
}

/// The Gray–Scott constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrayScott {
    /// Diffusion of u (per step, in cell units).
    pub du: f32,
    /// Diffusion of v.
    pub dv: f32,
    /// Feed rate F.
    pub feed: f32,
    /// Kill rate k.
    pub kill: f32,
}

impl Default for GrayScott {
    /// Pearson's "spots" regime (F = 0.0367, k = 0.0649) with D_u = 1, D_v = ½.
    fn default() -> Self {
        Self {
            du: 1.0,
            dv: 0.5,
            feed: 0.0367,
            kill: 0.0649,
        }
    }
}

impl GrayScott {
    /// Checks ranges (explicit stepping needs D ≤ 1 with this kernel).
    ///
    /// # Errors
    /// A message naming the parameter.
    pub fn validate(&self) -> Result<(), String> {
        for (v, n) in [(self.du, "du"), (self.dv, "dv")] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(format!(
                    "{n} must be in [0, 1] for a stable explicit step, got {v}"
                ));
            }
        }
        for (v, n) in [(self.feed, "feed"), (self.kill, "kill")] {
            if !(v.is_finite() && (0.0..=0.2).contains(&v)) {
                return Err(format!("{n} must be in [0, 0.2], got {v}"));
            }
        }
        Ok(())
    }
}

impl Rule for GrayScott {
    type State = Chemicals;

    fn next(&self, cell: usize, view: &View<'_, Chemicals>, _rng: &mut CellRng) -> Chemicals {
        let c = view.states[cell];
        let (mut lu, mut lv, mut w) = (0.0f32, 0.0f32, 0.0f32);
        for (n, k) in view.cells.neighbours(cell) {
            let wk = if is_side(k) { 1.0 } else { 0.25 };
            let s = view.states[n];
            lu += wk * (s.u - c.u);
            lv += wk * (s.v - c.v);
            w += wk;
        }
        if w > 0.0 {
            lu /= w;
            lv /= w;
        }
        let uvv = c.u * c.v * c.v;
        Chemicals {
            u: (c.u + self.du * lu - uvv + self.feed * (1.0 - c.u)).clamp(0.0, 1.0),
            v: (c.v + self.dv * lv + uvv - (self.feed + self.kill) * c.v).clamp(0.0, 1.0),
        }
    }

    fn classes(&self) -> &[&'static str] {
        &["substrate", "activator"]
    }

    fn class(&self, s: &Chemicals) -> usize {
        usize::from(s.v > 0.2)
    }
}

/// The homogeneous state u = 1, v = 0 with `patches` seeded cells (and their
/// neighbours) set to u = v = ½, drawn with the counter-based generator.
pub fn seeded_state(cells: &Cells, patches: usize, seed: u64) -> Vec<Chemicals> {
    let mut s = vec![Chemicals { u: 1.0, v: 0.0 }; cells.len()];
    let sites = crate::voronoi::random_sites(cells, patches, seed ^ 0x6a7);
    for c in sites {
        s[c] = Chemicals { u: 0.5, v: 0.5 };
        for (n, _) in cells.neighbours(c) {
            s[n] = Chemicals { u: 0.5, v: 0.5 };
            for (m, _) in cells.neighbours(n) {
                s[m] = Chemicals { u: 0.5, v: 0.5 };
            }
        }
    }
    s
}
