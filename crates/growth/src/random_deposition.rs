//! Random deposition, RD (kim-machiraju-thompson §4.1, Fig. 3(a)): "from a
//! randomly chosen site over the surface, a particle drops vertically until it
//! reaches the top of the column under it, whereupon it is deposited".
//!
//! Columns are independent, so each height is Binomial(n, 1/N) after n
//! depositions on N columns and the width is known exactly (Barabási & Stanley
//! ch. 4): ⟨W²⟩ = t (1 − 1/N) with t = n/N monolayers; β = 1/2, no saturation.

use crate::lattice::{Landing, Lattice, Rule};
use crate::rng::FastRng;

/// The RD rule: the particle lands on top of its own column.
#[derive(Clone, Copy, Debug, Default)]
pub struct Rd;

impl Rule for Rd {
    #[inline(always)]
    fn deposit(
        &self,
        lattice: &Lattice,
        heights: &mut [u32],
        x: usize,
        y: usize,
        _rng: &mut FastRng,
    ) -> Landing {
        let i = lattice.index(x, y);
        let z = heights[i];
        heights[i] = z + 1;
        Landing {
            column: i,
            old: z,
            z,
        }
    }
}
