//! Random deposition with surface relaxation, RDSR (kim-machiraju-thompson §4.1,
//! Fig. 3(b); the Family model, Family 1986): "the deposited particle diffuses
//! along the surface up to a finite distance, stopping when it finds the
//! position with the lowest height".
//!
//! **Rule.** A particle dropped on column i considers the columns within
//! Manhattan distance `radius` of i (periodic). Radius 1 is Family's model: i and
//! its 2 (1+1D) or 4 (2+1D) nearest neighbours.
//!
//! **Tie rule.** If column i is among the lowest candidates the particle stays on
//! i. Otherwise it settles on the lowest candidate nearest to i (Manhattan
//! distance); several such columns are chosen between uniformly at random. The
//! tie rule changes amplitudes, not exponents.
//!
//! The deposit is compact (no overhangs). It belongs to the Edwards–Wilkinson
//! class: β = 1/4, α = 1/2 in 1+1D; in 2+1D (the critical dimension) W² grows
//! like ln t and W²_sat like ln L (Barabási & Stanley ch. 5).

use crate::lattice::{Landing, Lattice, Rule};
use crate::rng::{FastRng, below};

/// The RDSR rule with its relaxation neighbourhood.
#[derive(Clone, Debug)]
pub struct Rdsr {
    radius: u32,
    /// (dx, dy, distance) within the radius, excluding (0, 0), by distance.
    offsets: Vec<(isize, isize, u32)>,
}

impl Rdsr {
    /// The rule for relaxation `radius` (≥ 1) on a `dim`-dimensional substrate.
    pub fn new(radius: u32, dim: usize) -> Self {
        let r = radius as isize;
        let mut offsets = Vec::new();
        for dy in if dim == 2 { -r..=r } else { 0..=0 } {
            for dx in -r..=r {
                let d = (dx.abs() + dy.abs()) as u32;
                if d >= 1 && d <= radius {
                    offsets.push((dx, dy, d));
                }
            }
        }
        offsets.sort_by_key(|o| o.2);
        Self { radius, offsets }
    }
}

impl Rule for Rdsr {
    #[inline(always)]
    fn deposit(
        &self,
        lattice: &Lattice,
        heights: &mut [u32],
        x: usize,
        y: usize,
        rng: &mut FastRng,
    ) -> Landing {
        let i = lattice.index(x, y);
        let here = heights[i];
        let target = if self.radius == 1 {
            let (nb, k) = lattice.neighbours(x, y);
            let mut low = u32::MAX;
            for &j in &nb[..k] {
                low = low.min(heights[j]);
            }
            if here <= low {
                i
            } else {
                let mut best = [0usize; 4];
                let mut m = 0;
                for &j in &nb[..k] {
                    if heights[j] == low {
                        best[m] = j;
                        m += 1;
                    }
                }
                if m == 1 {
                    best[0]
                } else {
                    best[below(rng, m as u64) as usize]
                }
            }
        } else {
            let col = |&(dx, dy, _): &(isize, isize, u32)| {
                lattice.index(lattice.wrap(x, dx), lattice.wrap(y, dy))
            };
            let low = self
                .offsets
                .iter()
                .map(|o| heights[col(o)])
                .min()
                .unwrap_or(u32::MAX);
            if here <= low {
                i
            } else {
                // Nearest ring holding a lowest column, then uniform within it.
                let ring = self
                    .offsets
                    .iter()
                    .find(|o| heights[col(o)] == low)
                    .map(|o| o.2)
                    .expect("low is attained");
                let best: Vec<usize> = self
                    .offsets
                    .iter()
                    .filter(|o| o.2 == ring)
                    .map(col)
                    .filter(|&j| heights[j] == low)
                    .collect();
                best[below(rng, best.len() as u64) as usize]
            }
        };
        let z = heights[target];
        heights[target] = z + 1;
        Landing {
            column: target,
            old: z,
            z,
        }
    }
}
