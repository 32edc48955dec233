//! Regular 2-D grids and height fields.

use crate::{CoreError, MemoryBudget, PointSet, TriMesh, Units};

/// Regular 2-D grid, x fastest: value (i, j) is `data[i + nx * j]`, and
/// sample (i, j) sits at `origin + [i·spacing[0], j·spacing[1]]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid2<T> {
    dims: [usize; 2],
    spacing: [f64; 2],
    origin: [f64; 2],
    units: Units,
    data: Vec<T>,
}

/// Heights z(i, j) over the (x, y) plane, in the same length unit as the spacing.
pub type HeightField = Grid2<f64>;

/// Which diagonal splits each grid cell when a height field becomes triangles.
///
/// Cell (i, j) has corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Diagonal {
    /// Every cell split along a–c (the "/" diagonal in x-right, y-up view).
    #[default]
    Forward,
    /// Every cell split along b–d ("\").
    Backward,
    /// a–c where i + j is even, b–d where odd: the alternating-diagonal facets of
    /// peridier (Figure 7), where interior nodes belong to 4 or 8 triangles.
    Alternating,
}

pub(crate) fn check_spacing(spacing: &[f64]) -> crate::Result<()> {
    if spacing.iter().all(|s| s.is_finite() && *s > 0.0) {
        Ok(())
    } else {
        Err(CoreError::BadSpacing(spacing.to_vec()))
    }
}

impl Grid2<f64> {
    /// The field in `units`: where both the old and the new unit are lengths,
    /// the spacing and origin (xy) or the heights (z) are converted; a unitless
    /// side is only labelled.
    pub fn in_units(mut self, units: Units) -> Self {
        let factor =
            |from: crate::LengthUnit, to: crate::LengthUnit| match (from.metres(), to.metres()) {
                (Some(a), Some(b)) if a != b => Some(a / b),
                _ => None,
            };
        if let Some(k) = factor(self.units.xy, units.xy) {
            self.spacing = self.spacing.map(|v| v * k);
            self.origin = self.origin.map(|v| v * k);
        }
        if let Some(k) = factor(self.units.z, units.z) {
            self.data.iter_mut().for_each(|v| *v *= k);
        }
        self.units = units;
        self
    }
}

impl<T: Clone> Grid2<T> {
    /// A grid of `dims = [nx, ny]` filled with `value`, unit spacing, origin 0.
    ///
    /// # Panics
    /// If a dimension is zero; use [`Grid2::try_filled`] for user-controlled sizes.
    pub fn filled(dims: [usize; 2], value: T) -> Self {
        Self::try_filled(dims, value, &MemoryBudget::unlimited()).expect("non-zero grid dimensions")
    }

    /// Like [`Grid2::filled`] but checks dimensions and the memory budget first.
    ///
    /// # Errors
    /// [`CoreError::GridSize`] for a zero dimension, [`CoreError::MemoryLimit`] if too big.
    pub fn try_filled(dims: [usize; 2], value: T, budget: &MemoryBudget) -> crate::Result<Self> {
        if dims.contains(&0) {
            return Err(CoreError::GridSize {
                dims: dims.to_vec(),
                expected: 0,
                got: 0,
            });
        }
        let n = dims[0] as u128 * dims[1] as u128;
        budget.check_elements(
            n,
            size_of::<T>() as u64,
            &format!("a {}×{} grid", dims[0], dims[1]),
        )?;
        Ok(Self {
            dims,
            spacing: [1.0, 1.0],
            origin: [0.0, 0.0],
            units: Units::default(),
            data: vec![value; dims[0] * dims[1]],
        })
    }
}

