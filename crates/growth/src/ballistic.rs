//! Ballistic deposition, BD, with nearest-neighbour sticking (Vold 1959; the
//! KPZ-class model behind the weathering references of kim-machiraju-thompson
//! §2 and §4.1).
//!
//! A particle falls down its column and sticks at the **first contact**: the cell
//! above the column's top, or a cell level with the top of a taller nearest
//! neighbour, whichever it meets first. With h the number of the top-most
//! occupied cell plus one:
//!
//! h_i ← max(h_i + 1, max_{j ∈ nn(i)} h_j),
//!
//! the same rule as Gwyddion's ballistic-deposition module. The cells skipped
//! below a lateral contact stay empty, so the deposit is porous (density ≈ 0.47 in
//! 1+1D). Expected exponents (Barabási & Stanley ch. 6; Kelling et al. 2016):
//! β = 1/3, α = 1/2 in 1+1D; β ≈ 0.241, α ≈ 0.39 in 2+1D — reachable at
//! accessible times only after the intrinsic width is removed (see
//! [`crate::interface_width`]).

use crate::lattice::{Landing, Lattice, Rule};
use crate::rng::FastRng;

/// The BD rule.
#[derive(Clone, Copy, Debug, Default)]
pub struct Bd;

impl Rule for Bd {
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
        let (nb, k) = lattice.neighbours(x, y);
        let mut tallest = 0;
        for &j in &nb[..k] {
            tallest = tallest.max(heights[j]);
        }
        let old = heights[i];
        let z = old.max(tallest.saturating_sub(1));
        heights[i] = z + 1;
        Landing { column: i, old, z }
    }
}
