//! The periodic substrate lattice and the rule a deposition model implements on
//! it, after [kim-machiraju-thompson] §4.1: a d-dimensional substrate (d = 1 or
//! 2) of L^d columns with periodic boundaries, on which every model (RD, RDSR,
//! BD) drops particles one column at a time.
//!
//! The models live in [`crate::random_deposition`], [`crate::rdsr`] and
//! [`crate::ballistic`]; the driver that runs them is [`crate::deposition`].
//!
//! [kim-machiraju-thompson]: https://doi.org/10.1007/978-3-662-07443-5 "Kim, Machiraju, Thompson: Modeling Rough Surfaces. In Geometric Modeling for Scientific Visualization, Springer 2004, pp. 123-138"

use serde::Serialize;

use crate::GrowthError;
use crate::error::bad;
use crate::rng::FastRng;

/// A periodic substrate of `length` columns per side in `dim` (1 or 2) dimensions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Lattice {
    /// L, columns per side.
    pub length: usize,
    /// d, the substrate dimension (1 for 1+1D, 2 for 2+1D).
    pub dim: usize,
}

impl Lattice {
    /// A lattice of side `length` in `dim` dimensions.
    ///
    /// # Errors
    /// [`GrowthError::BadParameter`] unless `dim` is 1 or 2 and `length` ≥ 2.
    pub fn new(length: usize, dim: usize) -> Result<Self, GrowthError> {
        if dim != 1 && dim != 2 {
            return Err(bad(format!(
                "substrate dimension must be 1 or 2, got {dim}"
            )));
        }
        if length < 2 {
            return Err(bad(format!(
                "substrate size must be at least 2 columns, got {length}"
            )));
        }
        if length > (1 << 24) || (dim == 2 && length > (1 << 15)) {
            return Err(bad(format!(
                "substrate size {length} is too large (at most 16777216 in 1+1D, 32768 in 2+1D)"
            )));
        }
        Ok(Self { length, dim })
    }

    /// N = L^d.
    pub fn columns(&self) -> usize {
        self.length.pow(self.dim as u32)
    }

    /// Column index of (x, y).
    #[inline(always)]
    pub fn index(&self, x: usize, y: usize) -> usize {
        x + self.length * y
    }

    /// `x + dx` with periodic wrap (|dx| < L).
    #[inline(always)]
    pub fn wrap(&self, x: usize, dx: isize) -> usize {
        let l = self.length as isize;
        let v = x as isize + dx;
        (if v < 0 {
            v + l
        } else if v >= l {
            v - l
        } else {
            v
        }) as usize
    }

    /// The nearest-neighbour columns of (x, y): 2 in 1+1D, 4 in 2+1D
    /// (order: −x, +x, −y, +y).
    #[inline(always)]
    pub fn neighbours(&self, x: usize, y: usize) -> ([usize; 4], usize) {
        let xm = self.wrap(x, -1);
        let xp = self.wrap(x, 1);
        if self.dim == 1 {
            ([xm, xp, 0, 0], 2)
        } else {
            let ym = self.wrap(y, -1);
            let yp = self.wrap(y, 1);
            (
                [
                    self.index(xm, y),
                    self.index(xp, y),
                    self.index(x, ym),
                    self.index(x, yp),
                ],
                4,
            )
        }
    }
}

/// A deposition model's rule: where a particle dropped on a column ends up.
pub trait Rule: Send + Sync {
    /// Drops a particle on column (x, y) of `heights`, applies the model,
    /// updates the column that grew (its height becomes z + 1) and says where
    /// the particle landed.
    fn deposit(
        &self,
        lattice: &Lattice,
        heights: &mut [u32],
        x: usize,
        y: usize,
        rng: &mut FastRng,
    ) -> Landing;
}

/// Where a deposited particle came to rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Landing {
    /// The column that grew.
    pub column: usize,
    /// Its height before the deposit.
    pub old: u32,
    /// The particle's cell height (0-based); the column's height is now z + 1.
    pub z: u32,
}
