//! The computational grid around a point set (§5.2, "Computing the Distance Function").
//!
//! The paper computes every field on a regular grid around the data (its Fig. 8 uses a
//! 112×115×114 grid for an RDSR sphere, Fig. 9 a 115×115×49 grid for a 64³ DLA run). The
//! grid here is cubic (one spacing `h` on every axis) and padded so that nothing the
//! pipeline does reaches the domain boundary: the offset surface lies at distance ε
//! from the data and the narrow tube reaches γ beyond it, so the padding is
//! `⌈(ε + γ)/h⌉ + 3` nodes on every side. Nodes are stored x fastest, as in
//! [`asperity_core::Grid3`].

use asperity_core::{CoreError, MemoryBudget};

/// How the spacing is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sizing {
    /// This many cells along the longest axis of the points' bounding box.
    Resolution(usize),
    /// This spacing, in the points' units.
    Spacing(f64),
}

/// Bytes per grid node the whole pipeline holds at its peak, while the initial
/// surface is built: the distance (`f32`), the exterior tags (`bool`), the packed
/// closest points of the tagged front (`u64`) and φ (`f32`), plus a byte for the
/// frontier lists and bitmaps. (The distance stage needs 12; tagging 14, as the
/// packed closest points are kept for the initial surface's wavefront to refill,
/// with two bytes of node states; the flow 12: d, φ and its scratch copy.)
pub const BYTES_PER_NODE: u64 = 4 + 1 + 8 + 4 + 1;

/// A cubic-cell grid: node (i, j, k) is at `origin + h·(i, j, k)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    /// Position of node (0, 0, 0).
    pub origin: [f64; 3],
    /// Spacing h.
    pub spacing: f64,
    /// Nodes per axis.
    pub dims: [usize; 3],
}