impl<T> Grid2<T> {
    /// Wraps `data` (x fastest) as an `nx × ny` grid with unit spacing and zero origin.
    ///
    /// # Errors
    /// [`CoreError::GridSize`] if a dimension is 0 or `data.len() != nx·ny`.
    pub fn from_vec(dims: [usize; 2], data: Vec<T>) -> crate::Result<Self> {
        let expected = dims[0].saturating_mul(dims[1]);
        if dims.contains(&0) || data.len() != expected {
            return Err(CoreError::GridSize {
                dims: dims.to_vec(),
                expected,
                got: data.len(),
            });
        }
        Ok(Self {
            dims,
            spacing: [1.0, 1.0],
            origin: [0.0, 0.0],
            units: Units::default(),
            data,
        })
    }

    /// Sets the physical spacing (dx, dy).
    ///
    /// # Errors
    /// [`CoreError::BadSpacing`] unless both are positive and finite.
    pub fn with_spacing(mut self, spacing: [f64; 2]) -> crate::Result<Self> {
        check_spacing(&spacing)?;
        self.spacing = spacing;
        Ok(self)
    }

    /// Sets the position of sample (0, 0).
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] if the origin is not finite.
    pub fn with_origin(mut self, origin: [f64; 2]) -> crate::Result<Self> {
        if let Some(a) = origin.iter().position(|v| !v.is_finite()) {
            return Err(CoreError::NonFinite {
                what: "origin coordinate",
                index: a,
                value: origin[a],
            });
        }
        self.origin = origin;
        Ok(self)
    }

    /// Sets the length units of the spacing, origin and values.
    pub fn with_units(mut self, units: Units) -> Self {
        self.units = units;
        self
    }

    /// The length units (none for synthetic data).
    pub fn units(&self) -> Units {
        self.units
    }

    /// Applies the spacing and origin that a file recorded, where it recorded them.
    ///
    /// # Errors
    /// As [`Grid2::with_spacing`] and [`Grid2::with_origin`].
    pub fn with_geometry(
        self,
        spacing: Option<[f64; 2]>,
        origin: Option<[f64; 2]>,
    ) -> crate::Result<Self> {
        let g = match spacing {
            Some(s) => self.with_spacing(s)?,
            None => self,
        };
        match origin {
            Some(o) => g.with_origin(o),
            None => Ok(g),
        }
    }

    /// `[nx, ny]`.
    pub fn dims(&self) -> [usize; 2] {
        self.dims
    }
    /// Samples along x.
    pub fn nx(&self) -> usize {
        self.dims[0]
    }
    /// Samples along y.
    pub fn ny(&self) -> usize {
        self.dims[1]
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.data.len()
    }
    /// Always false: grids have at least one sample.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
    /// `[dx, dy]`.
    pub fn spacing(&self) -> [f64; 2] {
        self.spacing
    }
    /// Position of sample (0, 0).
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }
    /// Physical extent `[(nx−1)·dx, (ny−1)·dy]` between the outermost samples.
    pub fn extent(&self) -> [f64; 2] {
        [0, 1].map(|a| (self.dims[a] - 1) as f64 * self.spacing[a])
    }
    /// The samples, x fastest.
    pub fn data(&self) -> &[T] {
        &self.data
    }
    /// Mutable samples, x fastest.
    pub fn data_mut(&mut self) -> &mut [T] {
        &mut self.data
    }
    /// Takes the samples out.
    pub fn into_data(self) -> Vec<T> {
        self.data
    }
    /// Linear index of (i, j).
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        debug_assert!(i < self.dims[0] && j < self.dims[1]);
        i + self.dims[0] * j
    }
    /// Sample (i, j).
    ///
    /// # Panics
    /// If (i, j) is outside the grid.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> &T {
        assert!(
            i < self.dims[0] && j < self.dims[1],
            "({i}, {j}) outside {:?} grid",
            self.dims
        );
        &self.data[i + self.dims[0] * j]
    }
    /// Mutable sample (i, j).
    ///
    /// # Panics
    /// If (i, j) is outside the grid.
    #[inline]
    pub fn get_mut(&mut self, i: usize, j: usize) -> &mut T {
        assert!(
            i < self.dims[0] && j < self.dims[1],
            "({i}, {j}) outside {:?} grid",
            self.dims
        );
        &mut self.data[i + self.dims[0] * j]
    }
    /// Physical (x, y) of sample (i, j).
    pub fn position(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + i as f64 * self.spacing[0],
            self.origin[1] + j as f64 * self.spacing[1],
        ]
    }
    /// Row j (all i), contiguous.
    pub fn row(&self, j: usize) -> &[T] {
        &self.data[j * self.dims[0]..(j + 1) * self.dims[0]]
    }
    /// Mutable row j (all i), contiguous.
    pub fn row_mut(&mut self, j: usize) -> &mut [T] {
        let nx = self.dims[0];
        &mut self.data[j * nx..(j + 1) * nx]
    }
    /// A grid of the same geometry holding `data` (row-major, as [`Grid2::data`]).
    ///
    /// # Errors
    /// [`crate::CoreError`] when `data` does not hold one sample per point.
    pub fn with_data<U>(&self, data: Vec<U>) -> crate::Result<Grid2<U>> {
        let mut grid = Grid2::from_vec(self.dims, data)?;
        (grid.spacing, grid.origin, grid.units) = (self.spacing, self.origin, self.units);
        Ok(grid)
    }
    /// A grid of the same geometry with `f` applied to every sample.
    pub fn map<U>(&self, f: impl FnMut(&T) -> U) -> Grid2<U> {
        Grid2 {
            dims: self.dims,
            spacing: self.spacing,
            origin: self.origin,
            units: self.units,
            data: self.data.iter().map(f).collect(),
        }
    }
}

