//! Dense regular 3-D grids: occupancy, distance fields, level sets.

use crate::grid2::check_spacing;
use crate::{CoreError, MemoryBudget};

/// Regular 3-D grid, x fastest: value (i, j, k) is `data[i + nx * (j + ny * k)]`
/// (libigl's marching-cubes convention) at `origin + (i·dx, j·dy, k·dz)`.
///
/// Big grids are bandwidth-bound, so users may store `f32`, `u8` or `bool`
/// instead of `f64`; they say so in their docs.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid3<T> {
    dims: [usize; 3],
    spacing: [f64; 3],
    origin: [f64; 3],
    data: Vec<T>,
}

/// Level-set φ or signed distance; φ < 0 inside.
pub type ScalarGrid = Grid3<f64>;
/// Occupancy (e.g. DLA clusters, voxelised substrates).
pub type VoxelGrid = Grid3<bool>;

impl<T: Clone> Grid3<T> {
    /// An `nx × ny × nz` grid of `value` with the given spacing and origin, after
    /// checking the dimensions and that it fits in `budget`.
    ///
    /// # Errors
    /// [`CoreError::GridSize`] for a zero dimension, [`CoreError::BadSpacing`],
    /// [`CoreError::MemoryLimit`] with the estimate when too large.
    pub fn try_new(
        dims: [usize; 3],
        spacing: [f64; 3],
        origin: [f64; 3],
        value: T,
        budget: &MemoryBudget,
    ) -> crate::Result<Self> {
        if dims.contains(&0) {
            return Err(CoreError::GridSize {
                dims: dims.to_vec(),
                expected: 0,
                got: 0,
            });
        }
        check_spacing(&spacing)?;
        let n = dims.iter().fold(1u128, |a, &d| a.saturating_mul(d as u128));
        let what = format!("a {}×{}×{} grid", dims[0], dims[1], dims[2]);
        budget.check_elements(n, size_of::<T>() as u64, &what)?;
        let n = usize::try_from(n).map_err(|_| CoreError::MemoryLimit {
            what,
            needed: u64::MAX,
            limit: budget.limit(),
            from: budget.source().describe(),
        })?;
        Ok(Self {
            dims,
            spacing,
            origin,
            data: vec![value; n],
        })
    }

    /// An `nx × ny × nz` grid of `value`, unit spacing, zero origin.
    ///
    /// # Panics
    /// If a dimension is zero; use [`Grid3::try_new`] for user-controlled sizes.
    pub fn filled(dims: [usize; 3], value: T) -> Self {
        Self::try_new(dims, [1.0; 3], [0.0; 3], value, &MemoryBudget::unlimited())
            .expect("non-zero grid dimensions")
    }
}

impl<T> Grid3<T> {
    /// Wraps `data` (x fastest) with the given geometry.
    ///
    /// # Errors
    /// [`CoreError::GridSize`] on a length mismatch, [`CoreError::BadSpacing`].
    pub fn from_vec(
        dims: [usize; 3],
        spacing: [f64; 3],
        origin: [f64; 3],
        data: Vec<T>,
    ) -> crate::Result<Self> {
        let expected = dims
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d))
            .unwrap_or(usize::MAX);
        if dims.contains(&0) || data.len() != expected {
            return Err(CoreError::GridSize {
                dims: dims.to_vec(),
                expected,
                got: data.len(),
            });
        }
        check_spacing(&spacing)?;
        Ok(Self {
            dims,
            spacing,
            origin,
            data,
        })
    }

    /// `[nx, ny, nz]`.
    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }
    /// `[dx, dy, dz]`.
    pub fn spacing(&self) -> [f64; 3] {
        self.spacing
    }
    /// Position of node (0, 0, 0).
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }
    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.data.len()
    }
    /// Always false: grids have at least one node.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
    /// The values, x fastest.
    pub fn data(&self) -> &[T] {
        &self.data
    }
    /// Mutable values, x fastest.
    pub fn data_mut(&mut self) -> &mut [T] {
        &mut self.data
    }
    /// Linear index of (i, j, k).
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        debug_assert!(i < self.dims[0] && j < self.dims[1] && k < self.dims[2]);
        i + self.dims[0] * (j + self.dims[1] * k)
    }
    /// (i, j, k) of a linear index.
    #[inline]
    pub fn coords(&self, index: usize) -> [usize; 3] {
        let [nx, ny, _] = self.dims;
        [index % nx, (index / nx) % ny, index / (nx * ny)]
    }
    /// Value at (i, j, k).
    ///
    /// # Panics
    /// If (i, j, k) is outside the grid.
    #[inline]
    pub fn get(&self, i: usize, j: usize, k: usize) -> &T {
        assert!(
            self.contains([i, j, k]),
            "({i}, {j}, {k}) outside {:?} grid",
            self.dims
        );
        &self.data[self.index(i, j, k)]
    }
    /// Mutable value at (i, j, k).
    ///
    /// # Panics
    /// If (i, j, k) is outside the grid.
    #[inline]
    pub fn get_mut(&mut self, i: usize, j: usize, k: usize) -> &mut T {
        assert!(
            self.contains([i, j, k]),
            "({i}, {j}, {k}) outside {:?} grid",
            self.dims
        );
        let idx = self.index(i, j, k);
        &mut self.data[idx]
    }
    /// Whether (i, j, k) is a node of the grid.
    #[inline]
    pub fn contains(&self, ijk: [usize; 3]) -> bool {
        ijk[0] < self.dims[0] && ijk[1] < self.dims[1] && ijk[2] < self.dims[2]
    }
    /// Physical position of node (i, j, k).
    pub fn position(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        let ijk = [i, j, k];
        [0, 1, 2].map(|a| self.origin[a] + ijk[a] as f64 * self.spacing[a])
    }
    /// A grid of the same geometry with `f` applied to every value.
    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> Grid3<U> {
        Grid3 {
            dims: self.dims,
            spacing: self.spacing,
            origin: self.origin,
            data: self.data.iter().map(f).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_and_geometry() {
        let mut g = Grid3::try_new(
            [4, 3, 2],
            [0.5, 0.5, 1.0],
            [1.0, 2.0, 3.0],
            0u8,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        *g.get_mut(3, 2, 1) = 7;
        assert_eq!(g.data()[3 + 4 * (2 + 3)], 7);
        assert_eq!(g.coords(g.index(3, 2, 1)), [3, 2, 1]);
        assert_eq!(g.position(3, 2, 1), [2.5, 3.0, 4.0]);
        assert!(!g.contains([4, 0, 0]));
    }

    #[test]
    fn refuses_big_grids_with_estimate() {
        let budget = MemoryBudget::new(1 << 30);
        let err =
            ScalarGrid::try_new([1024, 1024, 1024], [1.0; 3], [0.0; 3], 0.0, &budget).unwrap_err();
        assert_eq!(
            err,
            CoreError::MemoryLimit {
                what: "a 1024×1024×1024 grid".into(),
                needed: 8 << 30,
                limit: 1 << 30,
                from: "as given"
            }
        );
        assert!(err.to_string().contains("8.00 GiB"));
        assert!(VoxelGrid::try_new([0, 1, 1], [1.0; 3], [0.0; 3], false, &budget).is_err());
        assert!(VoxelGrid::try_new([1, 1, 1], [1.0, -1.0, 1.0], [0.0; 3], false, &budget).is_err());
        let huge = usize::MAX / 2;
        assert!(
            VoxelGrid::try_new([huge, huge, huge], [1.0; 3], [0.0; 3], false, &budget).is_err()
        );
    }
}