/// The bounding box of finite, non-empty `points`.
fn bounds(points: &[[f64; 3]]) -> asperity_core::Result<([f64; 3], [f64; 3])> {
    if points.is_empty() {
        return Err(CoreError::Empty("the point set"));
    }
    for (index, p) in points.iter().enumerate() {
        if let Some(&value) = p.iter().find(|v| !v.is_finite()) {
            return Err(CoreError::NonFinite {
                what: "point",
                index,
                value,
            });
        }
    }
    let mut lo = points[0];
    let mut hi = points[0];
    for p in points {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    Ok((lo, hi))
}

/// The spacing `sizing` asks for on points whose longest extent is `longest`.
fn spacing(sizing: Sizing, longest: f64) -> asperity_core::Result<f64> {
    match sizing {
        Sizing::Resolution(n) => {
            if !(2..=65_536).contains(&n) {
                return Err(CoreError::InvalidParameter {
                    name: "resolution",
                    reason: format!("must be between 2 and 65536 cells, got {n}"),
                });
            }
            Ok(longest / n as f64)
        }
        Sizing::Spacing(h) => {
            if !(h.is_finite() && h > 0.0) {
                return Err(CoreError::InvalidParameter {
                    name: "spacing",
                    reason: format!("must be positive and finite, got {h}"),
                });
            }
            Ok(h)
        }
    }
}

/// Nodes per axis: the extent in cells, plus one, plus `pad` on each side.
fn dims(extent: [f64; 3], spacing: f64, pad: usize) -> asperity_core::Result<[usize; 3]> {
    let mut dims = [0usize; 3];
    for a in 0..3 {
        let cells = (extent[a] / spacing).ceil();
        if cells.is_nan() || cells >= 1e7 {
            return Err(CoreError::InvalidParameter {
                name: "spacing",
                reason: format!(
                    "{spacing} gives {cells} cells along axis {a}; choose a coarser grid"
                ),
            });
        }
        dims[a] = cells as usize + 1 + 2 * pad;
    }
    Ok(dims)
}

impl GridSpec {
    /// The grid around `points` with the spacing from `sizing` and `pad` nodes of
    /// padding on every side (see [`padding_nodes`]), after checking the points and
    /// that [`BYTES_PER_NODE`] per node fits in `budget`: the dense pipeline's
    /// grid.
    ///
    /// # Errors
    /// An empty set, a non-finite coordinate, identical points, a bad sizing, or
    /// the memory estimate above the budget.
    pub fn around(
        points: &[[f64; 3]],
        sizing: Sizing,
        pad: impl Fn(f64) -> usize,
        budget: &MemoryBudget,
    ) -> asperity_core::Result<Self> {
        let grid = Self::fitting(points, sizing, pad)?;
        budget.check_elements(
            grid.len() as u128,
            BYTES_PER_NODE,
            &format!(
                "level-set reconstruction on a {}×{}×{} grid",
                grid.dims[0], grid.dims[1], grid.dims[2]
            ),
        )?;
        if grid.len() as u128 > u32::MAX as u128 / 4 {
            return Err(CoreError::InvalidParameter {
                name: "resolution",
                reason: format!(
                    "{} grid nodes is more than the dense grid indexes (2³⁰)",
                    grid.len()
                ),
            });
        }
        Ok(grid)
    }

    /// The grid around `points` with the spacing from `sizing` and `pad` nodes
    /// of padding on every side, with no memory check: the sparse pipeline
    /// checks the bricks it will hold instead. At most 2³² − 1 nodes (the
    /// largest grid whose 8³-node bricks all have 32-bit node ids).
    ///
    /// # Errors
    /// An empty set, a non-finite coordinate, identical points, a bad sizing, or
    /// more nodes than that.
    pub fn fitting(
        points: &[[f64; 3]],
        sizing: Sizing,
        pad: impl Fn(f64) -> usize,
    ) -> asperity_core::Result<Self> {
        let (lo, hi) = bounds(points)?;
        let extent = [0, 1, 2].map(|a| hi[a] - lo[a]);
        let longest = extent.iter().copied().fold(0.0, f64::max);
        if longest <= 0.0 {
            return Err(CoreError::InvalidParameter {
                name: "points",
                reason: format!(
                    "all {} points are identical ({:?}); a surface needs points that span a volume or a sheet",
                    points.len(),
                    lo
                ),
            });
        }
        let spacing = spacing(sizing, longest)?;
        let dims = dims(extent, spacing, pad(spacing))?;
        let bricked = dims
            .iter()
            .fold(512u128, |acc, &d| acc * d.div_ceil(8) as u128);
        if bricked > u32::MAX as u128 {
            return Err(CoreError::InvalidParameter {
                name: "resolution",
                reason: format!(
                    "a {}×{}×{} grid is more than this build indexes (2³² nodes); choose a coarser grid",
                    dims[0], dims[1], dims[2]
                ),
            });
        }
        let origin = [0, 1, 2].map(|a| {
            // Centre the points in the grid.
            let span = (dims[a] - 1) as f64 * spacing;
            0.5 * (lo[a] + hi[a]) - 0.5 * span
        });
        Ok(Self {
            origin,
            spacing,
            dims,
        })
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    /// Whether the grid has no nodes (never true for a built grid).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Linear index of node (i, j, k).
    #[inline]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// Node coordinates of a linear index.
    #[inline]
    pub fn coords(&self, index: usize) -> [usize; 3] {
        let i = index % self.dims[0];
        let rest = index / self.dims[0];
        [i, rest % self.dims[1], rest / self.dims[1]]
    }

    /// World position of node (i, j, k).
    #[inline]
    pub fn position(&self, i: usize, j: usize, k: usize) -> [f64; 3] {
        [
            self.origin[0] + i as f64 * self.spacing,
            self.origin[1] + j as f64 * self.spacing,
            self.origin[2] + k as f64 * self.spacing,
        ]
    }

    /// `f` at every node's position, x fastest (for tests).
    #[cfg(test)]
    pub(crate) fn sample(&self, f: impl Fn([f64; 3]) -> f64) -> Vec<f32> {
        (0..self.len())
            .map(|u| {
                let c = self.coords(u);
                f(self.position(c[0], c[1], c[2])) as f32
            })
            .collect()
    }

    /// Index strides along x, y, z.
    #[inline]
    pub fn strides(&self) -> [usize; 3] {
        [1, self.dims[0], self.dims[0] * self.dims[1]]
    }

    /// Whether node `c` lies on the outer faces of the grid.
    #[inline]
    pub fn on_boundary(&self, c: [usize; 3]) -> bool {
        (0..3).any(|a| c[a] == 0 || c[a] + 1 == self.dims[a])
    }
}

/// Padding nodes for an offset `eps` and tube half-width `gamma` (world units) at
/// spacing `h`: `⌈(ε + γ)/h⌉ + 3`.
pub fn padding_nodes(eps: f64, gamma: f64, h: f64) -> usize {
    ((eps + gamma) / h).ceil() as usize + 3
}

/// A length in world units or in grid cells (multiples of the spacing h).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Length {
    /// In the points' units.
    World(f64),
    /// In cells of the grid spacing h (the paper gives ε this way: "3 grid cells").
    Cells(f64),
}

impl Length {
    /// The length in world units on a grid of spacing `h`.
    pub fn world(self, h: f64) -> f64 {
        match self {
            Self::World(v) => v,
            Self::Cells(c) => c * h,
        }
    }

    /// The number itself, whatever its unit.
    pub(crate) fn value(self) -> f64 {
        match self {
            Self::World(v) | Self::Cells(v) => v,
        }
    }

    /// Parses `3` (world units) or `3h` (cells of h).
    ///
    /// # Errors
    /// A message naming the text, for anything else.
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        let (number, cells) = match t.strip_suffix('h') {
            Some(n) => (n.trim(), true),
            None => (t, false),
        };
        let v: f64 = number.parse().map_err(|_| {
            format!(
                "expected a length like 0.5 (units of the points) or 3h (grid cells), got {text:?}"
            )
        })?;
        Ok(if cells {
            Self::Cells(v)
        } else {
            Self::World(v)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts() -> Vec<[f64; 3]> {
        vec![[0.0, 0.0, 0.0], [10.0, 5.0, 2.0]]
    }

    #[test]
    fn resolution_sets_the_spacing_from_the_longest_axis() {
        let g = GridSpec::around(
            &pts(),
            Sizing::Resolution(20),
            |_| 4,
            &MemoryBudget::unlimited(),
        )
        .unwrap();
        assert!((g.spacing - 0.5).abs() < 1e-12);
        assert_eq!(g.dims, [20 + 1 + 8, 10 + 1 + 8, 4 + 1 + 8]);
        // Points are centred: the first point is 4 nodes in.
        let p = g.position(4, 4, 4);
        assert!((p[0] - 0.0).abs() < 1e-9 && (p[1] - 0.0).abs() < 1e-9);
        assert_eq!(g.coords(g.index(3, 7, 2)), [3, 7, 2]);
    }

    #[test]
    fn bad_input_is_refused_with_a_reason() {
        let b = MemoryBudget::unlimited();
        let e = GridSpec::around(&[], Sizing::Resolution(10), |_| 1, &b).unwrap_err();
        assert!(e.to_string().contains("empty"), "{e}");
        let e = GridSpec::around(&[[0.0, f64::NAN, 0.0]], Sizing::Resolution(10), |_| 1, &b)
            .unwrap_err();
        assert!(e.to_string().contains("not finite"), "{e}");
        let e =
            GridSpec::around(&[[1.0; 3], [1.0; 3]], Sizing::Resolution(10), |_| 1, &b).unwrap_err();
        assert!(e.to_string().contains("identical"), "{e}");
        let e = GridSpec::around(&pts(), Sizing::Spacing(-1.0), |_| 1, &b).unwrap_err();
        assert!(e.to_string().contains("spacing"), "{e}");
        let small = MemoryBudget::new(1 << 20);
        let e = GridSpec::around(&pts(), Sizing::Resolution(1000), |_| 1, &small).unwrap_err();
        assert!(matches!(e, CoreError::MemoryLimit { .. }), "{e}");
        assert!(e.to_string().contains("limit"), "{e}");
    }
}