/// Unmeasured points.
///
/// An instrument leaves some points unmeasured (shadowed slopes, dropouts,
/// points outside a circular aperture). A [`HeightField`] carries them as NaN
/// heights: the mask is `is_nan()`, as in numpy (`np.isnan`), x3p (ISO
/// 5436-2 float data) and Gwyddion's import of NaNs as a mask. ±∞ is never a
/// height. Readers accept missing points ([`HeightField::validate_measured`]);
/// every step that needs a height at every point calls
/// [`HeightField::validate`], which refuses them with their count, so a NaN
/// cannot flow silently into a mesh or a spectrum.
impl HeightField {
    /// Every height finite: no missing point and no infinity.
    ///
    /// # Errors
    /// [`CoreError::MissingPoints`] with the count where heights are NaN;
    /// [`CoreError::NonFinite`] for an infinite height.
    pub fn validate(&self) -> crate::Result<()> {
        self.validate_for("this step")
    }

    /// [`HeightField::validate`], naming the step that needs every point in
    /// the error (`"a mesh"`, `"the PSD"`, …).
    ///
    /// # Errors
    /// As [`HeightField::validate`].
    pub fn validate_for(&self, what: &str) -> crate::Result<()> {
        self.validate_measured()?;
        match self.missing_count() {
            0 => Ok(()),
            missing => Err(CoreError::MissingPoints {
                missing,
                total: self.data.len(),
                what: what.to_string(),
            }),
        }
    }

    /// No infinite height and at least one measured point; missing points
    /// (NaN) are allowed.
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] for an infinite height;
    /// [`CoreError::MissingPoints`] when no point was measured.
    pub fn validate_measured(&self) -> crate::Result<()> {
        if let Some(k) = self.data.iter().position(|v| v.is_infinite()) {
            return Err(CoreError::NonFinite {
                what: "height",
                index: k,
                value: self.data[k],
            });
        }
        if self.data.iter().all(|v| v.is_nan()) {
            return Err(CoreError::MissingPoints {
                missing: self.data.len(),
                total: self.data.len(),
                what: "a height field".into(),
            });
        }
        Ok(())
    }

    /// The number of missing (NaN) heights.
    pub fn missing_count(&self) -> usize {
        self.data.iter().filter(|v| v.is_nan()).count()
    }

    /// Whether any height is missing.
    pub fn has_missing(&self) -> bool {
        self.data.iter().any(|v| v.is_nan())
    }

    /// The measured points: true where a height is known (x fastest).
    pub fn measured_mask(&self) -> Grid2<bool> {
        self.map(|v| !v.is_nan())
    }

    /// (min, max) of the heights (NaNs ignored; `(+∞, −∞)` if all are NaN).
    pub fn min_max(&self) -> (f64, f64) {
        // `f64::min`/`max` return the other operand for a NaN, so no NaN is
        // filtered; eight lanes let the compiler use vector registers.
        const LANES: usize = 8;
        let (mut lo, mut hi) = ([f64::INFINITY; LANES], [f64::NEG_INFINITY; LANES]);
        let chunks = self.data.chunks_exact(LANES);
        let rest = chunks.remainder();
        for c in chunks {
            for k in 0..LANES {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
        }
        let lo = rest.iter().chain(&lo).fold(f64::INFINITY, |l, &v| l.min(v));
        let hi = rest
            .iter()
            .chain(&hi)
            .fold(f64::NEG_INFINITY, |h, &v| h.max(v));
        (lo, hi)
    }

    /// Mean height.
    pub fn mean(&self) -> f64 {
        self.data.iter().sum::<f64>() / self.data.len() as f64
    }

    /// 3-D position of sample (i, j).
    pub fn point(&self, i: usize, j: usize) -> [f64; 3] {
        let [x, y] = self.position(i, j);
        [x, y, self.data[self.index(i, j)]]
    }

    /// Triangulates the height field: one vertex per sample, two triangles per cell,
    /// split as `diagonal` says, counter-clockwise seen from +z, with UVs in [0, 1]².
    ///
    /// Missing points (NaN heights) leave holes: they have no vertex, and a
    /// triangle with a missing corner is left out. The vertices are then the
    /// measured samples in order (x fastest), so per-vertex values are
    /// [`HeightField::measured_values`].
    ///
    /// # Errors
    /// [`CoreError::NonFinite`] for an infinite height, [`CoreError::Empty`] if
    /// the grid has fewer than 2 samples along an axis or no measured cell.
    pub fn to_trimesh(&self, diagonal: Diagonal) -> crate::Result<TriMesh> {
        self.validate_measured()?;
        let [nx, ny] = self.dims;
        if nx < 2 || ny < 2 {
            return Err(CoreError::Empty("height field with fewer than 2×2 samples"));
        }
        // Vertex number of each sample; u32::MAX for a missing one.
        let mut vertex = vec![u32::MAX; nx * ny];
        let mut positions = Vec::with_capacity(nx * ny);
        let mut uvs = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let k = i + nx * j;
                if self.data[k].is_nan() {
                    continue;
                }
                vertex[k] = positions.len() as u32;
                positions.push(self.point(i, j));
                uvs.push([i as f64 / (nx - 1) as f64, j as f64 / (ny - 1) as f64]);
            }
        }
        let mut triangles = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
        let id = |i: usize, j: usize| vertex[i + nx * j];
        let mut push = |t: [u32; 3]| {
            if !t.contains(&u32::MAX) {
                triangles.push(t);
            }
        };
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                let along_ac = match diagonal {
                    Diagonal::Forward => true,
                    Diagonal::Backward => false,
                    Diagonal::Alternating => (i + j) % 2 == 0,
                };
                if along_ac {
                    push([a, b, c]);
                    push([a, c, d]);
                } else {
                    push([a, b, d]);
                    push([b, c, d]);
                }
            }
        }
        if triangles.is_empty() {
            return Err(CoreError::Empty(
                "height field without a cell whose corners were all measured",
            ));
        }
        TriMesh::new(positions, triangles)?.with_uvs(uvs)
    }

    /// The measured heights in order (x fastest): one per vertex of
    /// [`HeightField::to_trimesh`] and per point of [`HeightField::to_point_set`].
    pub fn measured_values(&self) -> Vec<f64> {
        self.data.iter().copied().filter(|v| !v.is_nan()).collect()
    }

    /// One point per measured sample at (x, y, z), with the height also as
    /// attribute `"height"` (missing points have none).
    pub fn to_point_set(&self) -> PointSet {
        let [nx, ny] = self.dims;
        let positions = (0..ny)
            .flat_map(|j| (0..nx).map(move |i| (i, j)))
            .map(|(i, j)| self.point(i, j))
            .filter(|p| !p[2].is_nan())
            .collect();
        let mut ps = PointSet::new(positions);
        ps.add_attribute("height", self.measured_values())
            .expect("one height per point");
        ps
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(nx: usize, ny: usize) -> HeightField {
        let data = (0..nx * ny)
            .map(|k| (k % nx) as f64 + 10.0 * (k / nx) as f64)
            .collect();
        HeightField::from_vec([nx, ny], data).unwrap()
    }

    #[test]
    fn indexing_is_x_fastest() {
        let g = ramp(3, 2)
            .with_spacing([0.5, 2.0])
            .unwrap()
            .with_origin([1.0, -1.0])
            .unwrap();
        assert_eq!(*g.get(2, 1), 12.0);
        assert_eq!(g.index(2, 1), 5);
        assert_eq!(g.position(2, 1), [2.0, 1.0]);
        assert_eq!(g.row(1), &[10.0, 11.0, 12.0]);
        assert_eq!(g.extent(), [1.0, 2.0]);
        assert_eq!(g.min_max(), (0.0, 12.0));
    }

    #[test]
    fn min_max_ignores_nans_at_every_length() {
        for n in 1..40 {
            let mut v: Vec<f64> = (0..n).map(|k| ((k * 7) % 11) as f64 - 5.0).collect();
            let expected = v
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &x| {
                    (l.min(x), h.max(x))
                });
            for k in (0..n).step_by(3) {
                v.insert(k, f64::NAN);
            }
            let g = HeightField::from_vec([v.len(), 1], v).unwrap();
            assert_eq!(g.min_max(), expected, "n = {n}");
        }
        let all_nan = HeightField::from_vec([3, 3], vec![f64::NAN; 9]).unwrap();
        assert_eq!(all_nan.min_max(), (f64::INFINITY, f64::NEG_INFINITY));
    }

    #[test]
    fn rejects_bad_shapes_and_values() {
        assert!(HeightField::from_vec([0, 3], vec![]).is_err());
        assert!(HeightField::from_vec([2, 3], vec![0.0; 5]).is_err());
        assert!(ramp(2, 2).with_spacing([0.0, 1.0]).is_err());
        assert!(ramp(2, 2).with_spacing([f64::NAN, 1.0]).is_err());
        let mut h = ramp(2, 2);
        *h.get_mut(1, 1) = f64::NAN;
        assert!(matches!(
            h.validate(),
            Err(CoreError::MissingPoints { missing: 1, .. })
        ));
        // Every cell of a 2×2 field has that corner: no triangle is left.
        assert!(h.to_trimesh(Diagonal::Forward).is_err());
        *h.get_mut(1, 1) = f64::NEG_INFINITY;
        assert!(matches!(
            h.validate(),
            Err(CoreError::NonFinite { index: 3, .. })
        ));
        let budget = MemoryBudget::new(1000);
        assert!(matches!(
            HeightField::try_filled([100, 100], 0.0, &budget),
            Err(CoreError::MemoryLimit { needed: 80_000, .. })
        ));
    }

    #[test]
    fn triangulation_counts_orientation_and_alternation() {
        let h = ramp(5, 4);
        for diag in [Diagonal::Forward, Diagonal::Backward, Diagonal::Alternating] {
            let m = h.to_trimesh(diag).unwrap();
            assert_eq!(m.n_faces(), 2 * 4 * 3);
            // A disc: χ = 1, one boundary loop, manifold.
            assert_eq!(m.euler_characteristic(), 1);
            assert!(m.is_manifold());
            assert_eq!(m.boundary_loops().len(), 1);
            for n in m.face_normals() {
                assert!(n[2] > 0.0, "{diag:?}: normal {n:?} must point up");
            }
        }
        // Peridier's alternating facets: interior node valence (triangle count) is 4 or 8.
        let m = ramp(6, 6).to_trimesh(Diagonal::Alternating).unwrap();
        let mut count = vec![0usize; m.n_vertices()];
        for t in m.triangles() {
            for &v in t {
                count[v as usize] += 1;
            }
        }
        for j in 1..5 {
            for i in 1..5 {
                let c = count[i + 6 * j];
                assert_eq!(c, if (i + j) % 2 == 0 { 8 } else { 4 }, "node ({i},{j})");
            }
        }
    }

    #[test]
    fn point_set_carries_heights() {
        let p = ramp(3, 2).to_point_set();
        assert_eq!(p.len(), 6);
        assert_eq!(p.positions()[5], [2.0, 1.0, 12.0]);
        assert_eq!(p.attribute("height").unwrap()[5], 12.0);
    }

    /// A 4×3 ramp with sample (1, 1) missing.
    fn holed() -> HeightField {
        let mut h = ramp(4, 3);
        *h.get_mut(1, 1) = f64::NAN;
        h
    }

    #[test]
    fn missing_points_are_counted_and_refused_where_every_point_is_needed() {
        let h = holed();
        assert_eq!(h.missing_count(), 1);
        assert!(h.has_missing() && !ramp(4, 3).has_missing());
        assert!(h.validate_measured().is_ok());
        let e = h.validate_for("a spectrum").unwrap_err();
        assert!(
            matches!(
                e,
                CoreError::MissingPoints {
                    missing: 1,
                    total: 12,
                    ..
                }
            ),
            "{e}"
        );
        assert!(
            e.to_string().contains("1 of 12 points were not measured"),
            "{e}"
        );
        assert!(
            e.to_string()
                .contains("a spectrum needs a height at every point"),
            "{e}"
        );
        let mut inf = ramp(2, 2);
        *inf.get_mut(0, 0) = f64::INFINITY;
        assert!(matches!(
            inf.validate_measured(),
            Err(CoreError::NonFinite { .. })
        ));
        let none = HeightField::from_vec([2, 1], vec![f64::NAN; 2]).unwrap();
        assert!(none.validate_measured().is_err());
        assert_eq!(h.measured_mask().data().iter().filter(|m| !**m).count(), 1);
    }

    #[test]
    fn a_missing_point_leaves_a_hole_in_the_mesh_and_no_point() {
        let h = holed();
        let complete = ramp(4, 3).to_trimesh(Diagonal::Forward).unwrap();
        let m = h.to_trimesh(Diagonal::Forward).unwrap();
        // (1, 1) is a corner of the 6 triangles around it (forward diagonals).
        assert_eq!(complete.n_faces(), 12);
        assert_eq!(m.n_faces(), 6);
        assert_eq!(m.positions().len(), 11);
        assert!(
            m.positions()
                .iter()
                .all(|p| p.iter().all(|v| v.is_finite()))
        );
        assert_eq!(h.measured_values().len(), 11);
        let p = h.to_point_set();
        assert_eq!(p.len(), 11);
        assert_eq!(p.attribute("height").unwrap().len(), 11);
        // A field whose every cell has a missing corner has no mesh.
        let mut sparse = ramp(2, 2);
        *sparse.get_mut(0, 0) = f64::NAN;
        *sparse.get_mut(1, 1) = f64::NAN;
        assert!(sparse.to_trimesh(Diagonal::Forward).is_err());
    }
}
